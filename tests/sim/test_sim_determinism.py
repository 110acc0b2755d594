#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Same seed and scenario give byte-identical output files; another seed does not.

timing.json (wall-clock speed) is the one file that may differ between identical runs.
"""
import filecmp
import os

from simtest import Sim, check

sim = Sim()
runs = {}
for name, seed in [("a", 3), ("b", 3), ("c", 4)]:
    runs[name] = sim.out(name)
    sim.run("--duration", 60, "--seed", seed, "--out", runs[name])

files = sorted(f for f in os.listdir(runs["a"]) if f != "timing.json")
expected = ["config.txt", "metrics.json", "readings.csv", "trajectory.csv"] + [
    m + ext for m in ("om", "om_post", "om_ideal", "truth") for ext in (".pgm", ".yaml")] + ["tm.pgm"]
check(sorted(expected) == files, "the run wrote its files: " + " ".join(files))
same, diff, errors = filecmp.cmpfiles(runs["a"], runs["b"], files, shallow=False)
check(not diff and not errors, "seed 3 twice: all %d files byte-identical (differ: %s)" % (len(files), diff))
same, diff, errors = filecmp.cmpfiles(runs["a"], runs["c"], ["readings.csv", "om.pgm"], shallow=False)
check(len(diff) == 2, "seed 4 gives other readings and another map")
sim.done()
