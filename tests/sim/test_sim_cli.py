#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim's command line and input checks: --help, bad options, bad room files.

Every bad input must exit with status 2, name the file and line, and write nothing.
"""
import os

from simtest import Sim, check

sim = Sim()

p = sim.run("--help")
check("--room" in p.stdout and "--replay" in p.stdout and "--explore" in p.stdout,
      "--help lists the options")

for args, what in [
    (["--bogus"], "unknown option"),
    (["--duration", "abc"], "--duration"),
    (["--duration", "-5"], "--duration"),
    (["--cell", "7.5"], "--cell"),
    (["--cell", "2"], "--cell"),
    (["--explore", "spiral"], "unknown mode"),
    (["--seed", "-1"], "--seed"),
    (["--seed", " -1"], "--seed: ' -1' is not a whole number"),
    (["--seed", "99999999999999999999"], "--seed: '99999999999999999999' is out of range"),
    (["--duration", "1e9"], "--duration: '1e9' is out of range 0.01..1e+06"),
    (["--crop", "1", "2", "3", "1e7"], "--crop: '1e7' is out of range"),
    (["--start", "1", "x", "0"], "--start: 'x' is not a decimal number"),
    (["--error", "noise=0.6"], "--error noise: '0.6' is out of range 0..0.5"),
    (["--crop", "0", "0", "1", "1"], "a crop takes part of a ROS map"),
    (["--start", "6", "2", "0"], "--start 6 2 is outside the room"),
    (["--room", "/dev/zero"], "/dev/zero: is not a regular file"),
    (["--crop", "1", "2", "3"], "--crop"),
    (["--error", "slip"], "NAME=VALUE"),
    (["--error", "wobble=1"], "unknown error source"),
    (["--error", "dropout=2"], "0..1"),
    (["--set", "wheel_base_um=0"], "wheel_base_um"),
    (["--set", "nonsense=1"], "unknown key"),
    (["--sonar1", "0.05", "0", "120"], "--sonar1: '120' is out of range -90..90"),
    (["--set", "sonar1_map=1"], "sonar1_map = 1, but the simulated robot has no sonar 1"),
    (["--room"], "--room"),
]:
    out = sim.out("never")
    p = sim.run(*args, "--out", out, expect=2)
    check(what in p.stderr and not os.path.exists(out),
          "%s: exit 2, says '%s', writes nothing" % (" ".join(args), what))

bad_rooms = [  # text, where, what, and what the message says
    ("wall 0 0 1\nstart 0.5 0.5 0\n", ":1:", "wrong number of values", "wall needs 4 values"),
    ("wall 0 0 5 0\nbox 1 1 1 1\nstart 2 2 0\nteleport 3 3\n", ":4:", "unknown keyword", "teleport"),
    ("wall 0 0 5 nan\nstart 1 1 0\n", ":1:", "non-finite", "not a finite number"),
    ("# no geometry\nstart 1 1 0\n", "", "no geometry", "no walls or obstacles"),
    ("wall 0 0 5 0\nwall 0 4 5 4\n", "", "start", "no start pose"),
    ("box 0 0 5 4\ncircle 2 2 0.5\nstart 2 2 0\n", ":3:", "start", "inside an obstacle"),
    ("wall 0 0 5 0\nstart 1 1 0\nstart 2 2 0\n", ":3:", "start", "a second start"),
    ("wall 0 0 5 0\nwall 5 0 5 4\nwall 5 4 0 4\nwall 0 4 0 0\nstart 6 2 0\n", ":5:",
     "start outside the room", "start pose (6, 2) is outside the room"),
    ("wall 0 0 5 0\nwall 5 0 5 4\n\0wall 5 4 0 4\nwall 0 4 0 0\nstart 2 2 0\n", ":3:", "NUL",
     "a NUL byte"),
    ("\0wall 0 0 5 0\nstart 1 1 0\n", ":1:", "NUL in line 1", "a NUL byte"),
    ("wall 0 0 1e300 0\nstart 1 1 0\n", ":1:", "huge number", "out of range: values lie within +-10000"),
]
for i, (text, where, what, says) in enumerate(bad_rooms):
    path = sim.out("bad%d.room" % i)
    with open(path, "w") as f:
        f.write(text)
    out = sim.out("never")
    p = sim.run("--room", path, "--out", out, expect=2)
    check(path + where in p.stderr and says in p.stderr and not os.path.exists(out),
          "bad room %d (%s): exit 2, names %s%s, writes nothing" % (i, what, os.path.basename(path), where))

# ROS maps: an image that never ends, and a crop that holds no pixel.
yaml = sim.out("zero.yaml")
with open(yaml, "w") as f:
    f.write("image: /dev/zero\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
            "free_thresh: 0.2\n")
p = sim.run("--room", yaml, "--out", sim.out("never"), expect=2)
check("/dev/zero: is not a regular file" in p.stderr, "an endless image: exit 2, not a file")
with open(sim.out("tiny.pgm"), "wb") as f:
    f.write(b"P5\n4 4\n255\n" + bytes([0] * 16))
yaml = sim.out("tiny.yaml")
with open(yaml, "w") as f:
    f.write("image: tiny.pgm\nresolution: 0.5\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
            "free_thresh: 0.2\n")
p = sim.run("--room", yaml, "--crop", "0.3", "0.3", "0.1", "0.1", "--out", sim.out("never"), expect=2)
check("holds no pixel centre (the pixels are 0.5 m)" in p.stderr, "a crop smaller than a pixel says so")
p = sim.run("--room", yaml, "--crop", "30", "30", "1", "1", "--out", sim.out("never"), expect=2)
check("lies outside the map (0 0 .. 2 2)" in p.stderr, "a crop beside the map says so")

p = sim.run("--room", sim.out("missing.room"), "--out", sim.out("never"), expect=2)
check("missing.room" in p.stderr, "a missing room file is named")

# A room larger than the simulator's grid can grow to (1024 cells, 51.2 m at 50 mm) is
# refused with advice; one larger than 256 cells but within it grows the grid (test_sim_config).
big = sim.out("big.room")
with open(big, "w") as f:
    f.write("wall 0 0 60 0\nwall 60 0 60 30\nwall 60 30 0 30\nwall 0 30 0 0\nstart 30 15 0\n")
p = sim.run("--room", big, "--out", sim.out("never"), expect=2)
check("does not fit" in p.stderr and "--cell" in p.stderr, "a room too large for the grid says how to fit it")
sim.done()
