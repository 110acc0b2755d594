#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/corpus_report.py: the grid's fit test, the summaries against cases worked by hand,
what a touch met (roomfile.touched(), touch_side()) and the table of it, --quick end to end
(its tables, its JSON, the bulky files gone, --keep), a host_sim that refuses every room as
too large (counted, not scored), --shift-start's start, and bad options."""
import contextlib
import io
import json
import math
import os
import re
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
import corpus_report as cr  # noqa: E402
from slamtools import roomfile  # noqa: E402

REPORT = os.path.join(sim.src, "tools", "corpus_report.py")


def metrics(w, h, cells, cell_mm=50):
    return {"scenario": {"room_bounds": [1.0, 2.0, 1.0 + w, 2.0 + h], "cell_mm": cell_mm,
                         "grid": {"a": cells, "b": cells, "origin": [0, 0]}}}


check(not cr.fits_grid(metrics(9.0, 4.0, 160)) and cr.fits_grid(metrics(9.0, 4.0, 256)),
      "a 9 m room does not fit 160 cells of 50 mm, fits 256")
check(cr.fits_grid(metrics(7.9, 7.9, 160)) and not cr.fits_grid(metrics(4.0, 7.96, 160)),
      "7.9 m fits 8 m of grid, 7.96 m does not (half a cell each side for the start's cell)")
check(cr.fits_grid(metrics(9.0, 9.0, 160, cell_mm=100)), "at 100 mm cells 9 m fits 160 cells")

# By hand: F1 0.9, 0.7, 0.8 → mean 0.8, σ 0.1, standard error 0.1 / sqrt(3); the 5th
# percentile lies a tenth of the way from 0.7 to 0.8; the runs that do not fit and the one
# that failed are counted and left out.
def fig(f1, touches=0, stuck_s=10.0, recovery_s=None, explored=None):
    return {"f1": f1, "gap": 1 - f1, "position_m": f1, "heading_deg": f1, "touches": touches,
            "stuck_s": stuck_s, "recovery_s": recovery_s, "wall_coverage": f1,
            "explored_s": None if explored is None else 100.0, "explored_coverage": explored}


s = cr.summarise([("ok", fig(0.9, stuck_s=30.0, explored=0.96)), ("ok", fig(0.7, 2, 29.9, 5.1)),
                  ("ok", fig(0.8, 1, recovery_s=5.0, explored=0.9)),
                  (cr.NOT_FIT, None), (cr.NOT_FIT, None), ("failed", None)])
check((s["runs"], s["scored"], s["not_fitting"], s["failed"]) == (6, 3, 2, 1),
      "6 runs: 3 scored, 2 not fitting, 1 failed")
check(abs(s["f1"]["mean"] - 0.8) < 1e-12 and abs(s["f1"]["se"] - 0.1 / math.sqrt(3)) < 1e-12,
      "mean 0.8 and standard error 0.1 / sqrt(3)")
check(abs(s["f1"]["p5"] - 0.71) < 1e-12 and abs(s["gap"]["p95"] - 0.29) < 1e-12,
      "5th percentile of F1 0.71, 95th of the gap 0.29")
check((s["touching_runs"], s["touches"]) == (2, 3), "2 runs touch, 3 touches")
check((s["stuck_runs"], s["stuck_longest_s"]) == (1, 30.0),
      "1 run stuck 30 s or more (29.9 s is not), the longest 30 s")
check((s["slow_runs"], s["slow_longest_s"]) == (1, 5.1),
      "1 run with a touch left in over 5 s (5 s is not), the longest 5.1 s")
check((s["done_runs"], round(s["done_coverage"], 9)) == (2, 0.93),
      "2 runs done, their wall coverage then 0.93 on average")
check("| 2 (3) | 1 (30) | 1 (5) | 2 (0.930) |" in cr.row("x", s),
      "the row: touching runs (touches), stuck runs (longest), slow runs (longest), runs done")
series = {"exploration": {"wall_series": [[10.0, 0.5], [20.0, 0.8], [30.0, 0.9]]}}
check(cr.coverage_at(series, 25.0) == 0.8 and cr.coverage_at(series, 5.0) == 0.0 and
      cr.coverage_at(series, None) is None,
      "the wall coverage when done: the last of wall_series at or before that time")
none = cr.summarise([(cr.NOT_FIT, None)])
check("1 %s" % cr.NOT_FIT in cr.row("x", none) and "nan" not in cr.row("x", none),
      "a row of runs that do not fit says so, and no figure")


# What a touch met, by hand: the body (radius 0.09 m) against a room of four walls, a
# partition with a free end at (2, 1), a box, a table's leg and a bin.
ROOM = """wall 0 0 4 0
wall 4 0 4 3
wall 4 3 0 3
wall 0 3 0 0
wall 2 0 2 1
box 3 2 0.5 0.5
circle 1 2 0.012
circle 1 1 0.15
start 0.5 0.5 0
"""
room = roomfile.parse(ROOM)
d = 0.09 / math.sqrt(2)
for x, y, kind in ((2.0, 1.09, "wall end"), (3 - d, 2 - d, "corner"), (3.25, 1.91, "face"),
                   (1.0, 2 - 0.102, "leg"), (1.0, 1 - 0.24, "round"), (2.5, 0.09, "face"),
                   (0.09, 0.09, "face"), (3.5 + d, 2.5 + d, "corner")):
    check(roomfile.touched(room, x, y) == kind, "the body at (%.3f, %.3f) met a %s (%s)" % (
        x, y, kind, roomfile.touched(room, x, y)))
check([roomfile.touch_side(b) for b in (0, 30, 31, -31, 135, 136, -136)] ==
      ["front", "front", "left", "right", "left", "behind", "behind"],
      "the side of a touch from its bearing: front within 30°, behind beyond 135°")
path = sim.out("touch.room")
with open(path, "w") as f:
    f.write(ROOM)
touch = {"t_s": 1.0, "x_m": 3 - d, "y_m": 2 - d, "heading_deg": 45.0, "bearing_deg": 2,
         "position_error_m": 0.0, "heading_error_deg": 0.0}
check(cr.first_touch({"exploration": {"first_touch": touch}}, path) ==
      {"kind": "corner", "side": "front"} and
      cr.first_touch({"exploration": {"first_touch": touch}}, "x.yaml")["kind"] == "map" and
      cr.first_touch({"exploration": {"first_touch": None}}, path) is None,
      "a run's first touch: what it met in a .room file, a building map's, none")
jobs = [cr.Job("rooms", 600, "x", path, k) for k in (1, 2, 3)]
jobs.append(cr.Job("flats", 3600, "x", path, 1))
met = ({"kind": "corner", "side": "front"}, {"kind": "leg", "side": "behind"}, None, None)
done = {j.name: ("ok", dict(fig(0.8), first_touch=t)) for j, t in zip(jobs, met)}
with contextlib.redirect_stdout(io.StringIO()) as text:
    rows = cr.touch_table(jobs, done)
check("| Generated rooms, 10 min | 2 | 1 | 0 | 0 | 1 | 0 | 0 | 1 | 0 | 0 | 1 |" in text.getvalue()
      and "| Generated flats, 60 min | 0 |" in text.getvalue() and rows[0]["corner"] == 1,
      "the table of first touches: 2 runs, a corner in front and a leg behind")


def report(*args):
    return subprocess.run(["/usr/bin/python3", REPORT, "--maps", sim.out("no-maps")] +
                          [str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)


out = sim.out("quick")
p = report("--host-sim", sim.bin, "--quick", "--jobs", 2, "--out", out)
check(p.returncode == 0, "corpus_report --quick runs%s" % (
    "" if p.returncode == 0 else ": " + p.stderr.strip()[-300:]))
for title in ("Shipped rooms, 1 min", "Generated rooms, 1 min", "Generated flats, 2 min"):
    check(("### %s" % title) in p.stdout, "a table: %s" % title)
rows = re.findall(r"^\| (.+?) \| (\d+) \| (\d\.\d{3}) ± ", p.stdout, re.M)
shipped = sorted(f[:-5] for f in os.listdir(os.path.join(sim.src, "host_sim", "rooms"))
                 if f.endswith(".room"))
check([r[0] for r in rows[:len(shipped) + 1]] == shipped + ["**all**"],
      "a row for every shipped room and one for all")
check("no building maps at" in p.stdout, "no building maps: said, and their table left out")
check(re.search(r"progress|runs done", p.stderr) and "runs in" in p.stderr,
      "progress and the total time on stderr")
with open(os.path.join(out, "corpus.json")) as f:
    doc = json.load(f)
runs = doc["runs"]
check(len(runs) == 2 * len(shipped) + 6 + 2 and all(r["status"] == "ok" for r in runs),
      "corpus.json: %d runs, all scored" % len(runs))
r0 = next(r for r in runs if r["name"] == "shipped-60-default-1")
with open(os.path.join(out, r0["name"], "metrics.json")) as f:
    m = json.load(f)
check(r0["f1"] == m["maps"]["odometry"]["raw"]["f1"] and
      abs(r0["gap"] - (m["maps"]["perfect_odometry"]["raw"]["f1"] - r0["f1"])) < 1e-9 and
      r0["touches"] == m["robot"]["collisions"] and r0["escapes"] == m["robot"]["escapes"] and
      r0["recovery_s"] == m["exploration"]["longest_touch_recovery_s"] and
      (r0["first_touch"] is None) == (m["exploration"]["first_touch"] is None),
      "a run's figures are its metrics.json's (F1 %.4f, gap %.4f)" % (r0["f1"], r0["gap"]))
check("### What the touching runs met first" in p.stdout and
      len(doc["first_touches"]) == 3, "the table of first touches, and its rows in the JSON")
allrow = [x for x in doc["summaries"] if x["group"] == "shipped" and x["rows"] == "all"][0]
shown = [r for r in rows if r[0] == "**all**"][0]
check(abs(float(shown[2]) - allrow["f1"]["mean"]) < 0.0005 + 1e-9,
      "the table's mean is the JSON's (%s)" % shown[2])
left = [n for r in runs for n in os.listdir(os.path.join(out, r["name"]))
        if n.endswith((".pgm", ".csv"))]
check(not left, "the bulky files are gone (%d left)" % len(left))
p2 = report("--host-sim", sim.bin, "--quick", "--jobs", 2, "--out", out)
check(p2.returncode == 0 and p2.stdout == p.stdout, "run again: the same tables, from its runs")

keep = sim.out("keep")
p = report("--host-sim", sim.bin, "--quick", "--seeds", 1, "--rooms", 1, "--flats", 0, "--keep",
           "--out", keep)
check(p.returncode == 0 and os.path.exists(os.path.join(keep, "shipped-60-default-1",
                                                        "readings.csv")),
      "--keep keeps the readings")

# A simulator whose grid holds none of the rooms: every run counted, none scored.
fake = sim.out("fake_host_sim")
with open(fake, "w") as f:
    f.write("#!/bin/sh\necho 'host_sim: the room (9.0 x 9.0 m) does not fit the 160x160 grid "
            "of 50 mm cells (8.0 x 8.0 m): use a larger --cell or a smaller --crop' >&2\nexit 2\n")
os.chmod(fake, 0o755)
p = report("--host-sim", fake, "--quick", "--seeds", 1, "--rooms", 2, "--flats", 1,
           "--out", sim.out("nofit"))
n = len(shipped) + 2 + 1
check(p.returncode == 0 and ("%d runs: 0 scored, %d that do not fit the grid" % (n, n)) in p.stdout
      and "nan" not in p.stdout, "rooms that do not fit the grid: counted, not scored")

# --shift-start: the room's start moved along x and y, its heading kept; nothing at 0.
room = sim.out("shift.room")
with open(room, "w") as f:
    f.write("wall 0 0 4 0\nstart 1.5 2.0 90   # a comment\n")
check(cr.shifted_start(room, 12.5) == ["--start", "1.5125", "2.0125", "90"] and
      cr.shifted_start(room, 0) == [], "--shift-start 12.5: --start 1.5125 2.0125 90")

for bad in (["--jobs", "0"], ["--room-durations", "x"], ["--rooms", "-1"],
            ["--shift-start", "100"], ["--shift-start", "-1"], ["--host-sim", sim.out("nothing")]):
    p = report(*bad)
    check(p.returncode == 2, "corpus_report %s: exit 2" % " ".join(bad))
sim.done()
