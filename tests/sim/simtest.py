# SPDX-License-Identifier: MIT
"""Shared helpers of the simulator's integration tests: run host_sim, read its outputs."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import schema


class Sim:
    """host_sim in a scratch folder; argv[1] is the binary, argv[2] the source tree."""

    def __init__(self):
        if len(sys.argv) < 3:
            sys.exit("usage: %s HOST_SIM SOURCE_DIR" % sys.argv[0])
        self.bin = sys.argv[1]
        self.src = sys.argv[2]
        self.work = tempfile.mkdtemp(prefix="slam-simtest-")

    def room(self, name):
        return os.path.join(self.src, "host_sim", "rooms", name)

    def run(self, *args, expect=0):
        """Runs host_sim; fails the test unless it exits with `expect`."""
        cmd = [self.bin, "--no-plot", "--quiet"] + [str(a) for a in args]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != expect:
            fail("%s exited %d, expected %d\n%s%s" % (" ".join(cmd), p.returncode, expect,
                                                      p.stdout, p.stderr))
        if expect == 0 and "--out" in cmd and "--replay" not in cmd:
            self.check_metrics(cmd[cmd.index("--out") + 1])
        return p

    def check_metrics(self, out):
        """Every run's metrics.json must follow host_sim/metrics.schema.json exactly."""
        with open(os.path.join(self.src, "host_sim", "metrics.schema.json")) as f:
            sch = json.load(f)
        errors = schema.validate(self.metrics(out), sch)
        if errors:
            fail("%s/metrics.json does not follow the schema:\n  %s" % (out, "\n  ".join(errors)))

    def out(self, name):
        return os.path.join(self.work, name)

    def metrics(self, out):
        with open(os.path.join(out, "metrics.json")) as f:
            return json.load(f)

    def done(self):
        shutil.rmtree(self.work, ignore_errors=True)


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)
    print("ok: " + msg)


# Where the simulated world is not the reference one, a claim about where given runs go
# (that they touch nothing), measured on the 64-bit builds' runs, is shown, not checked:
# in host-m32, i386's C library computes atan2, log and exp on the x87 unit and rounds
# otherwise, so the same seed drives another path (tests/sim/CMakeLists.txt sets it).
PATHS_VARY = os.environ.get("SLAM_SIM_PATHS_VARY") == "1"


def check_path(cond, msg):
    if PATHS_VARY and not cond:
        print("not checked in this build (SLAM_SIM_PATHS_VARY): " + msg)
        return
    check(cond, msg)


def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs)
