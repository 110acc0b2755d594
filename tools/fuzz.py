#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Runs the libFuzzer targets of tests/fuzz, one after the other (make fuzz).

usage: tools/fuzz.py [--build DIR] [--seconds S | --runs N] [TARGET...]

Each target starts from its seed corpus (tests/fuzz/corpus/TARGET, never written) and
keeps what it finds in DIR/corpus/TARGET; an input that breaks something is saved as
DIR/artifacts/TARGET-crash-... . Prints the executions each target reached.
Exit status: 0 no target failed, 1 a target found a crash (or could not run), 2 bad
options or a target that is not built (make fuzz builds them).
"""
import argparse
import os
import re
import subprocess
import sys
import time

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGETS = ("room", "rosmap", "config", "replay", "telemetry")
# Longest input each target is given: a few hundred lines, a small map with its image.
MAX_LEN = {"room": 8192, "rosmap": 8192, "config": 8192, "replay": 8192, "telemetry": 4096}


def fuzz(build, target, seconds, runs):
    """Runs one target; returns (executions, seconds, ok)."""
    exe = os.path.join(build, "tests", "fuzz", "fuzz_" + target)
    seeds = os.path.join(SRC, "tests", "fuzz", "corpus", target)
    found = os.path.join(build, "corpus", target)
    artifacts = os.path.join(build, "artifacts")
    os.makedirs(found, exist_ok=True)
    os.makedirs(artifacts, exist_ok=True)
    cmd = [exe, "-print_final_stats=1", "-max_len=%d" % MAX_LEN[target],
           "-artifact_prefix=%s/%s-" % (artifacts, target)]
    cmd += ["-runs=%d" % runs] if runs else ["-max_total_time=%d" % seconds]
    d = os.path.join(SRC, "tests", "fuzz", target + ".dict")
    if os.path.exists(d):
        cmd.append("-dict=" + d)
    cmd += [found, seeds]
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       errors="replace")
    wall = time.monotonic() - t0
    m = re.search(r"stat::number_of_executed_units:\s*(\d+)", p.stdout)
    execs = int(m.group(1)) if m else 0
    if p.returncode != 0:
        tail = "\n".join(p.stdout.splitlines()[-30:])
        print("fuzz: %s failed (exit %d):\n%s" % (target, p.returncode, tail), file=sys.stderr)
    return execs, wall, p.returncode == 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--build", default=os.path.join(SRC, "build", "fuzz"))
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--seconds", type=int, default=60, help="time per target (default 60)")
    group.add_argument("--runs", type=int, help="executions per target instead of a time")
    ap.add_argument("targets", nargs="*", metavar="TARGET",
                    help="some of: " + " ".join(TARGETS) + " (default: all)")
    args = ap.parse_args()
    targets = args.targets or list(TARGETS)
    for t in targets:
        if t not in TARGETS:
            ap.error("unknown target '%s' (%s)" % (t, ", ".join(TARGETS)))
        exe = os.path.join(args.build, "tests", "fuzz", "fuzz_" + t)
        if not os.access(exe, os.X_OK):
            print("fuzz: %s not found: build it first (make fuzz)" % exe, file=sys.stderr)
            sys.exit(2)
    if args.seconds <= 0 or (args.runs is not None and args.runs <= 0):
        ap.error("--seconds and --runs need a positive number")
    print("| target | executions | seconds | executions/s |\n|---|---|---|---|")
    failed = []
    for t in targets:
        execs, wall, ok = fuzz(args.build, t, args.seconds, args.runs)
        print("| %s | %d | %.0f | %.0f |%s" % (t, execs, wall, execs / wall if wall else 0,
                                              "" if ok else " FAILED"), flush=True)
        if not ok:
            failed.append(t)
    if failed:
        print("fuzz: a crash in %s: see %s/artifacts/" % (", ".join(failed), args.build),
              file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
