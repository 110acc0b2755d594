#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The firmware's telemetry, as host_sim records it, decodes with tools/telemetry.py and
says exactly what the run's logs say: every reading and the pose ten times a second."""
import csv
import importlib.util
import math
import os
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))  # the tool imports slamtools
spec = importlib.util.spec_from_file_location("telemetry", os.path.join(sim.src, "tools", "telemetry.py"))
telemetry = importlib.util.module_from_spec(spec)
spec.loader.exec_module(telemetry)

run = sim.out("run")
tel = sim.out("telemetry.bin")
sim.run("--duration", 60, "--seed", 2, "--out", run, "--telemetry", tel)

frames = list(f for f in telemetry.frames(tel, 115200, False) if f is not None)
kinds = {}
for f in frames:
    kinds[f["type"]] = kinds.get(f["type"], 0) + 1
check(kinds.get("hello", 0) >= 12 and kinds.get("status", 0) >= 59,
      "hello every 5 s and status every second: %s" % kinds)

with open(os.path.join(run, "readings.csv")) as f:
    rows = list(csv.DictReader(f))
readings = [f for f in frames if f["type"] == "reading"]
check(len(readings) == len(rows) and len(rows) > 500,
      "one READING frame per logged reading (%d)" % len(rows))
mismatch = 0
for fr, row in zip(readings, rows):
    same = (abs(fr["ticks"] / 100.0 - float(row["t_s"])) < 1e-9 and
            fr["servo_mdeg"] == round(float(row["servo_deg"]) * 1000) and
            fr["x_um"] == round(float(row["odom_x_m"]) * 1e6) and
            fr["y_um"] == round(float(row["odom_y_m"]) * 1e6) and
            abs(math.remainder(fr["heading"] * telemetry.BAM - float(row["odom_th_rad"]), 2 * math.pi)) < 1e-8)
    if row["status"] != "timeout":
        same = same and fr["range_um"] == round(float(row["range_m"]) * 1e6)
        same = same and telemetry.reading_status(fr["outcome"]) == row["status"]
    else:
        same = same and fr["outcome"] == 4 and fr["range_um"] == 0
    mismatch += not same
check(mismatch == 0, "every READING frame matches its readings.csv row")

with open(os.path.join(run, "trajectory.csv")) as f:
    traj = {round(float(r["t_s"]) * 100): r for r in csv.DictReader(f)}
poses = [f for f in frames if f["type"] == "pose"]
check(len(poses) == 600, "600 POSE frames in 60 s")
matched = [p for p in poses if p["ticks"] in traj]
bad = sum(1 for p in matched
          if abs(p["x_um"] * 1e-6 - float(traj[p["ticks"]]["odom_x_m"])) > 1e-6 or
          abs(p["y_um"] * 1e-6 - float(traj[p["ticks"]]["odom_y_m"])) > 1e-6)
check(len(matched) == 600 and bad == 0, "POSE frames match the odometry in trajectory.csv")

# A home that fits says nothing of the grid's edge; one that does not (the default room in
# 20 mm cells: a 5.12 m grid) is told, never only clipped: a warning at the end, the count
# in metrics.json, and the STATUS frames carry it once there is one.
fits = sim.run("--duration", 20, "--seed", 2, "--out", sim.out("fits"))
check("does not fit" not in fits.stderr and all(
    f.get("outside", 0) == 0 for f in frames if f["type"] == "status"),
      "a room that fits: no warning, no STATUS with points outside")
small = sim.out("small")
tel = sim.out("small.bin")
p = sim.run("--duration", 120, "--seed", 1, "--cell", 20, "--out", small, "--telemetry", tel)
outside = sim.metrics(small)["robot"]["outside_grid"]
check(outside > 0 and "warning: the home does not fit the grid" in p.stderr
      and "256 x 256 cells of 20 mm" in p.stderr,
      "a room larger than the grid: %d hits outside, and the warning: %r" % (outside, p.stderr))
said = [f["outside"] for f in telemetry.frames(tel, 115200, False)
        if f is not None and f["type"] == "status" and f.get("outside", 0) > 0]
# (the hits still held back for matching when the run ends are placed after the last STATUS)
check(said and 0 < said[-1] <= outside,
      "STATUS frames carry the points outside the grid (%s)" % said[-3:])

# A robot that has explored everything it can reach says so: the STATUS frames carry the
# flag from the second metrics.json gives (the default room, seed 9, is done at 928 s).
done = sim.out("done")
tel = sim.out("done.bin")
sim.run("--duration", 1100, "--seed", 9, "--out", done, "--telemetry", tel)
at = sim.metrics(done)["exploration"]["explored_at_s"]
status = [f for f in telemetry.frames(tel, 115200, False) if f is not None and f["type"] == "status"]
flagged = [f["ticks"] / 100.0 for f in status if f["flags"] & telemetry.slamlink.FLAG_EXPLORED]
check(at is not None and flagged and at <= flagged[0] <= at + 1.0 and
      len(flagged) == sum(1 for f in status if f["ticks"] / 100.0 >= at),
      "STATUS says explored from %s s on (metrics.json: %s s)" % (flagged[:1], at))
sim.done()
