#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Commands over the telemetry link drive the simulated robot (host_sim --commands): it
stops, starts, takes a new setting, sends its map; each malformed command gets exactly
one ERROR frame and changes nothing: the run's logs are byte-identical to a run without
them."""
import csv
import filecmp
import importlib.util
import math
import os
import sys

from simtest import Sim, check, fail

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))  # the tool imports slamtools
spec = importlib.util.spec_from_file_location("telemetry", os.path.join(sim.src, "tools", "telemetry.py"))
telemetry = importlib.util.module_from_spec(spec)
spec.loader.exec_module(telemetry)
link = telemetry.slamlink

SET = link.COMMANDS["set"][0]
good_set = link.command(["set", "cruise_mm_s", "300"])
bad_crc = bytearray(good_set)
bad_crc[-1] ^= 0x55
short = link.frame(SET, good_set[4:8])                # SET one byte short, CRC right
unknown = link.frame(0x5E)                            # no such command
stray = link.frame(link.HELLO)                        # a telemetry type sent to the robot
get99 = link.frame(link.COMMANDS["get"][0], bytes([99]))  # no such key
malformed = [  # (time, hex, what the ERROR must say)
    (16.0, bad_crc.hex(), ("set", "crc", 0)),
    (17.0, short.hex(), ("set", "length", 0)),
    (18.0, unknown.hex(), (0x5E, "command", 0)),
    (19.0, stray.hex(), (link.HELLO, "command", 0)),
    (20.0, get99.hex(), ("get", "key", 99)),
    (21.0, good_set[:-3].hex(), ("set", "length", 0)),    # stops half-way
    (22.0, None, ("set", "range", "cruise_mm_s")),         # above the top speed
    (23.0, None, ("set", "fixed", "cell_um")),             # only at start
    (24.0, None, ("mode", "range", 0)),                    # no mode 7
]
words = {22.0: "set cruise_mm_s 400", 23.0: "set cell_um 100000",
         24.0: "hex " + link.frame(link.COMMANDS["mode"][0], bytes([7])).hex()}
good = ["2 stop", "6 start", "10 set cruise_mm_s 120", "12 get cruise_mm_s", "14 map",
        "26 mode tm"]


def write_commands(path, with_bad):
    lines = ["# time command"] + good[:5]
    if with_bad:
        for t, hexbytes, _ in malformed:
            lines.append("%g %s" % (t, "hex " + hexbytes if hexbytes else words[t]))
    lines += good[5:]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


runs = {}
for name, with_bad in (("bad", True), ("clean", False)):
    cmds = sim.out(name + ".cmds")
    write_commands(cmds, with_bad)
    runs[name] = sim.out(name)
    sim.run("--duration", 60, "--seed", 2, "--commands", cmds, "--telemetry",
            sim.out(name + ".tel"), "--out", runs[name])

frames = [f for f in telemetry.frames(sim.out("bad.tel")) if f is not None]
replies = [(f, i) for i, f in enumerate(frames) if f["type"] in ("ack", "error", "config")]
said = [link.describe(f) for f, _ in replies]
want = (["ack command=stop", "ack command=start", "config key=cruise_mm_s value=120",
         "config key=cruise_mm_s value=120", "ack command=map"] +
        ["error command=%s code=%s%s" % (link.COMMAND_NAMES.get(c, "0x%02x" % c) if isinstance(c, int) else c,
                                         code, " key=%s" % (link.KEY_BY_ID.get(k, (k,))[0] if isinstance(k, int) else k) if k else "")
         for _, _, (c, code, k) in malformed] +
        ["ack command=mode"])
check(said == want, "every command is answered once, in order:\n    %s" % "\n    ".join(said))

status = [f for f in frames if f["type"] == "status"]
refused = max(s["refused"] for s in status)
check(refused == len(malformed), "the robot counts %d refused commands" % refused)

# Stop and start: the robot stands from soon after 2 s until 6 s, and moves before and after.
with open(os.path.join(runs["bad"], "trajectory.csv")) as f:
    traj = [(float(r["t_s"]), float(r["true_x_m"]), float(r["true_y_m"])) for r in csv.DictReader(f)]


def moved(t0, t1):
    pts = [(x, y) for t, x, y in traj if t0 <= t <= t1]
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:]))


check(moved(0.5, 2.0) > 0.05 and moved(3.0, 6.0) < 1e-6 and moved(6.5, 9.5) > 0.05,
      "it stands between STOP and START (%.3f m before, %.6f m stopped, %.3f m after)"
      % (moved(0.5, 2.0), moved(3.0, 6.0), moved(6.5, 9.5)))
stopped = [s for s in status if 3 <= s["ticks"] / 100 <= 6]
check(stopped and all(s["flags"] & link.FLAG_STOPPED for s in stopped), "STATUS says it is stopped")


def top_speed(t0, t1):
    pts = [(t, x, y) for t, x, y in traj if t0 <= t <= t1]
    return max(math.hypot(b[1] - a[1], b[2] - a[2]) / (b[0] - a[0]) for a, b in zip(pts, pts[1:]))


# Before: near the cruise speed of 0.2 m/s, which the typical sonar's sweeps, half of whose
# pings time out at grazing walls, hold back (the robot slows when few pings echo): 0.169
# m/s where the optimistic sonar let it reach 0.215.
check(top_speed(6.5, 10.0) > 0.16 and top_speed(11.0, 26.0) < 0.15,
      "cruise_mm_s = 120 slows it (%.3f m/s before, %.3f m/s after)"
      % (top_speed(6.5, 10.0), top_speed(11.0, 26.0)))
modes = {s["explore_mode"] for s in status if s["ticks"] >= 2700}
check(modes == {link.MODES.index("tm")}, "MODE tm is in force after it (%s)" % modes)

# The map: after its ACK a HELLO, then OM and TM from their first row, every cell once.
ack = next(i for f, i in replies if f["type"] == "ack" and f["command"] == link.COMMANDS["map"][0])
after = frames[ack + 1:]
rows = [f for f in after if f["type"] == "map_row"]
hello = next(f for f in after if f["type"] == "hello")
check(after.index(hello) < after.index(rows[0]) and (rows[0]["map"], rows[0]["row"], rows[0]["first"]) == (0, 0, 0),
      "SEND_MAP: a HELLO, then OM's first row")
a, b = hello["a"], hello["b"]
cells = {0: [bytearray(a) for _ in range(b)], 1: [bytearray(a) for _ in range(b)]}
seen = 0
for f in rows:
    if seen == 2 * a * b:
        break
    cells[f["map"]][f["row"]][f["first"]:f["first"] + len(f["cells"])] = f["cells"]
    seen += len(f["cells"])
check(seen == 2 * a * b, "both maps arrived whole (%d cells)" % seen)
om_cells = sum(1 for row in cells[0] for v in row if v)


def read_map(name, vmax):
    """A map of the run, back from its PGM (grey 255 - v·255/max, top row first)."""
    with open(os.path.join(runs["bad"], name), "rb") as f:
        data = f.read()
    grey = {255 - (v * 255 + vmax // 2) // vmax: v for v in range(vmax + 1)}
    pix = data[len(b"P5\n%d %d\n255\n" % (a, b)):]
    return [[grey[pix[(b - 1 - y) * a + x]] for x in range(a)] for y in range(b)]


tm_end = read_map("tm.pgm", hello["tm_max"])
later = sum(1 for y in range(b) for x in range(a) if cells[1][y][x] > tm_end[y][x])
tm_cells = sum(1 for row in cells[1] for v in row if v)
check(om_cells >= 5 and tm_cells >= 10 and later == 0,
      "the maps sent are the robot's: %d OM and %d TM cells, none of TM above its final count"
      % (om_cells, tm_cells))

# Refused commands changed nothing: the logs equal a run that never received them.
for name in ("readings.csv", "trajectory.csv", "om.pgm", "tm.pgm"):
    if not filecmp.cmp(os.path.join(runs["bad"], name), os.path.join(runs["clean"], name), shallow=False):
        fail("%s differs from the run without the malformed commands" % name)
check(True, "with and without the malformed commands, the logs and maps are byte-identical")

# A bad --commands file: exit 2, file and line named, nothing written.
for text, what in (("1 stop\nabc start\n", ":2:"), ("1 fly\n", ":1:"), ("2 stop\n1 start\n", ":2:"),
                   ("1 set nokey 3\n", "nokey"), ("1 hex a5 5\n", ":1:"), ("1 mode spiral\n", "spiral")):
    path = sim.out("bad-file.cmds")
    with open(path, "w") as f:
        f.write(text)
    out = sim.out("never")
    p = sim.run("--commands", path, "--out", out, expect=2)
    check(what in p.stderr and not os.path.exists(out), "a bad commands file (%r): exit 2, says %s"
          % (text, what))
# --realtime takes a speed factor (checked, not timed: the run must simply complete).
for factor, status in (("0", 2), ("abc", 2), ("5000", 2), ("500", 0)):
    out = sim.out("rt" + factor)
    p = sim.run("--realtime", factor, "--duration", 0.5, "--out", out, expect=status)
    check(status == 0 or ("FACTOR" in p.stderr and not os.path.exists(out)),
          "--realtime %s: exit %d" % (factor, status))
sim.done()
