#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One fault of the simulated world at its three levels (tools/sim_report.py FAULTS), over
seeds 1-10: the firmware keeps running to the end without a crash (the sanitizer build
checks that too), the robot keeps moving, the raw map's mean F1 stays above the level's
stated floor, and the body touches something in at most one of the fault's 30 runs (the
smallest clearance is reported). Ten seeds, not two: a level's runs spread widely (σ up
to 0.22 over seeds 1-100, tools/sim_report.py --faults-only --seeds 100), so a floor
judged on two seeds fails or passes by which runs a change happens to move.

Touching runs are rare but not gone: 14 of the 3 600 runs over seeds 1-100 touch
(tools/sim_report.py --faults-only --seeds 100), one in 260, and any change to the path
moves which. No touch in 30 runs would fail a fault's test by chance one time in nine; two
touches in 30 happen by chance one time in 160, and a fault level that touches one run in
ten fails its test four times in five.

The floors and the touch rule were set with the optimistic sonar. Since the default
sweep reaches 90 deg right (firmware/experiments.md, "Exploration") they are judged at the
default level, the typical sonar, for every fault but two (OPTIMISTIC): at the typical
level, seeds 1-10, every floor holds and 9 of the 370 runs touch, 3 with sonar dropouts
(level 3) and 5 with servo stalls (levels 1-3), which fail the touch rule; those two are
still judged with the optimistic sonar (1 touch each there). With the paper's sweep 28 of
the 370 runs touched at the typical level.

usage: test_sim_faults.py HOST_SIM SOURCE_DIR FAULT
"""
import importlib.util
import os
import sys

from simtest import Sim, check, check_path, fail, mean

SEEDS = range(1, 11)
DURATION = 600
OPTIMISTIC = ("dropout", "servo_stall")

fault = sys.argv.pop(3) if len(sys.argv) > 3 else None
SONAR = ("--sonar", "optimistic") if fault in OPTIMISTIC else ()
sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))  # the tool imports slamtools
spec = importlib.util.spec_from_file_location(
    "sim_report", os.path.join(sim.src, "tools", "sim_report.py"))
report = importlib.util.module_from_spec(spec)
spec.loader.exec_module(report)
faults = {f[0]: f for f in report.FAULTS}
if fault not in faults:
    fail("name a fault: %s" % ", ".join(sorted(faults)))
_, what, levels = faults[fault]

touching = []
for k, (args, floor) in enumerate(levels):
    ms = []
    for s in SEEDS:
        out = sim.out("%s-%d-%d" % (fault, k + 1, s))
        sim.run("--seed", s, "--duration", DURATION, "--out", out, *SONAR,
                *report.fault_args(args))
        ms.append(sim.metrics(out))
    label = "%s level %d (%s)" % (fault, k + 1, " ".join(args))
    ticks = DURATION * 100
    check(all(m["robot"]["ticks"] <= ticks and m["robot"]["ticks"] >= ticks * 0.7 for m in ms),
          "%s: the firmware ran to the end (ticks %s of %d)" % (
              label, [m["robot"]["ticks"] for m in ms], ticks))
    check(all(m["odometry"]["path_m"] >= 10.0 for m in ms),
          "%s: the robot kept moving (%s m)" % (label, ["%.0f" % m["odometry"]["path_m"] for m in ms]))
    f1 = mean(m["maps"]["odometry"]["raw"]["f1"] for m in ms)
    check(f1 >= floor, "%s: raw F1 %.3f >= its floor %.2f" % (label, f1, floor))
    clear = [report.clearance_of(m) for m in ms]
    coll = [m["robot"]["collisions"] for m in ms]
    print("   collisions %s, smallest clearance %s" % (
        coll, "not measured" if None in clear else ["%.3f m" % c for c in clear]))
    touching += ["%s seed %d" % (label, s) for s, c in zip(SEEDS, coll) if c]
check_path(len(touching) <= 1, "%s: at most one of its %d runs touches (%s)" % (
    fault, len(levels) * len(SEEDS), ", ".join(touching) or "none"))
sim.done()
