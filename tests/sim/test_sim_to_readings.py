#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A robot's run back on the PC: the telemetry log of a run, turned into readings.csv by
tools/telemetry.py to-readings and replayed by host_sim --replay, gives the run's own
om.pgm byte for byte; with another confidence radius it maps what it called far."""
import csv
import filecmp
import os
import re
import subprocess

from simtest import Sim, check, fail

sim = Sim()
tool = os.path.join(sim.src, "tools", "telemetry.py")
run = sim.out("run")
log = sim.out("robot.log")
sim.run("--duration", 120, "--seed", 4, "--room", sim.room("obstacles.room"), "--out", run,
        "--telemetry", log)

p = subprocess.run(["/usr/bin/python3", tool, "to-readings", log, "--out", sim.out("back")],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 0 and "readings.csv" in p.stdout and "Traceback" not in p.stderr,
      "to-readings converts the log: %s" % p.stdout.strip().splitlines()[0])
back = os.path.join(sim.out("back"), "readings.csv")

with open(os.path.join(run, "readings.csv")) as f:
    logged = list(csv.DictReader(f))
with open(back) as f:
    reader = csv.DictReader(f)
    columns = reader.fieldnames
    rows = list(reader)
check(columns == ["t_s", "servo_deg", "range_m", "status", "odom_x_m", "odom_y_m", "odom_th_rad"],
      "readings.csv from telemetry has the run's columns without the truth")
same = len(rows) == len(logged)
for a, b in zip(rows, logged):
    same = same and all(a[k] == b[k] for k in columns if k != "odom_th_rad")
    same = same and abs(float(a["odom_th_rad"]) - float(b["odom_th_rad"])) < 1e-10
check(same and len(rows) > 1000, "its %d rows are the run's, to the last digit" % len(rows))
statuses = {r["status"] for r in rows}
check({"ok", "far", "timeout"} <= statuses, "with the statuses ok, far and timeout (%s)" % sorted(statuses))

rep = sim.out("replay")
sim.run("--replay", back, "--out", rep)
check(filecmp.cmp(os.path.join(run, "om.pgm"), os.path.join(rep, "om.pgm"), shallow=False) and
      filecmp.cmp(os.path.join(run, "om.yaml"), os.path.join(rep, "om.yaml"), shallow=False),
      "replayed, it gives the run's om.pgm and om.yaml byte for byte")

# Re-tuning on the PC: a larger rc maps the echoes the robot called far.
cfg = os.path.join(sim.out("back"), "config.txt")
with open(cfg) as f:
    text = f.read()
wide = sim.out("wide.txt")
with open(wide, "w") as f:
    f.write(text.replace("confidence_radius_um = 1000000", "confidence_radius_um = 1500000"))
if text == open(wide).read():
    fail("config.txt from to-readings lacks confidence_radius_um:\n" + text)


def replay_hits(*args):
    """A replay's OM hits, as it prints them."""
    p = subprocess.run([sim.bin, "--no-plot", "--replay", back] + list(args), stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    m = re.search(r"\((\d+) OM hits\)", p.stdout)
    if p.returncode != 0 or not m:
        fail("replay %s: exit %d\n%s%s" % (" ".join(args), p.returncode, p.stdout, p.stderr))
    return int(m.group(1))


# Between 1 m and 1.5 m: the echoes the robot called far, which the wider rc maps (less
# those that fall just behind a wall the map already holds: matched, not mapped).
far = sum(1 for r in rows if r["status"] == "far" and float(r["range_m"]) < 1.5)
narrow = replay_hits("--out", sim.out("narrow"))
widened = replay_hits("--config", wide, "--out", sim.out("wide"))
check(far > 50 and widened - narrow > far // 2,
      "a replay with rc = 1.5 m maps the echoes the robot called far: %d OM hits against %d with "
      "1 m (%d echoes from 1 m to 1.5 m)" % (widened, narrow, far))

# A log with nothing usable is refused, and nothing is written.
noise = sim.out("noise.log")
with open(noise, "wb") as f:
    f.write(bytes((i * 7919) % 251 for i in range(5000)))
for src, what in ((noise, "no telemetry frame"), (sim.out("missing.log"), "No such file"),
                  (sim.work, "is a directory")):
    p = subprocess.run(["/usr/bin/python3", tool, "to-readings", src, "--out", sim.out("never")],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    check(p.returncode == 2 and what in p.stderr and "Traceback" not in p.stderr and
          not os.path.exists(sim.out("never")), "to-readings on %s: exit 2, '%s'" % (os.path.basename(src), what))
sim.done()
