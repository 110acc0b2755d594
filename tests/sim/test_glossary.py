#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The glossary a first run points to: host_sim's summary names host_sim/GLOSSARY.md and
says what each of its figures means; the glossary explains every term the summary and the
README's first pages use, and the README links it."""
import re
import subprocess

from simtest import Sim, check

# The terms a newcomer meets first: the summary's, and the jargon of the README's tables.
TERMS = ["Calibration", "Closest", "Confidence sector", "Coverage", "E_d, E_b", "E_max,syst",
         "Exploration", "Explored", "F1", "Free-space evidence", "Gap", "Ghosts", "HAL", "Insert", "K",
         "map_server", "OM", "Odometry", "Perfect odometry", "Pose", "Pose correction",
         "Precision", "Raw OM", "Recall", "Seed", "Sonar level", "Tick", "TH", "TM",
         "Trinary map", "UMBmark", "Walls"]
# Each figure of the summary and the line that says what it means.
MEANINGS = ["precision", "recall", "F1", "perfect odometry F1", "raw OM", "pose error",
            "pose correction", "coverage", "walls", "explored", "calibration"]

sim = Sim()
glossary_path = sim.src + "/host_sim/GLOSSARY.md"
with open(glossary_path) as f:
    glossary = f.read()
entries = re.findall(r"^- \*\*([^*]+?)\.?\*\*", glossary, re.M)
missing = [t for t in TERMS if t not in entries]
check(not missing, "host_sim/GLOSSARY.md explains %d terms%s" % (
    len(TERMS), "" if not missing else "; missing: " + ", ".join(missing)))

cmd = [sim.bin, "--duration", "20", "--no-plot", "--out", sim.out("run")]
text = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, check=True).stdout
m = re.search(r"^  what these mean \(every term: (\S+)\)\n((?:    .*\n)+)", text, re.M)
check(m is not None and m.group(1) == "host_sim/GLOSSARY.md",
      "the summary points to host_sim/GLOSSARY.md")
said = [ln[4:].split("  ")[0].strip() for ln in m.group(2).splitlines()
        if ln.startswith("    ") and not ln.startswith("     ")]
check(all(w in said for w in MEANINGS),
      "the summary says what each figure means: %s" % ", ".join(said))
with open(sim.src + "/README.md") as f:
    readme = f.read()
check(readme.count("(host_sim/GLOSSARY.md)") >= 2,
      "README.md links the glossary where it shows the output, and among its pages")
sim.done()
