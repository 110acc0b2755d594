#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Measures the core: instructions per robot_tick() and static RAM. Counts, not seconds.

Runs the tick benchmark (tools/bench/bench_tick.c: a scripted ten-minute drive with the
full sonar sweep) under valgrind's callgrind, which dumps the instruction count of every
robot_tick() call; calls into the HAL are excluded, so the figures are the firmware's own.
Then reads the static RAM of the core from `size` of the objects.

usage: tools/bench.py [BUILD_DIR]      (default: build/host, made by `make bench`)
"""
import os
import re
import subprocess
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


if __name__ == "__main__":
    main()
