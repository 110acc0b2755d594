#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The Python tools against the second round of hostile input (issue 30).

Every header field a tool sizes memory by has a stated limit, and forged input fails
cleanly under a memory ceiling (RLIMIT_AS in the child: exit 1 or 2 with a message, never
a MemoryError or a traceback): `telemetry.py view`, `send map`, `to-readings` and
`plot_run.py`. Then N1 (a forged HELLO), N2 (SET values past a double), N9 (a 0 x 0 map
record), and the decoder's work on adversarial bytes, counted in lines of Python run,
never timed.
"""
import os
import pty
import resource
import struct
import subprocess
import sys
import threading
import tty
import zlib

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import link as slamlink  # noqa: E402

TOOLS = os.path.join(sim.src, "tools")
CEILING = 768 << 20  # address space for a tool: ample for numpy and matplotlib, not for 8 GiB


def limited():
    resource.setrlimit(resource.RLIMIT_AS, (CEILING, CEILING))


def tool(name, *args, stdin=None):
    return subprocess.run(["/usr/bin/python3", os.path.join(TOOLS, name)] + [str(a) for a in args],
                          capture_output=True, text=True, preexec_fn=limited, timeout=600)


def clean_failure(p, codes=(1, 2)):
    return (p.returncode in codes and p.stderr.strip() != "" and "Traceback" not in p.stderr
            and "MemoryError" not in p.stderr)


def write(name, data):
    path = sim.out(name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def hello(a, b):
    return slamlink.frame(slamlink.HELLO, struct.pack("<BHHIiiBB", 2, a, b, 50000, 0, 0, 9, 30) +
                          struct.pack("<IIiii", 1000000, 20000, 50000, 0, 0) + bytes([1, 4, 1]))


# ---- N1: a forged HELLO frame ---------------------------------------------------------------
check(slamlink.GRID_SIDE_MIN == 3 and slamlink.GRID_SIDE_MAX == 4096,
      "the grid's limits come from grid.h: 3..4096 cells a side")
check(slamlink.decode(slamlink.HELLO, hello(65535, 65535)[4:-2]) is None and
      slamlink.decode(slamlink.HELLO, hello(4097, 3)[4:-2]) is None and
      slamlink.decode(slamlink.HELLO, hello(2, 100)[4:-2]) is None and
      slamlink.decode(slamlink.HELLO, hello(4096, 4096)[4:-2])["a"] == 4096,
      "decode: a HELLO beyond 3..4096 cells a side is malformed, 4096 x 4096 is a grid")
row = slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", 0, 65534, 65000) + bytes(200))
check(slamlink.decode(slamlink.MAP_ROW, row[4:-2]) is None,
      "decode: a map row beyond 4096 x 4096 is malformed")
forged = write("forged.log", hello(65535, 65535) * 3 + row)
p = tool("telemetry.py", "view", forged, "--png", sim.out("forged.png"))
check(clean_failure(p, (2,)) and "holds no telemetry frame" in p.stderr,
      "view of three forged 65535 x 65535 HELLOs under a %d MiB ceiling: exit 2, a message "
      "(%s)" % (CEILING >> 20, p.stderr.strip()))
p = tool("telemetry.py", "to-readings", forged, "--out", sim.out("forged-readings"))
check(clean_failure(p, (2,)) and not os.path.exists(sim.out("forged-readings")),
      "to-readings of it: exit 2, a message, nothing left behind")


# `send map` against a robot that answers with a forged HELLO and rows beyond any grid.
def send_map(reply, wait="2"):
    master, slave = pty.openpty()
    tty.setraw(slave)
    proc = subprocess.Popen(["/usr/bin/python3", os.path.join(TOOLS, "telemetry.py"), "send",
                             os.ttyname(slave), "map", "--out", sim.out("sent"), "--wait", wait],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=limited)
    got = b""
    while len(got) < 6:
        got += os.read(master, 64)

    def robot():
        try:
            for chunk in reply:
                os.write(master, chunk)
        except OSError:
            pass  # the tool has gone

    t = threading.Thread(target=robot, daemon=True)
    t.start()
    out, err = proc.communicate(timeout=600)
    t.join(timeout=60)
    os.close(master)
    os.close(slave)
    return proc.returncode, out, err


rc, out, err = send_map([slamlink.frame(slamlink.ACK, b"\x16"), hello(65535, 65535)] +
                        [slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", m, r, 0) + bytes(250))
                         for m in (0, 1) for r in range(0, 65535, 997)])
check(rc == 1 and "did not arrive whole" in err and "Traceback" not in err and "MemoryError" not in err,
      "send map, a forged 65535 x 65535 HELLO under the ceiling: exit 1, a message (%s)" % err.strip())
# A whole map of the largest grid the tool believes comes through the same ceiling: the
# check that it is complete counts cells a row as they come (it went over every row
# received for every row of the grid: quadratic).
side = 300
frames = [slamlink.frame(slamlink.ACK, b"\x16"), hello(side, side)]
for m in (0, 1):
    for r in range(side):
        for first in range(0, side, 150):
            frames.append(slamlink.frame(slamlink.MAP_ROW, struct.pack("<BHH", m, r, first) +
                                         bytes([m + 1]) * 150))
rc, out, err = send_map([b"".join(frames)], wait="60")
with open(os.path.join(sim.out("sent"), "tm.pgm"), "rb") as f:
    head = f.read(20)
check(rc == 0 and head.startswith(b"P5\n300 300\n255\n"),
      "send map: a 300 x 300 map of 1 200 rows arrives whole and is written (%s)" % (err.strip() or out.strip()))

# to-readings writes rows as it reads them: a log of 400 000 readings (13 MB) under a
# ceiling a list of them as dicts would not fit in beside numpy (about 200 MB more).
reading = slamlink.frame(slamlink.READING, struct.pack("<IBBiIiiI", 5, 0, 0, 65000, 2495154, 2500000,
                                                       2000000, 0))
big = sim.out("many.log")
with open(big, "wb") as f:
    f.write(hello(160, 160))
    block = reading * 10000
    for _ in range(40):
        f.write(block)
resource_before = CEILING
CEILING = 240 << 20
p = tool("telemetry.py", "to-readings", big, "--out", sim.out("many"))
CEILING = resource_before
lines = sum(1 for _ in open(os.path.join(sim.out("many"), "readings.csv"))) if p.returncode == 0 else 0
check(p.returncode == 0 and lines == 400001,
      "to-readings: 400 000 readings under a 240 MiB ceiling, streamed (%d lines; %s)"
      % (lines, p.stderr.strip()[-200:]))

# ---- plot_run.py: map records and files ---------------------------------------------------
HEADER = struct.Struct("<IHHHHIiiIIiiIBBBBII")


def record(a, b, cells=None, seq=1):
    cells = bytes(2 * a * b) if cells is None else cells
    head = HEADER.pack(0x4D414C53, 1, HEADER.size, a, b, 50000, 0, 0, seq, 100, 0, 0, 0, 1, 4, 1, 9,
                       zlib.crc32(cells), 0)
    head = head[:-4] + struct.pack("<I", zlib.crc32(head[:-4]))
    return head + cells


# N9: a 0 x 0 record whose CRCs are right.
p = tool("plot_run.py", write("zero.bin", record(0, 0)))
check(clean_failure(p, (2,)) and "holds no map record" in p.stderr,
      "N9: plot_run.py on a 0 x 0 record: exit 2, no traceback (%s)" % p.stderr.strip())
# ... beside a good one, the good one is drawn.
p = tool("plot_run.py", write("zero-and-good.bin", record(0, 0, seq=9) + record(4, 3, seq=2)),
         "--out", sim.out("zg.png"), "--quiet")
check(p.returncode == 0 and os.path.exists(sim.out("zg.png")),
      "N9: ... beside a 4 x 3 record, that one is drawn")
# A slot file of 3 GiB (sparse: no disk), and a folder holding one: refused at the limit,
# never read into memory.
slots = sim.out("huge-storage")
os.makedirs(slots)
with open(os.path.join(slots, "slot0.bin"), "wb") as f:
    f.truncate(3 << 30)
for target in (os.path.join(slots, "slot0.bin"), slots):
    p = tool("plot_run.py", target, "--out", sim.out("huge.png"))
    check(clean_failure(p, (2,)) and "larger than 67108864 bytes" in p.stderr,
          "plot_run.py %s of 3 GiB under the ceiling: exit 2, the stated limit" % os.path.basename(target))
# An image whose header claims 65535 x 65535 pixels, with its YAML.
maps = sim.out("huge-maps")
os.makedirs(maps)
with open(os.path.join(maps, "om.pgm"), "wb") as f:
    f.write(b"P5\n65535 65535\n255\n")
    f.truncate(1 << 20)
with open(os.path.join(maps, "om.yaml"), "w") as f:
    f.write("image: om.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
p = tool("plot_run.py", maps, "--out", sim.out("m.png"))
check(clean_failure(p, (2,)), "plot_run.py, an image claiming 65535 x 65535: exit 2 (%s)" % p.stderr.strip())

# ---- N2: SET values past a double ----------------------------------------------------------
for value in ("inf", "1e400", "-inf", "nan", "1e308"):
    p = tool("telemetry.py", "frame", "set", "cal_left", value)
    check(clean_failure(p, (2,)) and ("cal_left" in p.stderr or "-inf" in p.stderr),
          "N2: frame set cal_left %s: exit 2, a message (%s)" % (value, p.stderr.strip()))

# ---- the decoder's work on adversarial bytes -------------------------------------------------
# Lines of slamtools/link.py run per byte fed, counted by a tracer: the CRC in Python cost about
# 500 lines a sync of length 255 (about 130 a byte, ~100 KB/s); now a few per sync.


def lines_per_byte(data):
    dec = slamlink.Decoder()
    count = [0]
    target = slamlink.__file__

    def tracer(frame, event, arg):
        if frame.f_code.co_filename != target:
            return None
        if event == "line":
            count[0] += 1
        return tracer

    sys.settrace(tracer)
    try:
        for i in range(0, len(data), 4096):
            dec.feed(data[i:i + 4096])
    finally:
        sys.settrace(None)
    return count[0] / len(data), dec


for name, data in (("syncs of length 255", b"\xa5\x5a\x01\xff" * 5000),
                   ("syncs back to back", b"\xa5\x5a" * 10000),
                   ("a log with one byte in 40 flipped",
                    bytes(b ^ (0x5A if i % 40 == 0 else 0) for i, b in enumerate(
                        slamlink.frame(slamlink.POSE, bytes(range(16))) * 900)))):
    per_byte, dec = lines_per_byte(data)
    check(per_byte <= 12.0 and dec.steps <= len(data) // 2 + 1,
          "decoder on %s: %.1f lines of Python a byte, %d syncs tried for %d bytes"
          % (name, per_byte, dec.steps, len(data)))
good = open(os.path.join(sim.src, "tests", "fuzz", "corpus", "telemetry", "stream-start.bin"), "rb").read()
d1 = slamlink.Decoder()
frames1 = d1.feed(good)
d2 = slamlink.Decoder()
frames2 = [f for i in range(len(good)) for f in d2.feed(good[i:i + 1])]
check(frames1 == frames2 and len(frames1) > 0 and d1.bad == d2.bad and d1.skipped == d2.skipped,
      "the decoder finds the same frames fed whole or a byte at a time (%d frames)" % len(frames1))
check(all(slamlink.crc16(bytes([i, j])) == slamlink.crc16_table(bytes([i, j]))
          for i in range(256) for j in range(0, 256, 17)),
      "the CRC in C (binascii) is the firmware's table CRC")
sim.done()
