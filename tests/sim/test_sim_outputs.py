#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim's output paths: every one is checked before anything is written, a bad one is
refused with exit 2 and leaves what was there as it was, and a write that fails while the
robot runs is an error (exit 1) that also leaves the earlier results whole.

In the sanitizer build every one of these runs is also a leak check: LeakSanitizer turns
a leak on any of these paths into another exit status.
"""
import hashlib
import os
import subprocess

from simtest import Sim, check

sim = Sim()


def snapshot(d):
    """Every file of a folder with its contents' digest."""
    out = {}
    for name in sorted(os.listdir(d)):
        with open(os.path.join(d, name), "rb") as f:
            out[name] = hashlib.sha256(f.read()).hexdigest()
    return out


run = sim.out("run")
sim.run("--duration", 20, "--out", run)
before = snapshot(run)
check(len(before) >= 14 and "readings.csv" in before, "a first run wrote its %d files" % len(before))

# B1: a bad output path is refused before anything is truncated.
missing = os.path.join(sim.work, "nope", "deeper")
os.mkdir(sim.out("adir"))
with open(sim.out("afile"), "w") as f:
    f.write("x")
for args, says in [
    (["--telemetry", "/proc/nope/x"], "--telemetry /proc/nope/x"),
    (["--trace", "/proc/nope/x"], "--trace /proc/nope/x"),
    (["--telemetry", sim.out("adir")], "is a directory"),
    (["--trace", os.path.join(sim.out("afile"), "x")], "is not a directory"),
    (["--trace", os.path.join(run, "readings.csv")], "a file the run writes into --out"),
    (["--trace", sim.out("same"), "--telemetry", sim.out("same")], "name the same file"),
]:
    p = sim.run("--duration", 20, "--out", run, *args, expect=2)
    check(says in p.stderr and snapshot(run) == before and not os.path.exists(sim.out("same")),
          "%s: exit 2, says '%s', %s untouched" % (" ".join(args), says, os.path.basename(run)))

# Folders where nothing can be created, even by root (to whom access() says yes).
for where in ("/proc/sonarslam-out", "/sys/sonarslam-out", "/proc"):
    p = sim.run("--duration", 20, "--out", where, expect=2)
    check("cannot create files in" in p.stderr and not os.path.exists(where + "/om.pgm"),
          "--out %s: exit 2 before anything is written: %s" % (where, p.stderr.strip()))

p = sim.run("--duration", 20, "--out", sim.out("afile"), expect=2)
check("exists and is not a directory" in p.stderr, "--out naming a file: exit 2")
p = sim.run("--duration", 20, "--out", os.path.join(sim.out("afile"), "sub"), expect=2)
check("is not a directory" in p.stderr, "--out below a file: exit 2")
os.mkdir(sim.out("blocked"))
os.mkdir(os.path.join(sim.out("blocked"), "om.pgm"))
p = sim.run("--duration", 20, "--out", sim.out("blocked"), expect=2)
check("om.pgm is there and is not a regular file" in p.stderr, "a folder where a map goes: exit 2")

# B2: a write that fails while the robot runs is an error, and the earlier results stay.
for opt in ("--telemetry", "--trace"):
    p = sim.run("--duration", 20, "--out", run, opt, "/dev/full", expect=1)
    check("writing /dev/full failed" in p.stderr and snapshot(run) == before,
          "%s /dev/full: exit 1, says so, the earlier results untouched" % opt)
    leftovers = [n for n in os.listdir(run) if n.startswith(".")]
    check(not leftovers, "no temporary files left behind (%s)" % leftovers)
fresh = os.path.join(missing, "run")
p = sim.run("--duration", 20, "--out", fresh, "--telemetry", "/dev/full", expect=1)
check(not os.path.exists(os.path.join(sim.work, "nope")),
      "a failed run removes the folders it created")

# A good run replaces the results whole; a device is written in place.
trace = sim.out("t.trace")
p = sim.run("--duration", 20, "--seed", 2, "--out", run, "--trace", trace, "--telemetry", "/dev/null")
after = snapshot(run)
check(after.keys() == before.keys() and after["readings.csv"] != before["readings.csv"],
      "a good run replaces every file")
with open(trace) as f:
    lines = f.read().splitlines()
check(lines[-1].startswith("end "), "the trace is complete (%d lines)" % len(lines))

# A run that will write more than 100 MB says so before it starts; a short one says nothing.
proc = subprocess.Popen([sim.bin, "--no-plot", "--quiet", "--duration", "100000", "--out",
                         sim.out("long"), "--telemetry", sim.out("long.tel")],
                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
first = proc.stderr.readline()
proc.kill()
proc.wait()
check("100000 simulated seconds will write about 772 MB (readings.csv 140 MB, trajectory.csv "
      "72 MB, --telemetry 560 MB)" in first, "a long run announces its size: %s" % first.strip())
p = sim.run("--duration", 5, "--out", sim.out("short"))
check("will write" not in p.stderr, "a short run says nothing of its size")

# Files renamed into place keep the mode a new file gets under the umask (another user of
# a shared folder reads them), whatever the temporary name was made with.
umask_run = sim.out("umask")
old_mask = os.umask(0o002)
try:
    sim.run("--duration", 5, "--out", umask_run, "--storage", sim.out("umask-store"))
finally:
    os.umask(old_mask)
modes = {n: os.stat(os.path.join(umask_run, n)).st_mode & 0o777 for n in os.listdir(umask_run)}
check(modes and all(m == 0o664 for m in modes.values()),
      "under umask 002 every output is 0664: %s" % sorted(modes.items()))
sim.done()
