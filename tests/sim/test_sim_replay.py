#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim --replay readings.csv rebuilds om.pgm exactly, through the same mapper."""
import filecmp
import os

from simtest import Sim, check

sim = Sim()
run = sim.out("run")
sim.run("--duration", 120, "--seed", 5, "--room", sim.room("obstacles.room"), "--out", run)
rep = sim.out("replay")
sim.run("--replay", os.path.join(run, "readings.csv"), "--out", rep)
check(filecmp.cmp(os.path.join(run, "om.pgm"), os.path.join(rep, "om.pgm"), shallow=False),
      "the replayed om.pgm is byte-identical to the run's")
check(filecmp.cmp(os.path.join(run, "om.yaml"), os.path.join(rep, "om.yaml"), shallow=False),
      "and so is om.yaml")
m = sim.metrics(run)
check(m["robot"]["om_hits"] > 100, "the log had something to replay (%d OM hits)" % m["robot"]["om_hits"])

# A damaged log is refused, naming the line.
bad = sim.out("bad.csv")
with open(os.path.join(run, "readings.csv")) as f:
    lines = f.readlines()
lines[5] = "12.3,65.000,zero,ok,1,2,3,4,5,6\n"
with open(bad, "w") as f:
    f.writelines(lines)
p = sim.run("--replay", bad, "--config", os.path.join(run, "config.txt"), "--out", sim.out("never"), expect=2)
check(bad + ":6:" in p.stderr and not os.path.exists(sim.out("never")), "a malformed reading names its line")
sim.done()
