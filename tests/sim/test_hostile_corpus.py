#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The second round's corpus (tests/hostile/): each file that broke a program, run through
that program again, must give the exit status and the message tests/hostile/expect.txt
names, never a traceback, and write nothing where it was told to."""
import os
import shlex
import subprocess

from simtest import Sim, check

sim = Sim()
corpus = os.path.join(sim.src, "tests", "hostile")
programs = {"host_sim": [sim.bin, "--no-plot", "--quiet", "--duration", "5"],
            "telemetry.py": ["/usr/bin/python3", os.path.join(sim.src, "tools", "telemetry.py")],
            "plot_run.py": ["/usr/bin/python3", os.path.join(sim.src, "tools", "plot_run.py")]}
cases = 0
with open(os.path.join(corpus, "expect.txt"), encoding="utf-8") as f:
    for n, line in enumerate(f, 1):
        line = line.rstrip("\n")
        if not line or line.startswith("#"):
            continue
        name, code, says, cmd = line.split("\t")
        out = sim.out("out%d" % n)
        words = [w.replace("{}", os.path.join(corpus, name)).replace("{dir}", corpus)
                 .replace("{out}", out) for w in shlex.split(cmd)]
        argv = programs[words[0]] + words[1:]
        if words[0] == "host_sim":
            argv += ["--out", out]
        p = subprocess.run(argv, capture_output=True, text=True, timeout=300)
        leftovers = [x for x in os.listdir(sim.work) if x.startswith("out%d" % n)]
        check(p.returncode == int(code) and says in p.stderr and "Traceback" not in p.stderr
              and not leftovers,
              "%s: %s exits %d, says '%s'%s" % (name, words[0], p.returncode, says,
                                               "" if says in p.stderr else " (it said: %s)"
                                               % p.stderr.strip()))
        cases += 1
check(cases >= 15, "every file of the corpus ran (%d)" % cases)
sim.done()
