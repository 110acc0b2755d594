#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""make calibrate: the whole UMBmark procedure in the simulator gives back the shipped
calibration (host_sim/calibration/default_robot.conf) within 1e-4 in each factor, cuts
E_max,syst at least tenfold on each of five fresh seeds (the same seed uncalibrated and
calibrated), and host_sim's default run uses that calibration for the default robot only."""
import os
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import umbmark  # noqa: E402

TOLERANCE = 1e-4  # 0.01 %: 0.3 mm of return error on the 1.5 m square
shipped_path = os.path.join(sim.src, "host_sim", "calibration", "default_robot.conf")
shipped = umbmark.read_config(shipped_path)

out = sim.out("calibrate")
made = sim.out("made.conf")
p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", "calibrate_sim.py"),
                    sim.bin, "--out", out, "--write", made],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 0 and p.stdout.count("E_max,syst before") == 5
      and p.stderr.count("UMBmark run") == 10,
      "the procedure runs: a progress line for each run of the calibration round, a line for "
      "each of five verification seeds:\n  %s" % "\n  ".join(p.stdout.strip().splitlines()))
again = umbmark.read_config(made)
for key in ("cal_left", "cal_right", "cal_base"):
    check(abs(again[key] - shipped[key]) <= TOLERANCE,
          "%s made again: %.6f, shipped %.6f (within %g)" % (key, again[key], shipped[key], TOLERANCE))


def analysed(*parts):
    d = os.path.join(out, *parts)
    return umbmark.calibrate(os.path.join(d, "umbmark.csv"), os.path.join(d, "config.txt"))[0]


first = analysed("calibration")
check(first["cal_before"] == (1.0, 1.0, 1.0), "the calibration round ran uncalibrated")
for seed in range(2, 7):
    before, after = analysed("verify-%d" % seed, "before"), analysed("verify-%d" % seed, "after")
    gain = before["e_max_syst"] / after["e_max_syst"]
    check(gain >= 10.0 and before["cal_before"] == (1.0, 1.0, 1.0) and
          all(abs(a - again[k]) < 1e-6
              for a, k in zip(after["cal_before"], ("cal_left", "cal_right", "cal_base"))),
          "seed %d: UMBmark cuts E_max,syst %.1fx: %.1f mm uncalibrated, %.1f mm with the new "
          "calibration (at least 10x)" % (seed, gain, before["e_max_syst"], after["e_max_syst"]))

# host_sim's default robot runs with the shipped calibration; another robot without it.
for name, args, want in (("default", (), shipped_path),
                         ("ideal", ("--ideal",), None),
                         ("other-wheels", ("--error", "ed=1.01"), None),
                         ("none", ("--calibration", "none"), None),
                         ("given", ("--ideal", "--calibration", made), made)):
    d = sim.out("run-" + name)
    sim.run("--duration", 5, "--out", d, *args)
    sc = sim.metrics(d)["scenario"]
    cal = sc["cal"]
    expect = umbmark.read_config(want) if want else {"cal_left": 1, "cal_right": 1, "cal_base": 1}
    same_file = (sc["calibration"] is None) == (want is None) and \
        (want is None or os.path.realpath(sc["calibration"]) == os.path.realpath(want))
    check(same_file and abs(cal["left"] - expect["cal_left"]) < 1e-6
          and abs(cal["right"] - expect["cal_right"]) < 1e-6
          and abs(cal["base"] - expect["cal_base"]) < 1e-6,
          "%s run: calibration %s (cal_base %.6f)" % (name, sc["calibration"], cal["base"]))
sim.run("--calibration", sim.out("missing.conf"), "--out", sim.out("bad"), expect=2)
check(not os.path.exists(sim.out("bad")), "a missing --calibration file: exit 2, nothing written")
sim.done()
