#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The building maps the reports use are in the repository (host_sim/maps), each with its
notice, the reports read them from there by default, and host_sim drives in each crop the
reports name: a clean clone reproduces the building-map figures."""
import os
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools.runs import BUILDINGS  # noqa: E402

maps = os.path.join(sim.src, "host_sim", "maps")
for name, yaml, crop in BUILDINGS:
    folder = os.path.join(maps, os.path.dirname(yaml))
    notice = os.path.join(folder, "NOTICE.txt")
    with open(notice) as f:
        text = f.read()
    check(os.path.isfile(os.path.join(maps, yaml)) and "License" in text
          and "Source repository" in text,
          "%s: host_sim/maps/%s is there with a NOTICE.txt naming its source and licence"
          % (name, yaml))
    args = ["--room", os.path.join(maps, yaml), "--duration", "5", "--out", sim.out(name)]
    if crop:
        args += ["--crop"] + [str(c) for c in crop]
    sim.run(*args)
    check(True, "%s: host_sim drives in it%s" % (name, " (crop %s)" % (crop,) if crop else ""))

for tool in ("sim_report.py", "corpus_report.py"):
    p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", tool), "--help"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check("(default: host_sim/maps)" in " ".join(p.stdout.split()),
          "tools/%s reads the building maps from host_sim/maps by default" % tool)
sim.done()
