#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""UMBmark on the simulated robot, as a robot builder does it on a real one (make calibrate).

usage: tools/calibrate_sim.py HOST_SIM [--write FILE] [--out DIR] [--side-mm MM]
                              [--seed N] [--verify N] [-- HOST_SIM_ARGS...]

1. The robot as built, uncalibrated (host_sim --calibration none), drives UMBmark in the
   default room: 5 squares clockwise, 5 counter-clockwise, each from the start pose.
   host_sim's simulated experimenter measures every run's return error with a tape (the
   true pose, +-5 mm) while the robot pauses, and puts it back at the start.
2. tools/umbmark.py turns those errors into E_d, E_b and the calibration.
3. Verification on fresh random errors: for each of the --verify seeds that follow (5 by
   default), the same robot drives UMBmark once uncalibrated and once with the new
   calibration, so before and after meet the same slip and noise.
It prints E_max,syst before and after for each seed and the smallest gain, and writes the
calibration (default: host_sim/calibration/default_robot.conf, what host_sim uses for the
default robot). Runs go to DIR/calibration and DIR/verify-SEED/{before,after} (default
out/calibrate). Arguments after `--` go to every host_sim run (another --room, --start,
--error ...).
Exit status: 0 done; 1 a run failed, or a verification seed gained less than 10x (the
calibration is written all the same); 2 bad options.
"""
import os
import subprocess
import sys

from slamtools import umbmark
from slamtools.errors import FAILED, ToolError, main as tool_main
from slamtools.runs import SRC

DEFAULT_WRITE = os.path.join(SRC, "host_sim", "calibration", "default_robot.conf")
SIDE_MM = 1500     # fits the default 5 m x 4 m room both ways from its start pose
PAUSE_S = 2        # the simulated person is quick
TARGET = 10.0      # Borenstein & Feng report 10-22x on real robots
VERIFY_SEEDS = 5   # fresh random errors the calibration is verified on


def round_of(host_sim, out, seed, side_mm, calibration, extra, title):
    """One UMBmark round in host_sim: the analysis of its runs (umbmark.analyse()); a
    title, when given, is printed with the round's E_max,syst."""
    if title:
        print(title, flush=True)
    args = [host_sim, "--explore", "umbmark", "--calibration", calibration,
            "--set", "square_side_um=%d" % round(side_mm * 1000), "--set",
            "umbmark_pause_s=%d" % PAUSE_S, "--seed", str(seed), "--duration", "3600",
            "--out", out, "--no-plot"] + extra
    # The runs' progress lines come on stderr, as they happen (those of the verification
    # rounds are left out: one line a seed says enough); host_sim's map summary is of no
    # interest here.
    p = subprocess.run(args, stdout=subprocess.PIPE,
                       stderr=None if title else subprocess.DEVNULL, text=True)
    if p.returncode != 0:
        raise ToolError("host_sim failed (exit %d): %s" % (p.returncode, " ".join(args)), FAILED)
    try:
        a, text = umbmark.calibrate(os.path.join(out, "umbmark.csv"),
                                    os.path.join(out, "config.txt"))
    except ToolError as e:
        raise ToolError("the runs of %s: %s" % (out, e), FAILED) from None
    if a["n_cw"] + a["n_ccw"] != 2 * umbmark.RUNS_EACH_WAY:
        raise ToolError("%s: %d runs measured, not %d (the run ended early?)"
                        % (out, a["n_cw"] + a["n_ccw"], 2 * umbmark.RUNS_EACH_WAY), FAILED)
    if title:
        print("  E_max,syst = %.1f mm (centres of gravity: cw %.1f mm, ccw %.1f mm)"
              % (a["e_max_syst"], a["r_cw"], a["r_ccw"]), flush=True)
    return a, text


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    host_sim = argv[0]
    opts = {"--write": DEFAULT_WRITE, "--out": "out/calibrate", "--side-mm": str(SIDE_MM),
            "--seed": "1", "--verify": str(VERIFY_SEEDS)}
    extra = []
    i = 1
    while i < len(argv):
        if argv[i] == "--":
            extra = argv[i + 1:]
            break
        if argv[i] in opts and i + 1 < len(argv):
            opts[argv[i]] = argv[i + 1]
            i += 2
            continue
        raise ToolError("unknown option or missing value '%s' (--help)" % argv[i])
    try:
        side_mm = float(opts["--side-mm"])
        seed = int(opts["--seed"])
        nverify = int(opts["--verify"])
    except ValueError:
        raise ToolError("--side-mm, --seed and --verify take numbers") from None
    if not 1 <= nverify <= 100:
        raise ToolError("--verify N: N must lie in 1..100")
    if not os.access(host_sim, os.X_OK):
        raise ToolError("%s is not a program (build host_sim first)" % host_sim)
    out = opts["--out"]
    os.makedirs(out, exist_ok=True)
    print("UMBmark on the simulated robot: a %.2f m square, %d runs each way, a tape of +-5 mm"
          % (side_mm / 1000.0, umbmark.RUNS_EACH_WAY))
    try:
        first, cal_text = round_of(host_sim, os.path.join(out, "calibration"), seed, side_mm,
                                   "none", extra,
                                   "1/3 the robot as built, uncalibrated (seed %d):" % seed)
        print("2/3 tools/umbmark.py: E_d = %.6f, E_b = %.6f: cal_left %.6f, cal_right %.6f, "
              "cal_base %.6f" % ((first["e_d"], first["e_b"]) + first["cal"]), flush=True)
        cal_path = os.path.join(out, "calibration.conf")
        umbmark.write_atomic(cal_path, cal_text)
        print("3/3 verification on %d fresh seeds, each uncalibrated and calibrated:" % nverify,
              flush=True)
        gains = []
        for s in range(seed + 1, seed + 1 + nverify):
            d = os.path.join(out, "verify-%d" % s)
            before, _ = round_of(host_sim, os.path.join(d, "before"), s, side_mm, "none", extra,
                                 None)
            after, _ = round_of(host_sim, os.path.join(d, "after"), s, side_mm, cal_path, extra,
                                None)
            gains.append((before["e_max_syst"] / max(after["e_max_syst"], 1e-9), s,
                          before["e_max_syst"], after["e_max_syst"]))
            print("  seed %3d: E_max,syst before %6.1f mm, after %5.1f mm: %6.1fx"
                  % (s, before["e_max_syst"], after["e_max_syst"], gains[-1][0]), flush=True)
    except OSError as e:
        raise ToolError(str(e), FAILED) from None
    worst = min(gains)
    ordered = sorted(g[0] for g in gains)
    median = ordered[len(ordered) // 2] if len(ordered) % 2 else \
        (ordered[len(ordered) // 2 - 1] + ordered[len(ordered) // 2]) / 2.0
    summary = ("E_max,syst over seeds %d-%d: before %.1f-%.1f mm, after %.1f-%.1f mm; "
               "%.1fx smaller at worst (seed %d), %.1fx the median (Borenstein & Feng report "
               "10-22x on real robots)"
               % (seed + 1, seed + nverify, min(g[2] for g in gains), max(g[2] for g in gains),
                  min(g[3] for g in gains), max(g[3] for g in gains), worst[0], worst[1], median))
    print(summary)
    header = ("# The odometry calibration of host_sim's default robot, made by make calibrate\n"
              "# (tools/calibrate_sim.py): UMBmark in the simulator, a tape of +-5 mm.\n"
              "# Verified on fresh runs: %s.\n" % summary)
    try:
        umbmark.write_atomic(opts["--write"], header + cal_text)
    except OSError as e:
        raise ToolError("cannot write %s: %s" % (opts["--write"], e.strerror), FAILED) from None
    print("calibration written to %s" % opts["--write"])
    if worst[0] < TARGET:
        raise ToolError("UMBmark cut E_max,syst only %.1fx on seed %d (expected at least %.0fx)"
                        % (worst[0], worst[1], TARGET), FAILED)
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
