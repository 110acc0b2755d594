#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The pose correction measured: maps and pose error with it on and off, every shipped room.

usage: tools/pose_report.py [--host-sim BIN] [--seeds N] [--out DIR] [--jobs N]
                            [--quick] [--no-long] [--long-seeds N] [--long-durations S,S]
                            [--host-arg ARG]...
                            [--perfect-odometry] [--figure PNG] [--keep]

Runs host_sim in every shipped room (host_sim/rooms/*.room) for seeds 1..N, 10 simulated
minutes each, once with the pose correction (the default, `localize = 1`) and once
without it (`localize = 0`: the paper's odometry alone), then 1-hour and 10-hour runs
(--long-durations) of the default room both ways, seeds 1..12 (--long-seeds): where a ten-hour run ends turns
on small differences early on, so the table gives medians and how many runs met the goal.
Prints Markdown tables (the ones in the README): mean raw and final F1 of OM built from
the firmware's own pose and from the true poses, the gap between them, median and worst
final heading and position error, the correction's counters, and per room the mean
difference on − off over the seeds with its standard error. With --figure, also draws the
1-hour maps side by side and the heading error over time
(host_sim/figures/pose_correction.png in the README). With --perfect-odometry every run's
odometry is exact (no E_d, E_b, wheel noise or slip, no calibration file): what gap is
left is the matcher's own. Each run keeps its metrics.json and small files in DIR/NAME
(default out/pose_report); its logs and maps are deleted once read, unless --keep (with
--figure, the one-hour runs it draws keep theirs).
Exit status: 0 done, 1 a run failed, 2 bad options.
"""
import argparse
import csv
import glob
import json
import math
import os
import statistics
import sys

from slamtools import pgm
from slamtools.errors import ToolError, main as tool_main
from slamtools.runs import ROOMS, SRC, add_host_arg, cores, mean, median, run_all

MODES = (("off", "0"), ("on", "1"))
LONG = (3600, 36000)  # s: the 1-hour and 10-hour runs (--long-durations)
LONG_SEEDS = 12  # a ten-hour run's outcome turns on small differences: one seed says little
# Odometry without an error of any kind, systematic or not (--perfect-odometry).
PERFECT_ODOMETRY = ["--error", "ed=1", "--error", "eb=1", "--error", "noise=0",
                    "--error", "slip=0", "--calibration", "none"]


def rooms():
    return sorted(os.path.splitext(os.path.basename(p))[0]
                  for p in glob.glob(os.path.join(ROOMS, "*.room")))


def jobs_for(args):
    dur = 120 if args.quick else 600
    extra = args.host_arg + (PERFECT_ODOMETRY if args.perfect_odometry else [])
    jobs = {}
    for room in rooms():
        for s in range(1, args.seeds + 1):
            for mode, val in MODES:
                jobs["%s-%s-%d" % (room, mode, s)] = [
                    "--room", os.path.join(ROOMS, room + ".room"), "--seed", s,
                    "--duration", dur, "--set", "localize=" + val] + extra
    for dur_l in () if args.no_long else args.long_durations if not args.quick else (600,):
        for s in range(1, args.long_seeds + 1):
            for mode, val in MODES:
                jobs["long%d-%s-%d" % (dur_l, mode, s)] = [
                    "--seed", s, "--duration", dur_l, "--set", "localize=" + val] + extra
    return jobs, dur


def summary(ms):
    """The table's figures over a list of runs' metrics."""
    def f1(which, step):
        return mean(m["maps"][which][step]["f1"] for m in ms)
    est_raw, true_raw = f1("odometry", "raw"), f1("perfect_odometry", "raw")
    head = [m["odometry"]["final_heading_deg"] for m in ms]
    pos = [m["odometry"]["final_position_m"] for m in ms]
    loc = [m["localization"] for m in ms]
    return {"est_raw": est_raw, "est_final": f1("odometry", "insert"),
            "true_raw": true_raw, "true_final": f1("perfect_odometry", "insert"),
            "gap": true_raw - est_raw,
            "head_med": median(head), "head_max": max(head),
            "pos_med": median(pos), "pos_max": max(pos),
            "tried": mean(x["tried"] for x in loc), "applied": mean(x["applied"] for x in loc),
            "refused": mean(x["refused"] for x in loc), "n": len(ms)}


def gap_spread(ms):
    """The gap (raw F1 from the true poses less from the own pose) of each run: its σ per
    run and the standard error of its mean over the runs."""
    g = [m["maps"]["perfect_odometry"]["raw"]["f1"] - m["maps"]["odometry"]["raw"]["f1"]
         for m in ms]
    if len(g) < 2:
        return float("nan"), float("nan")
    sd = statistics.stdev(g)
    return sd, sd / math.sqrt(len(g))


def paired_difference(on, off):
    """Mean of the per-seed differences of raw F1 (own pose), on minus off, and its standard
    error: the runs of one seed share the room and the start, so they are paired. Within about
    two standard errors of zero, the seeds cannot tell the two apart."""
    by_seed = {m["scenario"]["seed"]: m["maps"]["odometry"]["raw"]["f1"] for m in off}
    d = [m["maps"]["odometry"]["raw"]["f1"] - by_seed[m["scenario"]["seed"]]
         for m in on if m["scenario"]["seed"] in by_seed]
    if len(d) < 2:
        return (d[0] if d else float("nan")), float("nan")
    return statistics.mean(d), statistics.stdev(d) / math.sqrt(len(d))


ROW = "| %s | %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f | %.1f | %.3f | %.3f |"
HEAD = ("| room | correction | F1 raw (own pose) | F1 final (own pose) | F1 raw (true poses) "
        "| F1 final (true poses) | gap | heading median (°) | heading worst (°) "
        "| position median (m) | position worst (m) |\n|---|---|---|---|---|---|---|---|---|---|---|")


def row(label, mode, s):
    return ROW % (label, mode, s["est_raw"], s["est_final"], s["true_raw"], s["true_final"],
                  s["gap"], s["head_med"], s["head_max"], s["pos_med"], s["pos_max"])


def report(args):
    jobs, dur = jobs_for(args)
    base = args.out
    total = len(jobs)
    print("pose_report: %d runs of host_sim into %s" % (total, base), file=sys.stderr)
    # A figure draws the first seed's one-hour runs: their maps and trajectories stay.
    first_long = "long%d-" % (600 if args.quick else args.long_durations[0])
    res = run_all(args.host_sim, base, jobs, args.jobs, "pose_report",
                  keep=lambda n: args.keep or bool(args.figure) and n.startswith(first_long)
                  and n.endswith("-1"))

    def group(prefix):
        return [res[n] for n in sorted(res) if n.rsplit("-", 1)[0] == prefix]

    print("### Pose correction on and off (%d seeds, %d s each%s)\n"
          % (args.seeds, dur, ", odometry perfect" if args.perfect_odometry else ""))
    print(HEAD)
    alls = {}
    for room in rooms():
        for mode, _ in MODES:
            s = summary(group("%s-%s" % (room, mode)))
            print(row(room, mode, s))
    for mode, _ in MODES:
        ms = [m for room in rooms() for m in group("%s-%s" % (room, mode))]
        alls[mode] = summary(ms)
        print(row("**all %d rooms**" % len(rooms()), mode, alls[mode]))
    sd, se = gap_spread([m for room in rooms() for m in group(room + "-on")])
    print("\nThe gap with the correction, every room: σ %.3f per run, standard error %.3f over "
          "the runs.\n" % (sd, se))

    print("### Long runs (default room, seeds 1–%d)\n" % args.long_seeds)
    print("| run | correction | F1 raw (own pose) median | heading error median (°) "
          "| runs with F1 >= 0.75 | runs with heading <= 5° | runs that touch "
          "| F1 raw per seed | heading per seed (°) |\n|---|---|---|---|---|---|---|---|---|")
    longs = sorted({n.split("-")[0] for n in res if n.startswith("long")},
                   key=lambda x: int(x[4:]))
    for name in longs:
        for mode, _ in MODES:
            ms = sorted(group("%s-%s" % (name, mode)), key=lambda m: m["scenario"]["seed"])
            f1 = [m["maps"]["odometry"]["raw"]["f1"] for m in ms]
            head = [abs(m["odometry"]["final_heading_deg"]) for m in ms]
            secs = int(name[4:])
            touch = sum(m["robot"]["collisions"] > 0 for m in ms)
            print("| %s | %s | %.3f | %.1f | %d of %d | %d of %d | %d of %d | %s | %s |" % (
                "%g h" % (secs / 3600.0) if secs >= 3600 else "%g min" % (secs / 60.0),
                mode, median(f1), median(head),
                sum(f >= 0.75 for f in f1), len(ms), sum(h <= 5.0 for h in head), len(ms),
                touch, len(ms),
                " / ".join("%.2f" % f for f in f1), " / ".join("%.1f" % h for h in head)))
    print()

    on = alls["on"]
    print("### The correction's work (mean per %d s run, every room)\n" % dur)
    print("| matches tried | applied | refused |\n|---|---|---|")
    print("| %.0f | %.0f | %.0f |\n" % (on["tried"], on["applied"], on["refused"]))

    print("### What the correction changes, room by room\n")
    print("| room | raw F1 (own pose), on − off | standard error |\n|---|---|---|")
    worse = []
    for room in rooms():
        diff, se = paired_difference(group(room + "-on"), group(room + "-off"))
        print("| %s | %+.3f | %.3f |" % (room, diff, se))
        if diff < 0:  # every seed runs both ways: the mean difference is the means' difference
            worse.append(room)
    print()
    print("Rooms whose mean raw F1 (own pose) is lower with the correction than without: %s\n"
          % (", ".join(worse) if worse else "none"))
    if args.figure:
        if not longs:
            raise ToolError("--figure draws the long runs: leave out --no-long")
        figure(args, base, longs[0])


def heading_series(folder):
    t, e = [], []
    with open(os.path.join(folder, "trajectory.csv")) as f:
        for r in csv.DictReader(f):
            d = float(r["odom_th_rad"]) - float(r["true_th_rad"])
            d = math.atan2(math.sin(d), math.cos(d))
            t.append(float(r["t_s"]) / 60.0)
            e.append(abs(math.degrees(d)))
    return t, e


def room_window(metrics_path, margin_m=0.5):
    """The rows and columns of the exported grid that hold the room and a margin."""
    with open(metrics_path) as f:
        sc = json.load(f)["scenario"]
    x0, y0, x1, y1 = sc["room_bounds"]
    ox, oy = sc["grid"]["origin"]
    cell, h = sc["cell_mm"] / 1000.0, sc["grid"]["b"]

    def col(x):
        return min(max(int((x - ox) / cell), 0), sc["grid"]["a"])

    def row_(y):
        return min(max(h - int((y - oy) / cell), 0), h)
    return (slice(row_(y1 + margin_m), row_(y0 - margin_m)),
            slice(col(x0 - margin_m), col(x1 + margin_m)))


def figure(args, base, name):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ToolError("%s (tools/install-deps.sh sim)" % e, 1)
    fig, axes = plt.subplots(1, 4, figsize=(19, 4.6))
    folders = {mode: os.path.join(base, "%s-%s-1" % (name, mode)) for mode, _ in MODES}
    panels = ((folders["off"], "om.pgm", "without correction (odometry alone)"),
              (folders["on"], "om.pgm", "with the pose correction"),
              (folders["on"], "truth.pgm", "the room (truth)"))
    crop = room_window(os.path.join(folders["on"], "metrics.json"))
    for ax, (folder, image, title) in zip(axes[:3], panels):
        ax.imshow(pgm.read(os.path.join(folder, image))[crop], cmap="gray", vmin=0, vmax=255)
        ax.set_title("%s, %s" % (title, "%g min" % (int(name[4:]) / 60.0)), fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
    ax = axes[3]
    for mode, color in (("off", "tab:red"), ("on", "tab:green")):
        t, e = heading_series(folders[mode])
        ax.plot(t, e, color=color, lw=0.8, label="correction " + mode)
    ax.set_xlabel("time [min]")
    ax.set_ylabel("heading error [°]")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_title("heading error, default room, seed 1")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.figure, dpi=72, metadata={"Software": None})
    print("(figure: %s)" % args.figure, file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--host-sim", default=os.path.join(SRC, "build", "host", "host_sim", "host_sim"))
    ap.add_argument("--seeds", type=int, default=10, help="seeds 1..N per room (default 10)")
    ap.add_argument("--out", default=os.path.join(SRC, "out", "pose_report"))
    ap.add_argument("--jobs", type=int, default=cores(),
                    help="runs at a time (default: every core, %d)" % cores())
    ap.add_argument("--quick", action="store_true",
                    help="2-minute runs and no long runs, for a first look")
    ap.add_argument("--no-long", action="store_true", help="leave out the 1-hour and 10-hour runs")
    ap.add_argument("--long-seeds", type=int, default=LONG_SEEDS, metavar="N",
                    help="seeds 1..N of the 1-hour and 10-hour runs (default %d)" % LONG_SEEDS)
    ap.add_argument("--long-durations", default=",".join(str(s) for s in LONG), metavar="S,S",
                    help="the long runs' durations in s, the figure's first (default %s)"
                    % ",".join(str(s) for s in LONG))
    add_host_arg(ap, "--host-arg=--error --host-arg=eb=1.0")
    ap.add_argument("--perfect-odometry", action="store_true",
                    help="odometry without any error in every run: the gap that is left is "
                    "the matcher's own")
    ap.add_argument("--figure", help="also draw the 1-hour maps and heading error into this PNG")
    ap.add_argument("--keep", action="store_true",
                    help="keep every run's logs and maps (by default each keeps its "
                         "metrics.json and small files only)")
    args = ap.parse_args()
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs need at least 1")
    given = args.long_durations
    try:
        args.long_durations = tuple(int(s) for s in given.split(","))
    except ValueError:
        args.long_durations = ()
    if not args.long_durations or min(args.long_durations) < 1:
        ap.error("--long-durations: %r is not whole seconds, comma-separated" % given)
    if not os.path.exists(args.host_sim):
        raise ToolError("%s not found: build it first (make sim)" % args.host_sim)
    report(args)


if __name__ == "__main__":
    tool_main(main)
