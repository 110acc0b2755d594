#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim --replay readings.csv rebuilds om.pgm exactly, through the same mapper."""
import filecmp
import os

from simtest import Sim, check

sim = Sim()
run = sim.out("run")
sim.run("--duration", 120, "--seed", 5, "--room", sim.room("obstacles.room"), "--out", run)
rep = sim.out("replay")
sim.run("--replay", os.path.join(run, "readings.csv"), "--out", rep)
check(filecmp.cmp(os.path.join(run, "om.pgm"), os.path.join(rep, "om.pgm"), shallow=False),
      "the replayed om.pgm is byte-identical to the run's")
check(filecmp.cmp(os.path.join(run, "om.yaml"), os.path.join(rep, "om.yaml"), shallow=False),
      "and so is om.yaml")
m = sim.metrics(run)
check(m["robot"]["om_hits"] > 100, "the log had something to replay (%d OM hits)" % m["robot"]["om_hits"])

# With a second sonar mapped (looking left from the servo's axis), its readings are in the
# log too, at servo angle 0, between the sweep's; the replay maps them as the run did.
run1 = sim.out("run_sonar1")
sim.run("--duration", 60, "--seed", 5, "--room", sim.room("obstacles.room"), "--sonar1", 0.05, 0,
        90, "--out", run1)
m1 = sim.metrics(run1)
with open(os.path.join(run1, "readings.csv")) as f:
    rows = [ln.split(",") for ln in f if ln[:1].isdigit()]
left = [r for r in rows if float(r[1]) == 0.0]
sweep = len(rows) - len(left)
check(m1["robot"]["sonar1_readings"] > 300 and len(left) == m1["robot"]["sonar1_readings"] and
      m1["robot"]["pings"] - 1 <= sweep <= m1["robot"]["pings"],
      "the second sonar's %d readings are logged at servo angle 0, with the sweep's %d"
      % (len(left), sweep))
rep1 = sim.out("replay_sonar1")
sim.run("--replay", os.path.join(run1, "readings.csv"), "--out", rep1)
check(filecmp.cmp(os.path.join(run1, "om.pgm"), os.path.join(rep1, "om.pgm"), shallow=False),
      "a run with the second sonar replays byte-identically")

# A damaged log is refused, naming the line.
bad = sim.out("bad.csv")
with open(os.path.join(run, "readings.csv")) as f:
    lines = f.readlines()
lines[5] = "12.3,65.000,zero,ok,1,2,3,4,5,6\n"
with open(bad, "w") as f:
    f.writelines(lines)
p = sim.run("--replay", bad, "--config", os.path.join(run, "config.txt"), "--out", sim.out("never"), expect=2)
check(bad + ":6:" in p.stderr and not os.path.exists(sim.out("never")), "a malformed reading names its line")

# B11 and other input that is not a log: each exit 2, naming the line, writing nothing.
cfg = os.path.join(run, "config.txt")
header = lines[0]
cases = [
    ("/dev/null", None, "/dev/null: is not a regular file"),
    ("empty.csv", "", "empty.csv: empty: not a readings.csv"),
    ("nul.csv", header + lines[1][:10] + "\0" + lines[1][10:], ":2: a NUL byte"),
    ("long.csv", header + "1," * 300 + "\n", ":2: line longer than 511 characters"),
    ("fields.csv", header + "1,90,1.0,ok,0\n", ":2: malformed reading: a column is missing"),
    ("servo.csv", header + "1,1e300,1.0,ok,0,0,0,0,0,0\n", ":2: malformed reading: servo_deg"),
    ("status.csv", header + "1,90,,lost,0,0,0,0,0,0\n", ":2: malformed reading: status"),
    ("header.csv", "time,angle\n", ":1: not a readings.csv header"),
]
for name, text, says in cases:
    path = name if text is None else sim.out(name)
    if text is not None:
        with open(path, "w") as f:
            f.write(text)
    p = sim.run("--replay", path, "--config", cfg, "--out", sim.out("never"), expect=2)
    check(says in p.stderr and not os.path.exists(sim.out("never")),
          "%s: exit 2, says '%s', writes nothing" % (name, says))

# N8: a log without readings has nothing to replay (an empty map would pass for a result),
# and a log cut inside its last row would map the cut number: both refused, nothing written.
hdr = sim.out("header-only.csv")
with open(hdr, "w") as f:
    f.write(header)
p = sim.run("--replay", hdr, "--config", cfg, "--out", sim.out("empty"), expect=2)
check("header-only.csv: a header and no reading" in p.stderr and not os.path.exists(sim.out("empty")),
      "N8: a header without rows: exit 2, nothing written")
cut = sim.out("cut.csv")
with open(cut, "w") as f:
    f.write("".join(lines[:4]) + lines[4][:-4])  # the heading's last digits lost
p = sim.run("--replay", cut, "--config", cfg, "--out", sim.out("cut"), expect=2)
check("cut.csv:5: the last line has no newline" in p.stderr and not os.path.exists(sim.out("cut")),
      "N8: a file cut inside its last row's heading: exit 2, nothing written")

# The output folder is checked before anything is read or written.
with open(sim.out("afile"), "w") as f:
    f.write("x")
p = sim.run("--replay", os.path.join(run, "readings.csv"), "--out", sim.out("afile"), expect=2)
check("--out" in p.stderr and "not a directory" in p.stderr, "--out naming a file: exit 2")
sim.done()
