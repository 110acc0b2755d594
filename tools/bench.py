#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Measures the core and the simulator: instructions, RAM, and the simulator's speed.

1. The tick benchmark (tools/bench/bench_tick.c: a scripted ten-minute drive with the full
   sonar sweep) under valgrind's callgrind, which dumps the instruction count of every
   robot_tick() call; calls into the HAL are excluded, so the figures are the firmware's
   own. Then the static RAM of the core from `size` of the objects.
2. The simulator on its default scenario (host_sim, 600 s in the default room): callgrind
   splits the instructions of a control period between the firmware (robot_tick() without
   its HAL calls) and the simulated world (the HAL calls and sim_step()); then three plain
   runs give simulated ticks per wall-clock second (the best of three: the machine may be
   shared, and only interference slows a run down).

usage: tools/bench.py [BUILD_DIR]      (default: build/host, made by `make bench`)
"""
import json
import subprocess
import os
import re
import sys
import tempfile


def die(msg):
    print("bench: " + msg, file=sys.stderr)
    sys.exit(1)


def tick_counts(bench, workdir):
    out = os.path.join(workdir, "callgrind.out")
    cmd = ["valgrind", "--tool=callgrind", "--toggle-collect=robot_tick",
           "--toggle-collect=hal_*", "--dump-after=robot_tick", "--combine-dumps=yes",
           "--callgrind-out-file=" + out, bench]
    print("bench: running %s under callgrind (about 20 s) ..." % os.path.basename(bench),
          file=sys.stderr)
    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        die("valgrind failed:\n" + run.stderr[-2000:])
    counts = []
    with open(out) as f:
        for line in f:
            if line.startswith("totals:"):
                counts.append(int(line.split()[1]))
    # One part per robot_tick() return, and a last one at exit (nothing collected).
    return counts[:-1], run.stdout.strip()


def sizes(paths):
    run = subprocess.run(["size", "-t"] + paths, stdout=subprocess.PIPE, text=True, check=True)
    rows = {}
    for line in run.stdout.splitlines()[1:]:
        f = line.split()
        rows[" ".join(f[5:])] = (int(f[0]), int(f[1]), int(f[2]))
    return rows


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/host"
    if build in ("-h", "--help"):
        print(__doc__.strip())
        return
    bench = os.path.join(build, "tools", "bench", "bench_tick")
    core = os.path.join(build, "firmware", "libslam_core.a")
    robot = os.path.join(build, "tools", "bench", "CMakeFiles", "bench_tick.dir",
                         "robot_instance.c.o")
    for p in (bench, core, robot):
        if not os.path.exists(p):
            die("%s is missing: build the host preset first (make bench)" % p)

    with tempfile.TemporaryDirectory(prefix="slam-bench-") as tmp:
        counts, scenario = tick_counts(bench, tmp)
    if len(counts) != 60000:
        die("expected 60000 ticks, callgrind reported %d" % len(counts))
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

    sim = os.path.join(build, "host_sim", "host_sim")
    if os.path.exists(sim):
        simulator(sim)


# The HAL calls robot_tick() makes; toggling collection off inside them leaves the firmware.
TICK_HAL = ("hal_encoder_count", "hal_sonar_poll", "hal_sonar_trigger", "hal_servo_set_pulse",
            "hal_motor_set")


def collected(sim, tmp, toggles):
    """Instructions callgrind collects inside the toggled functions over a default run."""
    cg = os.path.join(tmp, "sim.callgrind")
    run = subprocess.run(["valgrind", "--tool=callgrind", "--collect-atstart=no",
                          "--callgrind-out-file=" + cg] +
                         ["--toggle-collect=" + t for t in toggles] +
                         [sim, "--quiet", "--no-plot", "--out", os.path.join(tmp, "cg")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        die("host_sim under callgrind failed:\n" + run.stderr[-2000:])
    m = re.search(r"Collected : (\d+)", run.stderr)
    if not m:
        die("callgrind reported no total")
    return int(m.group(1))


def simulator(sim):
    ticks = 60000
    with tempfile.TemporaryDirectory(prefix="slam-bench-") as tmp:
        print("bench: running host_sim under callgrind twice (about 20 s) ...", file=sys.stderr)
        period = collected(sim, tmp, ["hal_host_step"])
        firmware = collected(sim, tmp, ["robot_tick"] + list(TICK_HAL))
        rates = []
        for i in range(3):
            out = os.path.join(tmp, "run%d" % i)
            subprocess.run([sim, "--quiet", "--no-plot", "--out", out], check=True)
            with open(os.path.join(out, "timing.json")) as f:
                rates.append(json.load(f)["ticks_per_s"])
    best = max(rates)
    print("simulator (host_sim, default room, 600 s = %d control ticks)" % ticks)
    print("  instructions per control period: %.0f = firmware %.0f + simulated world %.0f"
          % (period / ticks, firmware / ticks, (period - firmware) / ticks))
    print("  speed: %.0f ticks per wall-clock second = %.0fx real time (best of %s)"
          % (best, best / 100.0, ", ".join("%.0f" % r for r in rates)))


if __name__ == "__main__":
    main()
