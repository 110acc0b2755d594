#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Runs the libFuzzer targets of tests/fuzz, one after the other, then the Python link's
property-based tests (make fuzz).

usage: tools/fuzz.py [--build DIR] [--seconds S | --runs N] [--examples E] [TARGET...]

Each C target starts from its seed corpus (tests/fuzz/corpus/TARGET, never written) and
keeps what it finds in DIR/corpus/TARGET; an input that breaks something is saved as
DIR/artifacts/TARGET-crash-... . libFuzzer's output goes to DIR/logs/TARGET.log as it
runs, so a long run's progress can be watched there. Prints the executions each target
reached; a run stopped by SIGINT or SIGTERM to its libFuzzer process is reported as
interrupted with the executions it had made. The target `slamlink` is
tests/fuzz/fuzz_slamlink.py (python3-hypothesis): E generated cases for each of its
properties (default 100 000), a row each.
Exit status: 0 no target failed, 1 a target found a crash (or could not run), 2 bad
options or a target that is not built (make fuzz builds them).
"""
import argparse
import os
import re
import subprocess
import sys
import time

from slamtools.errors import FAILED, ToolError, main as tool_main

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGETS = ("room", "rosmap", "config", "replay", "telemetry", "slamlink")
PY_TARGETS = ("slamlink",)  # tests/fuzz/fuzz_<name>.py, property-based (hypothesis)
# Longest input each target is given: a few hundred lines, a small map with its image.
# Telemetry's parser starts afresh at every frame (at most TELEM_FRAME_MAX, 261 bytes) and
# its round trip reads at most seven events (about 200 bytes): 1 KiB holds several of the
# largest frames or some ninety SETs, and each execution costs a quarter of 4 KiB's.
MAX_LEN = {"room": 8192, "rosmap": 8192, "config": 8192, "replay": 8192, "telemetry": 1024}


def fuzz(build, target, seconds, runs):
    """Runs one target; returns (executions, seconds, outcome): "ok", "interrupted" or
    "failed"."""
    exe = os.path.join(build, "tests", "fuzz", "fuzz_" + target)
    seeds = os.path.join(SRC, "tests", "fuzz", "corpus", target)
    found = os.path.join(build, "corpus", target)
    artifacts = os.path.join(build, "artifacts")
    os.makedirs(found, exist_ok=True)
    logs = os.path.join(build, "logs")
    for d in (found, artifacts, logs):
        os.makedirs(d, exist_ok=True)
    cmd = [exe, "-print_final_stats=1", "-max_len=%d" % MAX_LEN[target],
           "-artifact_prefix=%s/%s-" % (artifacts, target)]
    cmd += ["-runs=%d" % runs] if runs else ["-max_total_time=%d" % seconds]
    d = os.path.join(SRC, "tests", "fuzz", target + ".dict")
    if os.path.exists(d):
        cmd.append("-dict=" + d)
    cmd += [found, seeds]
    log = os.path.join(logs, target + ".log")
    t0 = time.monotonic()
    with open(log, "w") as out:
        rc = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode
    wall = time.monotonic() - t0
    with open(log, errors="replace") as f:
        text = f.read()
    m = re.search(r"stat::number_of_executed_units:\s*(\d+)", text)
    execs = int(m.group(1)) if m else 0
    if rc != 0 and "libFuzzer: run interrupted" in text:
        return execs, wall, "interrupted"
    if rc != 0:
        tail = "\n".join(text.splitlines()[-30:])
        print("fuzz: %s failed (exit %d), see %s:\n%s" % (target, rc, log, tail), file=sys.stderr)
    return execs, wall, "ok" if rc == 0 else "failed"


def fuzz_python(build, target, examples):
    """Runs a Python target; returns its table rows and whether every property held."""
    script = os.path.join(SRC, "tests", "fuzz", "fuzz_%s.py" % target)
    logs = os.path.join(build, "logs")
    os.makedirs(logs, exist_ok=True)
    with open(os.path.join(logs, target + ".log"), "w") as out:
        rc = subprocess.run(["/usr/bin/python3", script, "--examples", str(examples)],
                            stdout=subprocess.PIPE, stderr=out, text=True)
    rows = [line for line in rc.stdout.splitlines() if line.startswith("|")]
    if rc.returncode != 0:
        print("fuzz: %s failed (exit %d), see %s" % (target, rc.returncode,
                                                     os.path.join(logs, target + ".log")),
              file=sys.stderr)
    return rows, rc.returncode == 0


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--build", default=os.path.join(SRC, "build", "fuzz"))
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--seconds", type=int, default=60, help="time per target (default 60)")
    group.add_argument("--runs", type=int, help="executions per target instead of a time")
    ap.add_argument("--examples", type=int, default=100000,
                    help="cases per property of a Python target (default 100000)")
    ap.add_argument("targets", nargs="*", metavar="TARGET",
                    help="some of: " + " ".join(TARGETS) + " (default: all)")
    args = ap.parse_args(argv)
    targets = args.targets or list(TARGETS)
    for t in targets:
        if t not in TARGETS:
            ap.error("unknown target '%s' (%s)" % (t, ", ".join(TARGETS)))
        exe = os.path.join(args.build, "tests", "fuzz", "fuzz_" + t)
        if t not in PY_TARGETS and not os.access(exe, os.X_OK):
            raise ToolError("%s not found: build it first (make fuzz)" % exe)
    if args.seconds <= 0 or (args.runs is not None and args.runs <= 0):
        ap.error("--seconds and --runs need a positive number")
    if args.examples <= 0:
        ap.error("--examples needs a positive number")
    print("| target | executions | seconds | executions/s |\n|---|---|---|---|")
    failed = []
    for t in targets:
        if t in PY_TARGETS:
            print("| %s (property, cases, seconds, outcome) |" % t, flush=True)
            rows, ok = fuzz_python(args.build, t, args.examples)
            for row in rows:
                print(row, flush=True)
            if not ok:
                failed.append(t)
            continue
        execs, wall, outcome = fuzz(args.build, t, args.seconds, args.runs)
        print("| %s | %d | %.0f | %.0f |%s" % (t, execs, wall, execs / wall if wall else 0,
                                              {"ok": "", "interrupted": " interrupted",
                                               "failed": " FAILED"}[outcome]), flush=True)
        if outcome == "failed":
            failed.append(t)
    if failed:
        raise ToolError("a crash in %s: see %s/artifacts/" % (", ".join(failed), args.build),
                        FAILED)
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
