#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The scorer `make compare` scores every map with (tools/mapscore.py): hand-counted cases,
host_sim's own metrics.json reproduced to 4 decimals, the firmware's side of the
comparison (the log with the true poses, replayed) equal to the run's om_ideal.pgm, the
log of estimated poses OctoMap is given, and HIMM (slamtools/himm.py) by hand and on a
run. Needs no OctoMap."""
import os
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
import compare  # noqa: E402  (tools/ is on the path only now)
from slamtools import himm, mapscore  # noqa: E402
from slamtools.errors import ToolError  # noqa: E402

tool = os.path.join(sim.src, "tools", "mapscore.py")


def write_pgm(path, rows):
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (len(rows[0]), len(rows)))
        f.write(bytes(v for row in rows for v in row))


def score_cli(*args):
    return subprocess.run(["/usr/bin/python3", tool] + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)


# A 6 x 5 grid by hand. Truth: the top row; observable: its first four cells. Mapped
# (black, 0): (1, 1) next to the wall, (0, 5) on the unobservable end of it, (3, 5) far
# from it; grey and white pixels are not occupied. Precision 2/3; the observable cells
# 0..2 lie within one cell of (1, 1), cell 3 of nothing: recall 3/4; F1 12/17.
X, O, U, F = 0, 255, 205, 254
case = sim.out("case")
os.makedirs(case)
write_pgm(os.path.join(case, "scoring_truth.pgm"), [[X] * 6] + [[O] * 6] * 4)
write_pgm(os.path.join(case, "scoring_observable.pgm"), [[X] * 4 + [O] * 2] + [[O] * 6] * 4)
write_pgm(os.path.join(case, "map.pgm"), [[F, F, U, F, F, X],
                                          [U, X, F, F, U, F],
                                          [F, F, F, F, F, F],
                                          [U, U, U, U, U, X],
                                          [U, U, U, U, U, U]])
truth, observable = mapscore.load_truth(case)
s = mapscore.score_file(os.path.join(case, "map.pgm"), truth, observable)
check((s["mapped"], s["true_positive"], s["observable"], s["matched"]) == (3, 2, 4, 3),
      "hand-counted case: mapped 3, true positives 2, observable 4, matched 3: %s" % s)
check(abs(s["precision"] - 2 / 3) < 1e-12 and abs(s["recall"] - 0.75) < 1e-12 and
      abs(s["f1"] - 12 / 17) < 1e-12, "hand-counted case: P 2/3, R 3/4, F1 12/17: %s" % s)
p = score_cli(os.path.join(case, "map.pgm"), case)
check(p.returncode == 0 and "f1 0.7059" in p.stdout, "the command line says it: %s" % p.stdout.strip())

# The truth itself: every mapped cell true, every observable cell matched, the unobservable
# end of the wall counted for precision only. An empty map scores 0, not a division by 0.
write_pgm(os.path.join(case, "wall.pgm"), [[X] * 6] + [[U] * 6] * 4)
s = mapscore.score_file(os.path.join(case, "wall.pgm"), truth, observable)
check((s["mapped"], s["true_positive"], s["matched"], s["f1"]) == (6, 6, 4, 1.0),
      "the truth as a map: 6 of 6 true, 4 of 4 matched, F1 1: %s" % s)
write_pgm(os.path.join(case, "empty.pgm"), [[U] * 6] * 5)
s = mapscore.score_file(os.path.join(case, "empty.pgm"), truth, observable)
check((s["mapped"], s["precision"], s["recall"], s["f1"]) == (0, 0.0, 0.0, 0.0),
      "an empty map: precision, recall and F1 0: %s" % s)
# Two cells off the wall is not within one: a map shifted down by two rows scores nothing;
# by one row, everything (the tolerance of one cell, Chebyshev, diagonals included).
write_pgm(os.path.join(case, "shift2.pgm"), [[U] * 6] * 2 + [[X] * 6] + [[U] * 6] * 2)
write_pgm(os.path.join(case, "diag.pgm"), [[U] * 6, [U, X, U, X, U, U]] + [[U] * 6] * 3)
s2 = mapscore.score_file(os.path.join(case, "shift2.pgm"), truth, observable)
sd = mapscore.score_file(os.path.join(case, "diag.pgm"), truth, observable)
check(s2["true_positive"] == 0 and s2["matched"] == 0 and sd["true_positive"] == 2 and
      sd["matched"] == 4, "two rows off scores 0 (%s); one row off, diagonally, matches "
      "all 4 observable cells (%s)" % (s2, sd))

# host_sim's own scores of the firmware's maps, reproduced from the masks --scoring writes.
run = sim.out("run")
sim.run("--room", sim.room("obstacles.room"), "--duration", 300, "--seed", 3, "--out", run,
        "--scoring")
truth, observable = mapscore.load_truth(run)
maps = sim.metrics(run)["maps"]
for pgm, which in (("om.pgm", "odometry"), ("om_ideal.pgm", "perfect_odometry")):
    mine = mapscore.score_file(os.path.join(run, pgm), truth, observable)
    check(mine["mapped"] > 0 and compare.same_4(mine, maps[which]["raw"]),
          "%s scores as metrics.json's %s raw map: %s" % (pgm, which, mine))

# The firmware's side of make compare: the log with the true poses, localizer off, replayed.
true_dir = sim.out("true")
n = compare.true_pose_log(run, true_dir)
sim.run("--replay", os.path.join(true_dir, "readings.csv"), "--out", true_dir)
with open(os.path.join(true_dir, "om.pgm"), "rb") as a, open(os.path.join(run, "om_ideal.pgm"), "rb") as b:
    check(n > 100 and a.read() == b.read(),
          "%d readings from the true poses replay into om_ideal.pgm byte for byte" % n)

# From the estimated poses: with the localizer on, the estimate is not odometry, and OctoMap
# gets it row for row in the odometry columns.
est = os.path.join(run, "readings_estimate.csv")
compare.estimate_log(run, est)
with open(os.path.join(run, "readings.csv")) as f:
    orig = [line.rstrip("\n").split(",") for line in f]
with open(os.path.join(run, "scoring_estimate.csv")) as f:
    believed = [line.rstrip("\n").split(",") for line in f]
with open(est) as f:
    got = [line.rstrip("\n").split(",") for line in f]
moved = sum(o[4:7] != b[1:4] for o, b in zip(orig[1:], believed[1:]))
check(len(got) == len(orig) == len(believed) and got[0] == orig[0] and
      all(g[4:7] == b[1:4] and g[:4] == o[:4] and g[7:] == o[7:]
          for g, o, b in zip(got[1:], orig[1:], believed[1:])) and moved > len(orig) // 4,
      "the estimate log: odometry columns replaced by the estimate (%d of %d rows differ "
      "from odometry), the rest unchanged" % (moved, len(orig) - 1))
# The last column: OM's byte where the echo ends, seen from the estimate; empty without
# one. A robot that knows where it is puts most of its echoes within rc where OM holds no
# free space (a wall it mapped, or nothing yet).
at = believed[0].index("om_at_echo")
ends = [(o[3], b[at]) for o, b in zip(orig[1:], believed[1:])]
within = [int(v) for st, v in ends if st == "ok"]
check(all(v == "" for st, v in ends if st == "timeout") and within and
      all(0 <= v <= 255 for v in within) and sum(v >= 127 for v in within) > 0.8 * len(within),
      "om_at_echo: empty without an echo, a byte with one, %d of %d echoes within rc where "
      "OM holds at most one beam's free space" % (sum(v >= 127 for v in within), len(within)))
with open(os.path.join(run, "scoring_estimate.csv"), "w") as f:
    f.write("\n".join(",".join(b) for b in believed[:-1]) + "\n")
try:
    compare.estimate_log(run, est)
    check(False, "an estimate log with a row missing is refused")
except ToolError as e:
    check("scoring_estimate.csv" in str(e), "an estimate log with a row missing is refused: %s" % e)

# HIMM by hand: a 10 x 10 grid of 0.1 m cells, the sonar at the robot's axle, the robot in
# cell (0, 5) facing +x, the servo at 90 deg (straight ahead). An echo at 0.5 m adds 3 to
# cell (5, 5) and takes 1 from cells 0..4 of its row: one hit is occupied (threshold 3).
# An echo beyond the 1 m reach then crosses (5, 5) without a hit: 2, free. A timeout and
# an echo under the minimum range change nothing; the odometry columns are read on asking.
def himm_log(lines):
    path = os.path.join(case, "himm.csv")
    with open(path, "w") as f:
        f.write("t_s,servo_deg,range_m,status,odom_x_m,odom_y_m,odom_th_rad,"
                "true_x_m,true_y_m,true_th_rad\n")
        for t, (rng, status) in enumerate(lines):
            f.write("%d,90,%s,%s,0.05,0.15,0,0.05,0.55,0\n" % (t, rng, status))
    return path


grid = (10, 10, 0.0, 0.0, 0.1)
row = 10 - 1 - 5  # the PGM's first row is the largest y
img = himm.himm_map(himm_log([("0.5", "ok"), ("", "timeout"), ("0.01", "near")]), grid,
                    (0, 0, 0))
check(img[row, 5] == 0 and all(img[row, :5] == 254) and (img == 205).sum() == 94,
      "HIMM: one echo, its cell occupied, the cells before it free, the rest unknown")
img = himm.himm_map(himm_log([("0.5", "ok"), ("1.5", "far")]), grid, (0, 0, 0))
check(img[row, 5] == 254 and all(img[row, :] == 254) and (img == 0).sum() == 0,
      "HIMM: an echo beyond the reach takes one from the hit, which is free then")
img = himm.himm_map(himm_log([("0.5", "ok")]), grid, (0, 0, 0), poses="odom")
check(img[10 - 1 - 1, 5] == 0 and img[row, 5] == 205, "HIMM: the odometry columns on asking")
try:
    himm.himm_map(os.path.join(case, "scoring_truth.pgm"), grid, (0, 0, 0))
    check(False, "HIMM refuses a file that is no readings.csv")
except ToolError as e:
    check("scoring_truth.pgm" in str(e), "HIMM refuses a file that is no readings.csv: %s" % e)
# On the run: from the true poses HIMM maps the room about as well as the firmware (a wrong
# bearing or mount would put its hits elsewhere).
fw = mapscore.score_file(os.path.join(run, "om_ideal.pgm"), truth, observable)["f1"]
hm = compare.himm_score(run, os.path.join(run, "readings.csv"), "true",
                        os.path.join(case, "himm_run.pgm"), truth, observable)["f1"]
check(abs(hm - fw) < 0.1 and hm > 0.7, "HIMM from the true poses F1 %.3f, the firmware's %.3f"
      % (hm, fw))

# Bad input: a message naming the file, exit 2.
p = score_cli(os.path.join(run, "om.pgm"), case + "-missing")
check(p.returncode == 2 and "scoring_truth.pgm" in p.stderr and "--scoring" in p.stderr,
      "a run without the masks is named: %s" % p.stderr.strip())
with open(os.path.join(case, "bad.pgm"), "w") as f:
    f.write("P2\n2 2\n255\n0 0 0 0\n")
p = score_cli(os.path.join(case, "bad.pgm"), case)
check(p.returncode == 2 and "bad.pgm" in p.stderr, "a text PGM is refused: %s" % p.stderr.strip())
p = score_cli(os.path.join(run, "om.pgm"), case)
check(p.returncode == 2 and "om.pgm" in p.stderr, "a map of another size is refused: %s" % p.stderr.strip())
sim.done()
