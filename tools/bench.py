#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Measures the core and the simulator: instructions, RAM, and the simulator's speed.

1. The tick benchmark (tools/bench/bench_tick.c: a scripted ten-minute drive with the full
   sonar sweep) under valgrind's callgrind, which dumps the instruction count of every
   robot_tick() call; calls into the HAL are excluded, so the figures are the firmware's
   own. Then the static RAM of the core from `size` of the objects.
2. The simulator on its default scenario (host_sim, 600 s in the default room): callgrind
   counts every instruction of the run, start-up and end included, and splits them per
   control period between the firmware's tick (robot_tick() without its HAL calls), its
   background loop (robot_idle()), the simulated world (sim_step() and the tick's HAL
   calls), host_sim's own measuring and logs, and the end of the run (finish(): scores,
   maps, metrics.json). Budgets: 6 000 instructions a control period, the end of the run
   at most 10 % of them. Then three plain runs give simulated ticks per wall-clock second
   (the best of three: the machine may be shared, and only interference slows a run down).
   Exit status 1 when the simulator is over a budget or a measurement fails, 2 for a wrong
   command line or a build that lacks a program.

usage: tools/bench.py [BUILD_DIR] [--sim-only | --core-only] [--json FILE]
       (BUILD_DIR: build/host by default, made by `make bench`; --sim-only: the simulator's
       part alone; --core-only: the tick benchmark and the sizes alone; FILE receives every
       figure printed, for tools/docs.py's tables, the wall-clock speed apart under "wall")
"""
import json
import subprocess
import os
import re
import sys
import tempfile

from slamtools.commands import take_value
from slamtools.errors import FAILED, ToolError, main as tool_main


def run_program(cmd, **kw):
    """subprocess.run(cmd), a program that is not installed a ToolError (valgrind comes with
    tools/install-deps.sh firmware)."""
    try:
        return subprocess.run(cmd, **kw)
    except OSError as e:
        raise ToolError("cannot run %s: %s (tools/install-deps.sh firmware)"
                        % (cmd[0], e.strerror), FAILED) from None


def tick_counts(bench, workdir):
    out = os.path.join(workdir, "callgrind.out")
    cmd = ["valgrind", "--tool=callgrind", "--toggle-collect=robot_tick",
           "--toggle-collect=hal_*", "--dump-after=robot_tick", "--combine-dumps=yes",
           "--callgrind-out-file=" + out, bench]
    print("bench: running %s under callgrind (about 20 s) ..." % os.path.basename(bench),
          file=sys.stderr)
    run = run_program(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        raise ToolError("valgrind failed:\n" + run.stderr[-2000:], FAILED)
    counts = []
    with open(out) as f:
        for line in f:
            if line.startswith("totals:"):
                counts.append(int(line.split()[1]))
    # One part per robot_tick() return, and a last one at exit (nothing collected).
    return counts[:-1], run.stdout.strip()


def sizes(paths):
    run = run_program(["size", "-t"] + paths, stdout=subprocess.PIPE, text=True)
    if run.returncode != 0:
        raise ToolError("size -t %s failed" % " ".join(paths), FAILED)
    rows = {}
    for line in run.stdout.splitlines()[1:]:
        f = line.split()
        rows[" ".join(f[5:])] = (int(f[0]), int(f[1]), int(f[2]))
    return rows


def write_json(path, figures):
    if path is None:
        return
    try:
        with open(path, "w") as f:
            json.dump(figures, f, indent=1)
    except OSError as e:
        raise ToolError("cannot write %s: %s" % (path, e.strerror), FAILED) from None


def main(argv):
    args = list(argv)
    out_json = take_value(args, "--json", "a file")
    sim_only = "--sim-only" in args
    core_only = "--core-only" in args
    args = [a for a in args if a not in ("--sim-only", "--core-only")]
    build = args[0] if args else "build/host"
    if build in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(args) > 1 or build.startswith("-"):
        raise ToolError("unknown argument %r (--help)" % args[-1])
    if sim_only and core_only:
        raise ToolError("--sim-only and --core-only exclude each other")
    sim = os.path.join(build, "host_sim", "host_sim")
    figures = {}
    if sim_only:
        if not os.path.exists(sim):
            raise ToolError("%s is missing: build the host preset first (make bench)" % sim)
        ok = simulator(sim, figures)
        write_json(out_json, figures)
        if not ok:
            raise ToolError("the simulator is over its budget", FAILED)
        return 0
    bench = os.path.join(build, "tools", "bench", "bench_tick")
    core = os.path.join(build, "firmware", "libslam_core.a")
    robot = os.path.join(build, "tools", "bench", "CMakeFiles", "bench_tick.dir",
                         "robot_instance.c.o")
    for p in (bench, core, robot):
        if not os.path.exists(p):
            raise ToolError("%s is missing: build the host preset first (make bench)" % p)

    with tempfile.TemporaryDirectory(prefix="slam-bench-") as tmp:
        counts, scenario = tick_counts(bench, tmp)
    if len(counts) != 60000:
        raise ToolError("expected 60000 ticks, callgrind reported %d" % len(counts), FAILED)
    worst = max(counts)
    mean = sum(counts) / len(counts)
    grid = re.search(r"grid (\d+)x(\d+)", scenario)

    rows = sizes([core, robot])
    core_text = sum(v[0] for k, v in rows.items() if "libslam_core.a" in k)
    core_data = sum(v[1] + v[2] for k, v in rows.items() if "libslam_core.a" in k)
    robot_ram = sum(v[1] + v[2] for k, v in rows.items() if "robot_instance" in k)

    print("sonarslam core benchmark (%s, %s)" % (build, os.uname().machine))
    print("  scenario: %s" % scenario)
    print("  robot_tick(), firmware only (HAL calls excluded), %d ticks = 10 min:" % len(counts))
    print("    instructions per tick: mean %.0f, worst %d (tick %d), best %d"
          % (mean, worst, counts.index(worst), min(counts)))
    if grid:
        a, b = int(grid.group(1)), int(grid.group(2))
        print("  static RAM of the core for A x B = %d x %d cells:" % (a, b))
        print("    robot_t %d B = OM + TM %d B + state %d B; module statics %d B"
              % (robot_ram, 2 * a * b, robot_ram - 2 * a * b, core_data))
    print("  code of the core (host build): %d B" % core_text)
    figures["core"] = {"ticks": len(counts), "mean": mean, "worst": worst,
                       "worst_tick": counts.index(worst), "best": min(counts),
                       "core_text": core_text, "core_data": core_data, "robot_t": robot_ram}
    if grid:
        figures["core"].update(grid_a=a, grid_b=b, om_tm=2 * a * b)

    ok = core_only or not os.path.exists(sim) or simulator(sim, figures)
    write_json(out_json, figures)
    if not ok:
        raise ToolError("the simulator is over its budget", FAILED)
    return 0


# The HAL calls robot_tick() makes; toggling collection off inside them leaves the firmware.
TICK_HAL = ("hal_encoder_count", "hal_sonar_poll", "hal_sonar_trigger", "hal_servo_set_pulse",
            "hal_motor_set")

SIM_TICKS = 60000        # the default run: 600 s of 10 ms control periods
SIM_BUDGET = 6000        # instructions per control period, the end of the run included
SIM_END_SHARE = 0.10     # the end of the run's share of it (no --sweep)


def callgrind(sim, tmp, opts):
    """host_sim's default run under callgrind: (instructions collected, the profile)."""
    cg = os.path.join(tmp, "sim.callgrind")
    run = run_program(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + cg] + opts +
                         [sim, "--quiet", "--no-plot", "--out", os.path.join(tmp, "cg")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        raise ToolError("host_sim under callgrind failed:\n" + run.stderr[-2000:], FAILED)
    m = re.search(r"Collected : (\d+)", run.stderr)
    if not m:
        raise ToolError("callgrind reported no total", FAILED)
    return int(m.group(1)), cg


def inclusive(profile, names):
    """Each named function's instructions, callees included (callgrind_annotate)."""
    run = run_program(["callgrind_annotate", "--inclusive=yes", "--threshold=100", profile],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        raise ToolError("callgrind_annotate failed:\n" + run.stderr[-2000:], FAILED)
    got = {}
    for line in run.stdout.splitlines():
        # "N (P%)  FILE:FUNCTION [OBJECT]", FUNCTION maybe a clone (finish.constprop.0); a
        # function's lines from inlined headers come under their own FILE, so the largest
        # figure of a name is the whole function's.
        m = re.match(r"\s*([\d,]+) .*:(\w+)(?:\.[\w.]+)?(?: \[.*\])?$", line)
        if m and m.group(2) in names:
            got[m.group(2)] = max(got.get(m.group(2), 0), int(m.group(1).replace(",", "")))
    missing = [n for n in names if n not in got]
    if missing:
        raise ToolError("no instructions for %s in the profile" % ", ".join(missing), FAILED)
    return got


def simulator(sim, figures):
    """Instructions per simulated control period of the default run, end of run included,
    by part; then the wall-clock speed. False when over a budget. The figures go into
    figures["sim"], the speed into figures["wall"] (it follows the machine's load)."""
    ticks = SIM_TICKS
    with tempfile.TemporaryDirectory(prefix="slam-bench-") as tmp:
        print("bench: running host_sim under callgrind twice (about 30 s) ...", file=sys.stderr)
        total, profile = callgrind(sim, tmp, [])
        part = inclusive(profile, ("robot_idle", "hal_host_step", "observe_tick", "finish"))
        tick, _ = callgrind(sim, tmp, ["--collect-atstart=no", "--toggle-collect=robot_tick"] +
                            ["--toggle-collect=" + t for t in TICK_HAL])
        rates = []
        for i in range(3):
            out = os.path.join(tmp, "run%d" % i)
            if subprocess.run([sim, "--quiet", "--no-plot", "--out", out]).returncode != 0:
                raise ToolError("%s --out %s failed" % (sim, out), FAILED)
            with open(os.path.join(out, "timing.json")) as f:
                rates.append(json.load(f)["ticks_per_s"])
    rows = (
        ("firmware: robot_tick() without its HAL calls", tick),
        ("firmware: robot_idle(), the background loop", part["robot_idle"]),
        ("simulated world: sim_step() and the tick's HAL calls", part["hal_host_step"] - tick),
        ("host_sim measuring and logging every period", part["observe_tick"]),
        ("end of the run: scores, maps, metrics.json", part["finish"]),
    )
    rest = total - sum(v for _, v in rows)
    per = total / ticks
    end_share = part["finish"] / total
    best = max(rates)
    print("simulator (host_sim, default room, 600 s = %d control periods; callgrind)" % ticks)
    print("  instructions per control period: %.0f, the end of the run included "
          "(%.1f M in all)" % (per, total / 1e6))
    for name, v in rows + (("start-up and the rest", rest),):
        print("    %-55s %6.0f" % (name, v / ticks))
    print("  end of the run: %.1f M instructions, %.1f %% of the run" % (part["finish"] / 1e6,
                                                                     100.0 * end_share))
    print("  speed: %.0f ticks per wall-clock second = %.0fx real time (best of %s)"
          % (best, best / 100.0, ", ".join("%.0f" % r for r in rates)))
    print("  budgets:")
    ok_per = per <= SIM_BUDGET
    ok_end = end_share <= SIM_END_SHARE
    print("  instructions per control period      %6.0f  budget %6d  %s"
          % (per, SIM_BUDGET, "ok" if ok_per else "OVER"))
    print("  end of the run, share of the run     %5.1f %%  budget %4.0f %%  %s"
          % (100.0 * end_share, 100.0 * SIM_END_SHARE, "ok" if ok_end else "OVER"))
    figures["sim"] = {"ticks": ticks, "total": total, "per_period": per,
                      "parts": [[name, v / ticks] for name, v in rows + (
                          ("start-up and the rest", rest),)],
                      "idle": part["robot_idle"] / ticks, "end": part["finish"],
                      "end_share": end_share, "budget": SIM_BUDGET,
                      "end_budget": SIM_END_SHARE}
    figures["wall"] = {"ticks_per_s": rates}
    return ok_per and ok_end


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
