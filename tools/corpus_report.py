#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The corpus report: maps and pose over groups of rooms nobody tuned the firmware for.

usage: tools/corpus_report.py [--host-sim BIN] [--jobs N] [--out DIR] [--json FILE] [--keep]
                              [--seeds N] [--rooms N] [--room-durations S,S...] [--flats M]
                              [--first-seed S] [--maps DIR] [--shift-start MM] [--quick]
                              [--host-arg ARG]...

Runs host_sim, --jobs at a time (default: every core), over four groups:
- shipped: every host_sim/rooms/*.room with seeds 1..N (--seeds, default 20), 10 min;
- rooms: N household rooms of tools/roomgen.py (--rooms, default 100, seeds from
  --first-seed, default 1), each run with its own seed, for each of --room-durations
  (default 600,1800 s);
- flats: M flats of tools/roomgen.py (--flats, default 12), 60 min;
- buildings: the crops of the building maps tools/sim_report.py uses (BUILDINGS), seeds
  1-3, 30 min, when host_sim/maps (or --maps DIR) holds them.
For each group and duration it prints a Markdown table: the runs, then the mean ± its
standard error and the bad 5 % (the 5th percentile of F1, the 95th of the others) of
the raw F1 of OM built from the robot's own pose (metrics.json maps.odometry.raw.f1), of
the gap (the same F1 from the true poses less it, as tools/pose_report.py has it), of the
final position and heading error; the runs that touch an obstacle and their touches; the
runs that went STUCK_S (30 s) or more without 0.2 m of progress and the longest such time
(metrics.json exploration.longest_without_progress_s, issue 29's goal); the runs with a
touch left in over SLOW_S (5 s) and the longest (exploration.longest_touch_recovery_s);
the runs the robot said it had explored everything it could reach (exploration.explored_at_s)
and the mean wall coverage they had then (from exploration.wall_series); the mean wall
coverage. Rooms are also shown by floor area (under 12, 12-25, 25-40, over 40 m²),
the shipped rooms and building maps one by one. A run whose room does not fit the
simulator's grid (fits_grid()) is counted as such and not scored. A last table says what
each touching run met first (metrics.json exploration.first_touch: the obstacle nearest
the body's centre, roomfile.touched(), "map" in a building map) and where on the body.
Progress and the total time go to stderr; every run's figures and every summary to --json
(default DIR/corpus.json). Each run's folder keeps metrics.json and the small files only
(readings.csv, trajectory.csv and the images are deleted) unless --keep. A run of the same
arguments, room file and host_sim binary is not run again. --quick: a few short runs.
--shift-start MM moves every room's and flat's start, and the grid with it, MM along x and
y: the same rooms with their walls met by the cells elsewhere, every run drawn afresh
(host_sim/experiments.md has what that does to the figures).
Exit status: 0 done, 1 a run failed, 2 bad options or no host_sim.
"""
import argparse
import functools
import hashlib
import json
import math
import os
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

from slamtools import roomfile, roomgen
from slamtools.errors import ToolError, main as tool_main
from slamtools.runs import (BUILDINGS, BUILDING_S, ROOMS, SRC, add_host_arg, percentile,
                            std_error)

BANDS = ((0, 12, "under 12 m²"), (12, 25, "12–25 m²"), (25, 40, "25–40 m²"),
         (40, math.inf, "over 40 m²"))
BULKY = ("readings.csv", "trajectory.csv")  # and every .pgm
BUILDING_SEEDS = 3
NOT_FIT = "does not fit the grid"
STUCK_S = 30.0  # a run this long without progress is stuck (issue 29)
SLOW_S = 5.0  # a touch left in longer than this is not recovered (issue 29)
GROUPS = ("shipped", "rooms", "flats", "buildings")  # in the order of the tables


def fits_grid(m):
    """Whether a run's room fits the simulator's grid (metrics.json: the room's bounds
    against the run's grid, scenario.grid). host_sim centres the room on the grid, with up
    to half a cell lost where the start's cell falls, and grows the grid past 256 x 256 up
    to its capacity for a room that needs it: only a room beyond the capacity, or a run
    given grid_a or grid_b, can fail here. The one place the report decides it."""
    sc = m["scenario"]
    x0, y0, x1, y1 = sc["room_bounds"]
    cell = sc["cell_mm"] / 1000.0
    return (x1 - x0 + cell <= sc["grid"]["a"] * cell and
            y1 - y0 + cell <= sc["grid"]["b"] * cell)


class Job:
    """One host_sim run: its group, the table row it falls in, what it runs."""

    def __init__(self, group, duration, row, room, seed, extra=(), area=None):
        self.group, self.duration, self.row = group, duration, row
        self.room, self.seed, self.area = room, seed, area
        self.args = ["--room", room, "--seed", seed, "--duration", duration] + list(extra)
        self.name = "%s-%d-%s-%d" % (group, duration, os.path.basename(room).split(".")[0], seed)


def band_of(area):
    return next(label for lo, hi, label in BANDS if lo <= area < hi)


@functools.lru_cache(maxsize=None)
def read_room(path):
    """A .room file, parsed once however many runs use it."""
    with open(path) as f:
        try:
            return roomfile.parse(f.read(), path)
        except ValueError as e:
            raise ToolError(str(e))


def shifted_start(room, mm):
    """host_sim's --start for a .room file's start moved mm along x and y: the grid follows
    the start, so the walls meet the cells mm further along. Nothing when mm is 0."""
    if mm == 0:
        return []
    x, y, th = read_room(room).start
    return ["--start", "%.4f" % (x + mm / 1000.0), "%.4f" % (y + mm / 1000.0), "%g" % th]


def plan(args):
    """Every run of the report (generated rooms and flats written to DIR/generated)."""
    q = args.quick
    jobs = []
    shipped = sorted(f for f in os.listdir(ROOMS) if f.endswith(".room"))
    for f in shipped:
        for s in range(1, args.seeds + 1):
            room = os.path.join(ROOMS, f)
            jobs.append(Job("shipped", 60 if q else 600, f[:-5], room, s,
                            shifted_start(room, args.shift_start)))
    gen = os.path.join(args.out, "generated")
    index = roomgen.write_corpus(gen, args.rooms, args.flats, args.first_seed)
    for e in index["files"]:
        path = os.path.join(gen, e["file"])
        if e["kind"] == "room":
            for dur in args.room_durations:
                jobs.append(Job("rooms", dur, band_of(e["area_m2"]), path, e["seed"],
                                shifted_start(path, args.shift_start), area=e["area_m2"]))
        else:
            jobs.append(Job("flats", 120 if q else 3600, "flats", path, e["seed"],
                            shifted_start(path, args.shift_start), area=e["area_m2"]))
    buildings = [b for b in BUILDINGS if os.path.exists(os.path.join(args.maps, b[1]))]
    for name, yaml, crop in buildings:
        for s in range(1, (1 if q else BUILDING_SEEDS) + 1):
            jobs.append(Job("buildings", 60 if q else BUILDING_S, name,
                            os.path.join(args.maps, yaml), s,
                            ["--crop"] + list(crop) if crop else []))
    for j in jobs:
        j.args += args.host_arg
    return jobs, bool(buildings)


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def run(bin_, out, job, keep):
    """One run: ("ok", metrics), (NOT_FIT, metrics or None) or ("failed", message)."""
    stamp = os.path.join(out, "args.json")
    key = {"args": [str(a) for a in job.args], "host_sim_mtime_ns": os.stat(bin_).st_mtime_ns,
           "room_sha256": digest(job.room)}
    metrics = os.path.join(out, "metrics.json")
    cached = False
    if os.path.exists(stamp) and os.path.exists(metrics):
        with open(stamp) as f:
            cached = json.load(f) == key
    if not cached:
        cmd = [bin_, "--quiet", "--no-plot", "--out", out] + key["args"]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            if p.returncode == 2 and "does not fit" in p.stderr:
                return NOT_FIT, None
            return "failed", "%s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip())
        with open(stamp, "w") as f:
            json.dump(key, f)
    with open(metrics) as f:
        m = json.load(f)
    if not keep:
        for name in os.listdir(out):
            if name in BULKY or name.endswith(".pgm"):
                os.remove(os.path.join(out, name))
    return ("ok" if fits_grid(m) else NOT_FIT), m


def first_touch(m, room):
    """What a run's first touch met and where on the body (roomfile.TOUCH_KINDS or "map",
    roomfile.touch_side()), or None without one."""
    t = m["exploration"]["first_touch"]
    if t is None:
        return None
    kind = roomfile.touched(read_room(room), t["x_m"], t["y_m"]) if room.endswith(".room") \
        else "map"
    return {"kind": kind, "side": roomfile.touch_side(t["bearing_deg"])}


def coverage_at(m, t):
    """The wall coverage a run had reached at t s (its metrics.json wall_series), or None
    when t is None (the run never said it was done)."""
    if t is None:
        return None
    return max((c for s, c in m["exploration"]["wall_series"] if s <= t), default=0.0)


def figures(m, room):
    """The figures of one run that the tables summarise (room: its .room file, or the
    building map's)."""
    own = m["maps"]["odometry"]["raw"]["f1"]
    return {"f1": own, "gap": round(m["maps"]["perfect_odometry"]["raw"]["f1"] - own, 4),
            "position_m": m["odometry"]["final_position_m"],
            "heading_deg": m["odometry"]["final_heading_deg"],
            "touches": m["robot"]["collisions"],
            "stuck_s": m["exploration"]["longest_without_progress_s"],
            "escapes": m["robot"]["escapes"],
            "recovery_s": m["exploration"]["longest_touch_recovery_s"],
            "explored_s": m["exploration"]["explored_at_s"],
            "explored_coverage": coverage_at(m, m["exploration"]["explored_at_s"]),
            "wall_coverage": m["exploration"]["wall_coverage"],
            "first_touch": first_touch(m, room)}


def run_all(args, jobs):
    """Runs every job, --jobs at a time, longest first; returns {name: (status, figures)}."""
    done, failed = {}, []
    t0 = time.monotonic()
    step = max(1, len(jobs) // 20)
    print("corpus_report: %d runs of %s, %d at a time, into %s"
          % (len(jobs), args.host_sim, args.jobs, args.out), file=sys.stderr)
    with ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futs = {ex.submit(run, args.host_sim, os.path.join(args.out, j.name), j, args.keep): j
                for j in sorted(jobs, key=lambda j: -j.duration)}
        for k, fut in enumerate(as_completed(futs), 1):
            job = futs[fut]
            status, m = fut.result()
            if status == "failed":
                failed.append(m)
                print("corpus_report: FAILED %s" % m, file=sys.stderr)
            done[job.name] = (status, figures(m, job.room) if status == "ok" else None)
            if k % step == 0 or k == len(jobs):
                print("corpus_report: %d of %d runs done, %.0f s" % (k, len(jobs),
                                                                     time.monotonic() - t0),
                      file=sys.stderr)
    return done, failed, time.monotonic() - t0


def summarise(runs):
    """The summary of (status, figures) pairs: counts, and for each figure its mean,
    standard error, 5th and 95th percentile over the runs that fit the grid."""
    ok = [f for status, f in runs if status == "ok"]
    out = {"runs": len(runs), "scored": len(ok),
           "not_fitting": sum(1 for status, _ in runs if status == NOT_FIT),
           "failed": sum(1 for status, _ in runs if status == "failed"),
           "touching_runs": sum(1 for f in ok if f["touches"] > 0),
           "touches": sum(f["touches"] for f in ok),
           "stuck_runs": sum(1 for f in ok if f["stuck_s"] >= STUCK_S),
           "stuck_longest_s": max((f["stuck_s"] for f in ok), default=math.nan),
           "slow_runs": sum(1 for f in ok if (f["recovery_s"] or 0.0) > SLOW_S),
           "slow_longest_s": max((f["recovery_s"] or 0.0 for f in ok), default=math.nan)}
    done = [f["explored_coverage"] for f in ok if f.get("explored_s") is not None]
    out["done_runs"] = len(done)
    out["done_coverage"] = statistics.mean(done) if done else math.nan
    for key in ("f1", "gap", "position_m", "heading_deg", "wall_coverage"):
        xs = [f[key] for f in ok]
        out[key] = {"mean": statistics.mean(xs) if xs else math.nan,
                    "se": std_error(xs),
                    "p5": percentile(xs, 5), "p95": percentile(xs, 95)}
    return out


HEAD = ("| %s | runs | F1 own pose | F1 5th pct | gap | gap 95th pct | position (m) "
        "| position 95th pct | heading (°) | heading 95th pct | touching runs (touches) "
        "| runs stuck " + "%g" % STUCK_S + " s (longest s) | runs with a touch left in over "
        + "%g" % SLOW_S + " s (longest s) | runs done (wall coverage then) | wall coverage |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def pm(s, fmt):
    se = "–" if math.isnan(s["se"]) else fmt % s["se"]
    return (fmt + " ± %s") % (s["mean"], se)


def row(label, s):
    runs = "%d" % s["scored"]
    if s["not_fitting"] or s["failed"]:
        runs += " (%s)" % ", ".join(
            x for x in ("%d %s" % (s["not_fitting"], NOT_FIT) if s["not_fitting"] else "",
                        "%d failed" % s["failed"] if s["failed"] else "") if x)
    if not s["scored"]:
        return "| %s | %s |%s" % (label, runs, " – |" * 13)
    done = "%d" % s["done_runs"]
    if s["done_runs"]:
        done += " (%.3f)" % s["done_coverage"]
    return ("| %s | %s | %s | %.3f | %s | %.3f | %s | %.2f | %s | %.1f | %d (%d) | %d (%.0f) "
            "| %d (%.0f) | %s | %s |") % (
        label, runs, pm(s["f1"], "%.3f"), s["f1"]["p5"], pm(s["gap"], "%.3f"), s["gap"]["p95"],
        pm(s["position_m"], "%.2f"), s["position_m"]["p95"], pm(s["heading_deg"], "%.1f"),
        s["heading_deg"]["p95"], s["touching_runs"], s["touches"], s["stuck_runs"],
        s["stuck_longest_s"], s["slow_runs"], s["slow_longest_s"], done,
        pm(s["wall_coverage"], "%.3f"))


TITLES = {"shipped": ("Shipped rooms", "room", "host_sim/rooms, seeds 1–%d"),
          "rooms": ("Generated rooms", "floor area", "tools/roomgen.py, each with its seed"),
          "flats": ("Generated flats", "", "tools/roomgen.py, each with its seed"),
          "buildings": ("Building maps", "map", "the crops of tools/sim_report.py, seeds 1–%d")}


def tables(jobs):
    """Each table's group, duration and runs, in the order they are printed."""
    for group in GROUPS:
        for dur in sorted({j.duration for j in jobs if j.group == group}):
            yield group, dur, [j for j in jobs if j.group == group and j.duration == dur]


def report(args, jobs, done):
    """Prints the tables; returns the summaries for the JSON file."""
    summaries = []
    for group, dur, mine in tables(jobs):
        title, what, source = TITLES[group]
        if "%d" in source:
            last = max(j.seed for j in mine)
            source = source.replace("s 1–%d", " 1") if last == 1 else source % last
        print("### %s, %s (%d runs; %s)\n" % (title, minutes(dur), len(mine), source))
        print(HEAD % (what or "group"))
        labels = [label for _, _, label in BANDS] if group == "rooms" else \
            sorted({j.row for j in mine}) if group != "flats" else []
        for label in labels:
            s = summarise([done[j.name] for j in mine if j.row == label])
            if s["runs"]:
                print(row(label, s))
                summaries.append(dict(s, group=group, duration_s=dur, rows=label))
        s = summarise([done[j.name] for j in mine])
        print(row("**all**" if labels else "all", s))
        summaries.append(dict(s, group=group, duration_s=dur, rows="all"))
        print()
    return summaries


TOUCHED = roomfile.TOUCH_KINDS + ("map",)
SIDES = ("front", "left", "right", "behind")
SIDE_HEADS = {"front": "in front", "left": "on the left", "right": "on the right",
              "behind": "behind"}


def touch_table(jobs, done):
    """What the touching runs met first, group by group; returns its rows for the JSON."""
    print("### What the touching runs met first\n")
    print("| group | touching runs | " + " | ".join(TOUCHED) + " | " + " | ".join(
        SIDE_HEADS[s] for s in SIDES) + " |")
    print("|---" * (2 + len(TOUCHED) + len(SIDES)) + "|")
    rows = []
    for group, dur, mine in tables(jobs):
        met = [done[j.name][1]["first_touch"] for j in mine
               if done[j.name][0] == "ok" and done[j.name][1]["first_touch"]]
        counts = {k: sum(1 for t in met if t["kind"] == k) for k in TOUCHED}
        counts.update({s: sum(1 for t in met if t["side"] == s) for s in SIDES})
        print("| %s, %s | %d | %s |" % (TITLES[group][0], minutes(dur), len(met), " | ".join(
            "%d" % counts[k] for k in TOUCHED + SIDES)))
        rows.append(dict(counts, group=group, duration_s=dur, touching_runs=len(met)))
    print()
    return rows


def minutes(s):
    return "%g min" % (s / 60.0)


def write_json(path, args, jobs, done, summaries, touched, wall):
    """Every run's figures and every table's summary."""
    runs = [dict(name=j.name, group=j.group, duration_s=j.duration, row=j.row, room=j.room,
                 seed=j.seed, area_m2=j.area, status=done[j.name][0], **(done[j.name][1] or {}))
            for j in jobs]
    with open(path, "w") as f:
        json.dump(no_nan({"host_sim": args.host_sim, "host_args": args.host_arg, "jobs": args.jobs,
                          "wall_s": round(wall, 1), "runs": runs, "summaries": summaries,
                          "first_touches": touched}),
                  f, indent=1, allow_nan=False)
        f.write("\n")


def no_nan(x):
    """JSON has no NaN: a figure over no runs (or a spread over one) is null."""
    if isinstance(x, dict):
        return {k: no_nan(v) for k, v in x.items()}
    if isinstance(x, list):
        return [no_nan(v) for v in x]
    return None if isinstance(x, float) and math.isnan(x) else x


def durations(text):
    try:
        out = [int(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("'%s': whole seconds, separated by commas" % text)
    if not out or any(v < 1 for v in out):
        raise argparse.ArgumentTypeError("'%s': each duration at least 1 s" % text)
    return out


def main():
    ap = argparse.ArgumentParser(prog="tools/corpus_report.py", usage=argparse.SUPPRESS,
                                 description=__doc__.strip(),
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--host-sim", metavar="BIN",
                    default=os.path.join(SRC, "build", "host", "host_sim", "host_sim"))
    ap.add_argument("--jobs", type=int, metavar="N", default=os.cpu_count() or 2,
                    help="runs at a time (default: every core)")
    ap.add_argument("--out", default=os.path.join(SRC, "out", "corpus"), metavar="DIR")
    ap.add_argument("--json", metavar="FILE", help="(default DIR/corpus.json)")
    ap.add_argument("--keep", action="store_true", help="keep every run's readings, trajectory "
                    "and images")
    ap.add_argument("--seeds", type=int, metavar="N", default=20,
                    help="seeds of each shipped room (default 20)")
    ap.add_argument("--rooms", type=int, metavar="N", default=100,
                    help="generated rooms (default 100)")
    ap.add_argument("--room-durations", type=durations, default=[600, 1800], metavar="S,S",
                    help="the generated rooms' durations (default 600,1800 s)")
    ap.add_argument("--flats", type=int, metavar="M", default=12,
                    help="generated flats (default 12)")
    ap.add_argument("--first-seed", type=int, metavar="S", default=1,
                    help="of the generated rooms and flats (default 1)")
    ap.add_argument("--maps", metavar="DIR",
                    default=os.path.join(SRC, "host_sim", "maps"),
                    help="the building maps (default: host_sim/maps)")
    ap.add_argument("--shift-start", type=float, metavar="MM", default=0.0,
                    help="move every room's and flat's start MM along x and y (the grid "
                    "with it): where the walls fall within the cells (default 0)")
    ap.add_argument("--quick", action="store_true",
                    help="a smoke test: 2 seeds, 6 rooms and 2 flats, runs of 1-2 min")
    add_host_arg(ap, "--host-arg=--set --host-arg=localize=0")
    args = ap.parse_args()
    if min(args.jobs, args.seeds) < 1 or min(args.rooms, args.flats, args.first_seed) < 0:
        ap.error("--jobs and --seeds need at least 1; --rooms, --flats and --first-seed "
                 "cannot be negative")
    if not 0.0 <= args.shift_start < 100.0:
        ap.error("--shift-start takes 0 up to 100 mm, the largest cell (a whole cell more "
                 "meets the walls as before)")
    if not os.path.exists(args.host_sim):
        raise ToolError("%s not found: build it first (make sim)" % args.host_sim)
    if args.quick:
        args.seeds, args.rooms = min(args.seeds, 2), min(args.rooms, 6)
        args.flats = min(args.flats, 2)
        args.room_durations = [60]
    jobs, buildings = plan(args)
    done, failed, wall = run_all(args, jobs)
    summaries = report(args, jobs, done)
    if not buildings:
        print("(no building maps at %s: their table is left out)\n" % args.maps)
    touched = touch_table(jobs, done)
    not_fit = sum(1 for status, _ in done.values() if status == NOT_FIT)
    print("%d runs: %d scored, %d that do not fit the grid, %d failed." % (
        len(done), len(done) - not_fit - len(failed), not_fit, len(failed)))
    path = args.json or os.path.join(args.out, "corpus.json")
    write_json(path, args, jobs, done, summaries, touched, wall)
    print("corpus_report: %d runs in %.0f s on %d jobs; figures in %s" % (
        len(done), wall, args.jobs, path), file=sys.stderr)
    for msg in failed:
        print("failed: %s" % msg, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    tool_main(main)
