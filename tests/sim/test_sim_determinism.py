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

# The room's grid in metrics.json is whole-number arithmetic: the same in every build
# (the 5 m x 4 m default room at 50 mm: 100 x 80 cells and one of margin each side).
ram = sim.metrics(runs["a"])["ram"]
check((ram["grid_a"], ram["grid_b"]) == (102, 82),
      "the default room needs %d x %d cells of 50 mm (102 x 82)" % (ram["grid_a"], ram["grid_b"]))
sim.done()
