#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/pose_report.py: the paired difference on − off and its standard error against a
case worked by hand, and its room-by-room table against the runs' own metrics.json (a short
report: two seeds, two-minute runs, no long runs), and --perfect-odometry's runs."""
import json
import math
import os
import re
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
import pose_report  # noqa: E402


def run(seed, f1):
    return {"scenario": {"seed": seed}, "maps": {"odometry": {"raw": {"f1": f1}}}}


# By hand: differences 0.1, 0.3, 0.2 (seed 4 has no partner and is left out); mean 0.2,
# sample variance 0.01, standard error sqrt(0.01 / 3).
on = [run(1, 0.6), run(2, 0.9), run(3, 0.5), run(4, 0.1)]
off = [run(3, 0.3), run(1, 0.5), run(2, 0.6)]
diff, se = pose_report.paired_difference(on, off)
check(abs(diff - 0.2) < 1e-12, "paired by seed, not by order: mean difference %.6f = 0.2" % diff)
check(abs(se - math.sqrt(0.01 / 3)) < 1e-12,
      "standard error %.6f = sqrt(0.01 / 3) = %.6f" % (se, math.sqrt(0.01 / 3)))
check(math.isnan(pose_report.paired_difference([run(1, 0.5)], [run(1, 0.4)])[1]),
      "one seed: no standard error claimed")

# The gap's spread: gaps 0.1, 0.3, 0.2 have σ 0.1 and a standard error of 0.1 / sqrt(3).
def gap_run(true_f1, own_f1):
    return {"maps": {"perfect_odometry": {"raw": {"f1": true_f1}},
                     "odometry": {"raw": {"f1": own_f1}}}}


sd, se = pose_report.gap_spread([gap_run(0.9, 0.8), gap_run(0.9, 0.6), gap_run(0.7, 0.5)])
check(abs(sd - 0.1) < 1e-12 and abs(se - 0.1 / math.sqrt(3)) < 1e-12,
      "the gap's σ %.6f = 0.1 and standard error %.6f = 0.1 / sqrt(3)" % (sd, se))

out = sim.out("report")
p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", "pose_report.py"),
                    "--host-sim", sim.bin, "--quick", "--seeds", "2", "--out", out],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 0, "pose_report --quick --seeds 2 runs (%s)" % p.stderr.strip()[-200:])
left = sorted({f for d in os.listdir(out) for f in os.listdir(os.path.join(out, d))})
check(left == ["args.json", "config.txt", "metrics.json", "timing.json"],
      "each run keeps its metrics and small files only, the logs and maps deleted: %s" % left)
check(re.search(r"^The gap with the correction, every room: σ \d\.\d{3} per run, standard "
                r"error \d\.\d{3} over the runs\.$", p.stdout, re.M) is not None,
      "the report prints the gap's spread")
table = p.stdout.split("### What the correction changes, room by room", 1)
check(len(table) == 2, "the report prints the room-by-room table")
rows = re.findall(r"^\| (\w+) \| ([+-]\d\.\d{3}) \| (\d\.\d{3}|nan) \|$", table[1], re.M)
rooms = pose_report.rooms()
check([r[0] for r in rows] == rooms, "a row for every shipped room: %s" % rooms)
for room, shown, _ in rows:
    f1 = {}
    for mode in ("on", "off"):
        for s in (1, 2):
            with open(os.path.join(out, "%s-%s-%d" % (room, mode, s), "metrics.json")) as f:
                f1[mode, s] = json.load(f)["maps"]["odometry"]["raw"]["f1"]
    expect = ((f1["on", 1] - f1["off", 1]) + (f1["on", 2] - f1["off", 2])) / 2
    check(abs(float(shown) - expect) <= 0.0005 + 1e-9,
          "%s: %s is the mean of its seeds' differences (%.4f)" % (room, shown, expect))

# --perfect-odometry: every run's odometry exact, so without the correction the pose ends
# where the robot is, but for the encoders' whole counts: 0.3 mm at most in two minutes in
# every room, against 32–123 mm with the default errors (seed 1).
out = sim.out("perfect")
p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", "pose_report.py"),
                    "--host-sim", sim.bin, "--quick", "--seeds", "1", "--perfect-odometry",
                    "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 0, "pose_report --perfect-odometry runs (%s)" % p.stderr.strip()[-200:])
check("odometry perfect" in p.stdout, "the report says its odometry was perfect")
for room in rooms:
    with open(os.path.join(out, "%s-off-1" % room, "metrics.json")) as f:
        m = json.load(f)
    e = m["scenario"]["errors"]
    check((e["ed"], e["eb"], e["noise"], e["slip"]) == (1, 1, 0, 0)
          and m["scenario"]["calibration"] is None,
          "%s: no odometry error and no calibration file (%s)" % (room, e))
    check(m["odometry"]["final_position_m"] < 0.005,
          "%s: odometry alone ends within 5 mm of the robot (%.4f m)"
          % (room, m["odometry"]["final_position_m"]))
sim.done()
