#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/telemetry.py as a user meets it: dump prints one format, bad input gets a message
and a count of bad frames (never a traceback), view says what to do without a display
and keeps a PNG up to date while following, send talks to a robot on a serial line, and
the tool's key table is the firmware's."""
import os
import pty
import re
import signal
import struct
import subprocess
import sys
import time
import tty

from simtest import Sim, check

sim = Sim()
tool = os.path.join(sim.src, "tools", "telemetry.py")
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import link as slamlink  # noqa: E402


def run_tool(*args, env=None):
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run(["/usr/bin/python3", tool] + [str(a) for a in args], env=e,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


# The key table: slamlink reads it from config_fields.h, one row per slam_config_t field
# in the members' order (tests/test_config_tables.py holds it to the compiled C).
with open(os.path.join(sim.src, "firmware", "include", "slam", "config.h")) as f:
    config = f.read()
struct_body = config[config.index("typedef struct {"):config.index("} slam_config_t;")]
fields = re.findall(r"^\s+\w+ (\w+);", struct_body, re.M)
ids = [k for k, _, _, _ in slamlink.KEYS]
check([f.name for f in slamlink.FIELDS] == fields and len(set(ids)) == len(ids) and
      sorted(slamlink.KEY_IDS) == sorted(fields),
      "tools/slamtools/link.py's %d keys are config_fields.h's, one per slam_config_t field" % len(ids))

log = sim.out("run.log")
sim.run("--duration", 30, "--seed", 3, "--out", sim.out("run"), "--telemetry", log)

# dump: one line per frame, key=value with units, headings in degrees.
p = run_tool("dump", log)
lines = p.stdout.splitlines()
kinds = {line.split()[0] for line in lines}
check(p.returncode == 0 and kinds == {"hello", "pose", "reading", "map_row", "status"},
      "dump prints every kind of frame (%d lines)" % len(lines))
form = re.compile(r"^[a-z_]+( [a-z_]+=\S+)+$")
check(all(form.match(line) for line in lines), "every line is `name key=value...`")
pose = next(line for line in lines if line.startswith("pose "))
reading = next(line for line in lines if line.startswith("reading "))
check("heading_deg=" in pose and "heading_deg=" in reading and "heading=" not in pose.replace("heading_deg", ""),
      "pose and reading lines both give the heading in degrees:\n    %s\n    %s" % (pose, reading))

p = run_tool("--help")
check(p.returncode == 0 and "Exit status" in p.stdout and "to-readings" in p.stdout and
      "calibrate" in p.stdout, "--help is whole: commands, keys, exit status")

# Bad input (issue 11, B12): a message and a count of bad frames, no traceback.
with open(log, "rb") as f:
    good = f.read()
hello_end = 6 + good[3]  # the log begins with a whole HELLO frame
cases = []
wrong_len = sim.out("wrong-length.log")
with open(wrong_len, "wb") as f:   # a POSE of 3 bytes with a right CRC, among good frames
    f.write(good[:hello_end] + slamlink.frame(slamlink.POSE, b"\x01\x02\x03") + good[hello_end:8000])
cases.append(("dump", wrong_len, 0, "1 bad frames skipped"))
far_row = sim.out("far-row.log")
with open(far_row, "wb") as f:     # a map row outside this grid, within what a grid may be
    f.write(good[:hello_end] + slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", 0, 4000, 0) + b"\x05" * 10)
            + good[hello_end:20000])
cases.append(("view", far_row, 0, "1 map rows outside the grid"))
beyond = sim.out("beyond-row.log")
with open(beyond, "wb") as f:      # a row no grid has (4096 cells a side at most): malformed
    f.write(good[:hello_end] + slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", 0, 60000, 0) + b"\x05" * 10)
            + good[hello_end:20000])
cases.append(("view", beyond, 0, "1 bad frames skipped"))
noise = sim.out("noise.log")
with open(noise, "wb") as f:
    f.write(bytes((i * 7919 + (i >> 3)) % 256 for i in range(20000)) + b"\xa5\x5a\x02\x10" + b"\x00" * 20)
cases.append(("dump", noise, 2, "holds no telemetry frame"))
cases.append(("view", noise, 2, "holds no telemetry frame"))
cases.append(("dump", sim.work, 2, "is a directory"))
cases.append(("view", sim.work, 2, "is a directory"))
cases.append(("dump", sim.out("missing"), 2, "No such file"))
empty = sim.out("empty.log")
open(empty, "wb").close()
cases.append(("dump", empty, 2, "holds no telemetry frame"))
for cmd, src, status, what in cases:
    extra = ["--png", sim.out("bad.png")] if cmd == "view" else []
    p = run_tool(cmd, src, *extra)
    check(p.returncode == status and what in p.stderr and "Traceback" not in p.stderr,
          "%s %s: exit %d, says '%s'" % (cmd, os.path.basename(src), status, p.stderr.strip()))

# view without a display: says so and how to get a picture.
p = run_tool("view", log, env={"MPLBACKEND": "Agg", "DISPLAY": ""})
check(p.returncode == 2 and "--png" in p.stderr and "Traceback" not in p.stderr,
      "view with no display says how to get a PNG: %s" % p.stderr.strip())
png = sim.out("view.png")
p = run_tool("view", log, "--png", png)
with open(png, "rb") as f:
    magic = f.read(8)
check(p.returncode == 0 and magic == b"\x89PNG\r\n\x1a\n" and png in p.stdout,
      "view --png draws the log and says where")

# view --follow --png: the picture is there while the tool still follows the file.
png = sim.out("follow.png")
# (SIGINT as a terminal sends it: a test run in the background would pass it on ignored.)
proc = subprocess.Popen(["/usr/bin/python3", tool, "view", log, "--follow", "--png", png,
                         "--every", "0.2"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
for _ in range(600):
    if os.path.exists(png) or proc.poll() is not None:
        break
    time.sleep(0.1)
running = proc.poll() is None
proc.send_signal(signal.SIGINT)
out, err = proc.communicate(timeout=120)
ok = running and os.path.exists(png) and "Traceback" not in err and "wrote " + png in out
check(ok, "view --follow --png writes the picture while it follows, and on Ctrl-C a last time%s"
      % ("" if ok else " (running when signalled: %s, exit %d, stdout %r, stderr %r)"
         % (running, proc.returncode, out[-500:], err[-1500:])))

# A Ctrl-C whose KeyboardInterrupt is lost (raised inside code that swallows exceptions)
# still ends a followed source: it stops waiting once the signal has come.
import telemetry  # noqa: E402
src = telemetry.Source(log, follow=True)
telemetry.Source.stopping = True
waits = 0
for fr in src:
    waits += fr is None
    if waits > 20:  # a second of waiting for bytes that will not come
        break
telemetry.Source.stopping = False
check(waits == 0 and src.frames > 0,
      "a followed file, once stopping, is read to its end and no further (%d frames, %d "
      "waits)" % (src.frames, waits))

# --until-idle: a followed file that stops growing ends the tool by itself.
p = subprocess.run(["/usr/bin/python3", tool, "view", log, "--follow", "--until-idle", "0.5",
                    "--png", sim.out("idle.png")], stdout=subprocess.PIPE,
                   stderr=subprocess.PIPE, text=True, timeout=120)
check(p.returncode == 0 and os.path.exists(sim.out("idle.png")),
      "view --follow --until-idle 0.5 ends once the file stops growing: %s" % p.stderr.strip())
p = run_tool("dump", log, "--until-idle", "1")
check(p.returncode == 2 and "needs --follow" in p.stderr, "--until-idle without --follow: exit 2")

# frame and send: a command as bytes, and a robot answering on a serial line.
p = run_tool("frame", "set", "cruise_mm_s", "150")
check(p.returncode == 0 and bytes.fromhex(p.stdout.strip()) == slamlink.command(["set", "cruise_mm_s", "150"]),
      "frame prints a command's bytes: %s" % p.stdout.strip())
for words, what in ((["set", "cruise_mm_s", "x"], "whole decimal number"), (["set", "nokey", "1"], "unknown key"),
                    (["mode", "spiral"], "spiral"), (["fly"], "expected a command"),
                    (["set", "square_laps", "300"], "does not fit")):
    p = run_tool("frame", *words)
    check(p.returncode == 2 and what in p.stderr and "Traceback" not in p.stderr,
          "frame %s: refused, '%s'" % (" ".join(words), what))


def robot_answers(words, reply, extra=()):
    """Runs `send` against a pseudo-terminal whose other end plays the robot."""
    master, slave = pty.openpty()
    tty.setraw(slave)
    proc = subprocess.Popen(["/usr/bin/python3", tool, "send", os.ttyname(slave)] + words +
                            list(extra), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    want = slamlink.command(words)
    got = b""
    while len(got) < len(want):
        got += os.read(master, 64)
    for chunk in reply(got):
        os.write(master, chunk)
    out, err = proc.communicate(timeout=60)
    os.close(master)
    os.close(slave)
    return got == want, proc.returncode, out, err


ok, rc, out, err = robot_answers(["set", "cruise_mm_s", "150"],
                                 lambda got: [slamlink.frame(slamlink.POSE, bytes(16)),
                                              slamlink.frame(slamlink.CONFIG, struct.pack("<BI", slamlink.KEY_IDS["cruise_mm_s"], 150))])
check(ok and rc == 0 and out.strip() == "config key=cruise_mm_s value=150",
      "send set: the robot gets the frame, the answer is printed: %s" % out.strip())
# Every mode of explore_modes.h, the robot's default (walls) among them, goes out as its
# number and the robot's ACK is printed.
ok, rc, out, err = robot_answers(["mode", "walls"],
                                 lambda got: [slamlink.frame(slamlink.ACK, got[2:3])])
check(ok and rc == 0 and slamlink.command(["mode", "walls"]) == slamlink.frame(0x12, b"\x04") and
      out.strip() == "ack command=mode" and "Traceback" not in err,
      "send mode walls: the robot gets MODE 4, its ACK is printed: %s%s" % (out.strip(), err.strip()))
for mode in slamlink.MODES:
    p = run_tool("frame", "mode", mode)
    check(p.returncode == 0 and bytes.fromhex(p.stdout.strip()) ==
          slamlink.frame(0x12, bytes([slamlink.MODES.index(mode)])), "frame mode %s" % mode)
ok, rc, out, err = robot_answers(["set", "cell_um", "100000"],
                                 lambda got: [slamlink.frame(slamlink.ERROR, bytes([0x14, 6, 11]))])
check(ok and rc == 1 and "only when the robot starts" in err,
      "send: a refusal is explained, exit 1: %s" % err.strip())
geo = struct.pack("<BHHIiiBB", 2, 4, 3, 50000, -100000, -50000, 9, 30) + struct.pack("<IIiii", 10**6, 20000, 50000, 0, 0)
rows = [slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", m, r, 0) + bytes([m * 10 + r] * 4))
        for m in (0, 1) for r in range(3)]
outdir = sim.out("maps")
ok, rc, out, err = robot_answers(["map"], lambda got: [slamlink.frame(slamlink.ACK, b"\x16"),
                                                        slamlink.frame(slamlink.HELLO, geo)] + rows,
                                 extra=["--out", outdir])
with open(os.path.join(outdir, "tm.pgm"), "rb") as f:
    tm = f.read()
check(ok and rc == 0 and tm.startswith(b"P5\n4 3\n255\n") and
      os.path.exists(os.path.join(outdir, "om.yaml")),
      "send map --out writes the robot's OM and TM: %s" % out.strip())
sim.done()
