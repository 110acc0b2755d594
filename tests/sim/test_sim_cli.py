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
    (["--crop", "1", "2", "3"], "--crop"),
    (["--error", "slip"], "NAME=VALUE"),
    (["--error", "wobble=1"], "unknown error source"),
    (["--error", "dropout=2"], "0..1"),
    (["--set", "wheel_base_um=0"], "wheel_base_um"),
    (["--set", "nonsense=1"], "unknown key"),
    (["--room"], "--room"),
]:
    out = sim.out("never")
    p = sim.run(*args, "--out", out, expect=2)
    check(what in p.stderr and not os.path.exists(out),
          "%s: exit 2, says '%s', writes nothing" % (" ".join(args), what))

bad_rooms = [
    ("wall 0 0 1\nstart 0.5 0.5 0\n", ":1:", "wrong number of values"),
    ("wall 0 0 5 0\nbox 1 1 1 1\nstart 2 2 0\nteleport 3 3\n", ":4:", "unknown keyword"),
    ("wall 0 0 5 nan\nstart 1 1 0\n", ":1:", "non-finite"),
    ("# no geometry\nstart 1 1 0\n", "", "no geometry"),
    ("wall 0 0 5 0\nwall 0 4 5 4\n", "", "start"),
    ("box 0 0 5 4\ncircle 2 2 0.5\nstart 2 2 0\n", ":3:", "start"),
    ("wall 0 0 5 0\nstart 1 1 0\nstart 2 2 0\n", ":3:", "start"),
]
for i, (text, where, what) in enumerate(bad_rooms):
    path = sim.out("bad%d.room" % i)
    with open(path, "w") as f:
        f.write(text)
    out = sim.out("never")
    p = sim.run("--room", path, "--out", out, expect=2)
    check(path + where in p.stderr and not os.path.exists(out),
          "bad room %d (%s): exit 2, names %s%s, writes nothing" % (i, what, os.path.basename(path), where))

p = sim.run("--room", sim.out("missing.room"), "--out", sim.out("never"), expect=2)
check("missing.room" in p.stderr, "a missing room file is named")

# A room larger than the grid at this cell size is refused with advice.
big = sim.out("big.room")
with open(big, "w") as f:
    f.write("wall 0 0 40 0\nwall 40 0 40 30\nwall 40 30 0 30\nwall 0 30 0 0\nstart 20 15 0\n")
p = sim.run("--room", big, "--out", sim.out("never"), expect=2)
check("does not fit" in p.stderr and "--cell" in p.stderr, "a room too large for the grid says how to fit it")
sim.done()
