#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/corpus_compare.py: paired changes and counts against cases worked by hand, the
verdict (outside the standard error on every draw, one way), runs left out, --json, and
bad input."""
import json
import math
import os
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
import corpus_compare as cc  # noqa: E402

TOOL = os.path.join(sim.src, "tools", "corpus_compare.py")


def run(name, f1, touches=0, stuck_s=10.0, escapes=1, recovery_s=None, group="rooms",
        duration_s=600, status="ok"):
    return {"name": name, "group": group, "duration_s": duration_s, "status": status,
            "f1": f1, "gap": 0.9 - f1, "wall_coverage": f1, "touches": touches,
            "stuck_s": stuck_s, "escapes": escapes, "recovery_s": recovery_s}


def report(name, runs):
    path = sim.out(name + ".json")
    with open(path, "w") as f:
        json.dump({"runs": runs}, f)
    return path


def tool(*args):
    return subprocess.run([sys.executable, TOOL] + [str(a) for a in args],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


# By hand: F1 0.8, 0.7, 0.9, 0.6 before (standard error σ/2 = 0.0645); after, each 0.05
# higher (inside it) or 0.1 higher (outside it).
BEFORE = [0.8, 0.7, 0.9, 0.6]
before = [run("r%d" % i, f) for i, f in enumerate(BEFORE)]
small = [run("r%d" % i, f + 0.05) for i, f in enumerate(BEFORE)]
big = [run("r%d" % i, f + 0.1) for i, f in enumerate(BEFORE)]
down = [run("r%d" % i, f - 0.1) for i, f in enumerate(BEFORE)]
se = 0.1290994 / 2

draw, left_out = cc.compare({r["name"]: r for r in before}, {r["name"]: r for r in big})
fig = draw[("rooms", 600)]
check(fig["runs"] == 4 and left_out == 0, "4 runs paired, none left out")
check(abs(fig["f1_before"]["mean"] - 0.75) < 1e-12 and abs(fig["f1"]["before_se"] - se) < 1e-6,
      "F1 before 0.75, its standard error %.4f" % se)
check(abs(fig["f1"]["mean"] - 0.1) < 1e-12 and fig["f1"]["se"] < 1e-12 and
      abs(fig["gap"]["mean"] + 0.1) < 1e-12, "F1 +0.1 on every run: change +0.1 ± 0, gap -0.1")
moved, unjudged = cc.changed([draw, draw])
check({k for _, k, _ in moved} == {"f1", "gap", "wall_coverage"} and unjudged == [],
      "+0.1 on both draws is outside 0.0645: F1, gap and coverage changed")
d_small, _ = cc.compare({r["name"]: r for r in before}, {r["name"]: r for r in small})
d_down, _ = cc.compare({r["name"]: r for r in before}, {r["name"]: r for r in down})
check(cc.changed([draw, d_small])[0] == [], "+0.1 then +0.05 (inside its error): no change")
check(cc.changed([draw, d_down])[0] == [], "+0.1 then -0.1 (one way each): no change")

# Counts: a run stuck 30 s counts, 29.9 s not; a touch left in 5.1 s is slow, 5 s not.
after = [run("r0", 0.8, touches=2, stuck_s=30.0, escapes=3, recovery_s=5.1),
         run("r1", 0.7, touches=1, stuck_s=29.9, escapes=0, recovery_s=5.0),
         run("r2", 0.9, status="does not fit the grid"), run("r3", 0.6), run("r9", 0.5)]
draw, left_out = cc.compare({r["name"]: r for r in before}, {r["name"]: r for r in after})
fig = draw[("rooms", 600)]
check(fig["runs"] == 3 and left_out == 2, "a run not scored and one in one report only: left out")
check(fig["before"]["touching"] == 0 and fig["after"]["touching"] == 2 and
      fig["after"]["slow"] == 1 and fig["after"]["stuck"] == 1 and
      fig["after"]["longest_s"] == 30.0 and fig["after"]["escapes"] == 4 and
      fig["before"]["escapes"] == 3, "touching 0 → 2, slow 1, stuck 1 (30 s), escapes 3 → 4")
old = [{k: v for k, v in r.items() if k not in ("escapes", "recovery_s")} for r in before]
draw, _ = cc.compare({r["name"]: r for r in old}, {r["name"]: r for r in before})
check(draw[("rooms", 600)]["before"]["escapes"] is None and
      draw[("rooms", 600)]["before"]["slow"] is None and
      cc.table(draw).splitlines()[-1].endswith("| 0 → 0 | – | 0 → 0 | 10 → 10 | – |"),
      "a report without escapes or recovery times shows –, not 0")

# End to end: two draws, the groups in the report's order, the verdict and --json.
ship = [run("s%d" % i, f, group="shipped") for i, f in enumerate(BEFORE)]
ship_big = [run("s%d" % i, f + 0.1, group="shipped") for i, f in enumerate(BEFORE)]
a1, b1 = report("a1", before + ship), report("b1", big + ship_big)
a2, b2 = report("a2", before), report("b2", big)
out = sim.out("cc.json")
p = tool(a1, b1, a2, b2, "--json", out)
lines = p.stdout.splitlines()
rows = [ln for ln in lines if ln.startswith("| Shipped") or ln.startswith("| Generated")]
check(p.returncode == 0 and rows[0].startswith("| Shipped rooms, 10 min | 4 | 0.750 ± 0.065 |"
                                                " +0.1000 ± 0.0000 |"),
      "draw 1: the shipped rooms first, F1 before and its change")
check("- Generated rooms, 10 min: own-pose F1 +0.1000, +0.1000" in lines and
      "Not judged, not in every draw: Shipped rooms, 10 min." in lines,
      "the verdict: the rooms changed on both draws; the shipped rooms, in one, not judged")
with open(out) as f:
    doc = json.load(f)
check(len(doc["draws"]) == 2 and doc["changed"][0]["figure"] == "f1" and
      not any(isinstance(v, float) and math.isnan(v) for v in doc["draws"][1][0]["f1"].values()),
      "--json: both draws and the verdict, no NaN")

for args, words in (([a1], "pairs"), ([out, b1], "not a corpus report"),
                    ([sim.out("none"), b1], "cannot read"),
                    ([report("other", [run("x", 0.5)]), b1], "share no run")):
    p = tool(*args)
    check(p.returncode == 2 and words in p.stderr,
          "corpus_compare %s: exit 2, '%s'" % (" ".join(os.path.basename(a) for a in args), words))
sim.done()
