#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/sim_report.py --faults-only: the faults' table alone, and every run that touched a
wall listed as the arguments that repeat it; the listing against made-up runs, and a short
report (one seed, two-minute runs) against its own table."""
import contextlib
import io
import json
import os
import re
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
import sim_report  # noqa: E402


TOUCH = {"t_s": 331.1, "x_m": 1.0, "y_m": 2.0, "heading_deg": 90.0, "bearing_deg": 85,
         "position_error_m": 0.517, "heading_error_deg": 10.15}


def fake(seed, collisions, touch=None):
    maps = {s: {"precision": 0.9, "recall": 0.9, "f1": 0.9} for s in sim_report.STEPS}
    return {"scenario": {"seed": seed}, "maps": {"odometry": maps},
            "robot": {"collisions": collisions},
            "exploration": {"min_clearance_m": 0.1, "first_touch": touch}}


# Made up: seeds 10 and 9 of the first fault's second level touched, twice and once (runs
# come sorted by name, so seed 10 before 9), seed 1 of the baseline once.
first = sim_report.FAULTS[0]


def group(prefix):
    if prefix == "cell-50":
        return [fake(1, 1), fake(2, 0)]
    if prefix == "fault-%s-2" % first[0]:
        return [fake(1, 0), fake(10, 2, TOUCH), fake(9, 1)]
    return [fake(1, 0), fake(2, 0)]


text = io.StringIO()
with contextlib.redirect_stdout(text):
    touching = sim_report.fault_table(group, 2, 600)
spec = tuple(first[2][1][0])
check(touching == [((), 1, None), (spec, 9, None), (spec, 10, TOUCH)],
      "the touching runs, in the table's order and by seed: %s" % touching)
check("| 3 in 2 of 3 runs |" in text.getvalue(), "the table counts the collisions of a level")
lines = sim_report.repeat_lines(touching)
errors = "--error " + " --error ".join(spec)
want = ["- `--seed 1`", "- `%s --seed 9`" % errors,
        "- `%s --seed 10`: at 331 s, the obstacle 85° left, the pose 0.52 m and 10.2° off"
        % errors]
check(lines == want, "each listed as the arguments that repeat it, with where it first "
      "touched when the run says: %s" % lines)
extra = sim_report.repeat_lines(touching[:1], ["--set", "sweep_stops=7"])
check(extra == ["- `--seed 1 --set sweep_stops=7`"],
      "--host-arg's arguments are part of what repeats a run: %s" % extra)

# The floor rule: the lower of the means over seeds 1-10 and all, less 0.1, down to 0.05.
by_seed = [(s, 0.9 if s <= 10 else 0.7) for s in range(1, 21)]  # means 0.9 and 0.8
check(abs(sim_report.floor_by_rule(by_seed) - 0.70) < 1e-9,
      "floor by the rule: %.2f" % sim_report.floor_by_rule(by_seed))
check(abs(sim_report.floor_by_rule([(s, 0.1) for s in range(1, 11)]) - 0.03) < 1e-9,
      "and at least 0.03")
check(abs(sim_report.floor_by_rule([(s, 0.449) for s in range(1, 11)]) - 0.30) < 1e-9,
      "rounded down")

# The default sweep given again through --host-arg: every run gets it, the figures are the
# build's own.
out = sim.out("faults")
p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", "sim_report.py"),
                    "--host-sim", sim.bin, "--faults-only", "--quick", "--seeds", "1",
                    "--host-arg=--set", "--host-arg=sweep_stops=6",
                    "--out", out], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 0, "sim_report --faults-only runs (%s)" % p.stderr.strip()[-200:])
check("### Post-processing" not in p.stdout and "### Faults" in p.stdout,
      "only the faults' table is printed")
rows = re.findall(r"^\| [^|]+ \| [^|]* \| \d\.\d{3} \| \d\.\d{3} \| [^|]* \| (\d+) in (\d+) of 1 runs \|",
                  p.stdout, re.M)
levels = sum(len(levels) for _, _, levels in sim_report.FAULTS)
check(len(rows) == 1 + levels, "a row for the baseline and each of the %d levels" % levels)
runs = sum(int(hit) for _, hit in rows)
m = re.search(r"^(\d+) of (\d+) runs touch", p.stdout, re.M)
check(m is not None and int(m.group(1)) == runs and int(m.group(2)) == 1 + levels,
      "the count line agrees with the table (%s)" % (m.group(0) if m else "missing"))
listed = re.findall(r"^- `(?:--error \S+ )*--seed \d+ --set sweep_stops=6`", p.stdout, re.M)
check(len(listed) == runs, "each touching run listed once, with --host-arg's arguments (%d)"
      % len(listed))
given = [json.load(open(os.path.join(out, d, "args.json")))["args"][-2:]
         for d in sorted(os.listdir(out)) if os.path.exists(os.path.join(out, d, "args.json"))]
check(len(given) == 1 + levels and all(a == ["--set", "sweep_stops=6"] for a in given),
      "--host-arg reaches every run (%d runs)" % len(given))
sim.done()
