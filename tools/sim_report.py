#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Reproduces the simulator's figures: the paper's claims, measured over several seeds.

usage: tools/sim_report.py [--host-sim BIN] [--seeds N] [--out DIR] [--quick] [--figure PNG]
                           [--maps DIR] [--faults-only] [--levels-only] [--host-arg ARG]...
                           [--keep]

Runs host_sim over a matrix of scenarios and prints Markdown tables (the ones in the
README): post-processing in the paper's two rooms at the paper's defaults and at the
threshold/template that maximise F1; odometry error under high and moderate
acceleration; the map with perfect odometry; per cell size, F1, odometry error and RAM;
the exploration modes over every shipped room (collisions, the closest approach, wall
coverage and when it reached 50, 80 and 90 %, raw F1) and the time they take to visit the
free cells; the wall coverage of each shipped room; and, when the building maps
of host_sim/maps (or --maps DIR) are there, the same in crops of them; and
every fault the simulator can inject at three levels (FAULTS), with the F1 floor each
level must keep (tests/sim/test_sim_faults.py asserts it). With --faults-only, that table
alone, each run that touched a wall as the arguments that repeat it with when and where
it first touched, and (with ten seeds or more) each level's means, spread and the floor
FAULTS' rule gives. The sonar's realism levels (SONAR_LEVELS, hal/host/README.md) over
every shipped room: the map from the firmware's own pose and from the true poses, the pose
error, the runs that touch, and what became of the pings (long readings by a mirror path,
and the wall cells of the true-pose map that they and the other readings lowered); with
--levels-only, that table alone and the touching runs. --host-arg adds an argument to
every run (a configuration to weigh: --host-arg=--set --host-arg=sweep_stops=7; with the
levels, a --sonar there would override theirs).
With --figure, also draws those results (host_sim/figures/report.png in the README).
Each run keeps its metrics.json, configuration and timing in DIR/NAME (default
out/report); its logs and maps are deleted once read, unless --keep.
Exit status: 0 done, 1 a run failed, 2 bad options or no host_sim.
"""
import argparse
import math
import os

from slamtools.errors import ToolError, main as tool_main
from slamtools.runs import BUILDINGS, BUILDING_S, ROOMS, SRC, add_host_arg, cores, mean, run_all

STEPS = ("raw", "threshold", "template", "insert")
ACCELS = (300, 10000)  # mm/s²: moderate, and so great that the motors limit it
MODES = ("walls", "random", "tm")  # the default first
# The sonar's realism levels (host_sim --sonar), the default in the middle.
SONAR_LEVELS = ("optimistic", "typical", "pessimistic")

# Every fault the simulator injects, at three levels, each on top of the default error
# levels: (name, what, levels); a level is (--error arguments, the F1 floor of the raw map:
# the mean over seeds 1-10 of the default room in 600 s must keep it). A floor is the lower
# of the means over seeds 1-10 and 1-100 of the build that set it, less 0.1, rounded down to
# 0.05 (and at least 0.03, so that each can fail; floor_by_rule(), which --faults-only
# --seeds 100 prints beside each floor): a fault may cost map quality, gradually, but no
# level may lose the map more than this. A ten-seed mean's standard error is 0.07 at most
# (an encoder stopping, whose runs spread most, σ 0.22; ghost echoes at level 3 0.05), so a
# change that costs a level nothing fails it a few times in a hundred at worst, where two
# seeds failed it by which runs the change happened to move.
FAULTS = (
    ("noise", "wheel noise (1σ of a tick's travel)",
     ((["noise=0.02"], 0.70), (["noise=0.05"], 0.45), (["noise=0.1"], 0.20))),
    ("slip", "slip beyond a gentler acceleration",
     ((["slip=0.5", "slip_free=0.4"], 0.45), (["slip=0.7", "slip_free=0.3"], 0.10),
      (["slip=1", "slip_free=0.2"], 0.05))),
    ("edeb", "E_d / E_b (uncalibrated wheels)",
     ((["ed=1.0005", "eb=1.003"], 0.75), (["ed=1.001", "eb=1.005"], 0.50),
      (["ed=1.002", "eb=1.01"], 0.25))),
    ("sonar_noise", "sonar range noise (1σ, m)",
     ((["sonar_noise=0.03"], 0.75), (["sonar_noise=0.1"], 0.55), (["sonar_noise=0.3"], 0.30))),
    ("dropout", "sonar dropouts (per ping)",
     ((["dropout=0.2"], 0.80), (["dropout=0.5"], 0.80), (["dropout=0.8"], 0.75))),
    ("ghost", "ghost echoes (per ping)",
     ((["ghost=0.05"], 0.75), (["ghost=0.15"], 0.50), (["ghost=0.4"], 0.25))),
    ("grazing", "grazing loss (echo up to this incidence, °)",
     ((["grazing=35"], 0.80), (["grazing=25"], 0.80), (["grazing=15"], 0.75))),
    ("echo_stuck", "echo line stuck high (episodes a second)",
     ((["echo_stuck=0.02"], 0.80), (["echo_stuck=0.1"], 0.80), (["echo_stuck=0.3"], 0.80))),
    ("servo_lag", "servo lag (share of its speed lost)",
     ((["servo_lag=0.3"], 0.80), (["servo_lag=0.6"], 0.70), (["servo_lag=0.9"], 0.50))),
    ("servo_stall", "servo stalls (episodes a second)",
     ((["servo_stall=0.02"], 0.80), (["servo_stall=0.1"], 0.75), (["servo_stall=0.3"], 0.60))),
    ("tick_miss", "missed control ticks (per tick)",
     ((["tick_miss=0.01"], 0.80), (["tick_miss=0.05"], 0.80), (["tick_miss=0.2"], 0.80))),
    ("encoder_stop", "an encoder stops counting (episodes a second)",
     ((["encoder_stop=0.002"], 0.60), (["encoder_stop=0.01"], 0.20),
      (["encoder_stop=0.05"], 0.03))),
)


def fault_args(levels_args):
    """The host_sim arguments of one fault level."""
    out = []
    for e in levels_args:
        out += ["--error", e]
    return out


def clearance_of(m):
    """The smallest clearance to an obstacle over the run, m, when metrics.json has it."""
    for part in ("robot", "exploration", "safety"):
        for key in ("min_clearance_m", "smallest_clearance_m", "clearance_min_m"):
            v = m.get(part, {}).get(key)
            if v is not None:
                return v
    return None


def fault_rows(group, baseline):
    """One row per fault level: mean F1 (raw, final), the floor, collisions, clearance."""
    rows = [("none (default errors)", "", baseline)]
    for name, what, levels in FAULTS:
        for k, (args, floor) in enumerate(levels):
            rows.append(("%s, level %d" % (what, k + 1), (" ".join(args), floor),
                         group("fault-%s-%d" % (name, k + 1))))
    return rows


def post_means(ms, which="odometry"):
    """Mean precision, recall, F1 over runs, per post-processing step."""
    return {s: tuple(mean(m["maps"][which][s][k] for m in ms) for k in ("precision", "recall", "f1"))
            for s in STEPS}


def tuned(ms):
    """The (TH, K) with the best mean F1 over runs, and its mean precision, recall, F1."""
    sw = [m["post_sweep"] for m in ms]
    ths, ks = sw[0]["threshold"], sw[0]["k"]
    best = None
    for i, th in enumerate(ths):
        for j, k in enumerate(ks):
            f1 = mean(s["f1"][i][j] for s in sw)
            if best is None or f1 > best[2]:
                best = (th, k, f1, mean(s["precision"][i][j] for s in sw),
                        mean(s["recall"][i][j] for s in sw))
    return best


def report(args):
    seeds = list(range(1, args.seeds + 1))
    base = args.out
    dur = 120 if args.quick else 600
    jobs = {}
    for room in ("default", "obstacles"):
        for s in seeds:
            jobs["post-%s-%d" % (room, s)] = ["--paper", "--room", os.path.join(ROOMS, room + ".room"),
                                              "--seed", s, "--duration", dur, "--sweep"]
            jobs["ideal-%s-%d" % (room, s)] = ["--room", os.path.join(ROOMS, room + ".room"),
                                               "--seed", s, "--duration", dur, "--ideal"]
    for acc in ACCELS:
        for s in seeds:
            jobs["accel-%d-%d" % (acc, s)] = ["--explore", "square", "--set", "square_laps=10",
                                              "--set", "square_side_um=1000000",
                                              "--set", "accel_mm_s2=%d" % acc, "--seed", s,
                                              "--duration", 400]
    for cell in (25, 50, 100):
        for s in seeds:
            jobs["cell-%d-%d" % (cell, s)] = ["--cell", cell, "--seed", s, "--duration", dur]
    for name, _, levels in FAULTS:
        for k, (fargs, _) in enumerate(levels):
            for s in seeds:
                jobs["fault-%s-%d-%d" % (name, k + 1, s)] = (
                    ["--room", os.path.join(ROOMS, "default.room"), "--seed", s, "--duration", dur]
                    + fault_args(fargs))
    cover = 600 if args.quick else 3600
    for mode in MODES:
        for s in seeds:
            jobs["cover-%s-%d" % (mode, s)] = ["--explore", mode, "--seed", s, "--cell", 100,
                                               "--duration", cover]
    rooms = sorted(f[:-5] for f in os.listdir(ROOMS) if f.endswith(".room"))
    for mode in MODES:
        for room in rooms:
            for s in seeds:
                jobs["explore-%s-%s-%d" % (mode, room, s)] = [
                    "--explore", mode, "--room", os.path.join(ROOMS, room + ".room"),
                    "--seed", s, "--duration", dur]
                if mode == MODES[0] and room in ("default", "obstacles"):
                    jobs["explore-%s-%s-%d" % (mode, room, s)].append("--sweep")  # tuned()
    for level in SONAR_LEVELS:
        for room in rooms:
            for s in seeds:
                jobs["level-%s-%s-%d" % (level, room, s)] = [
                    "--sonar", level, "--room", os.path.join(ROOMS, room + ".room"),
                    "--seed", s, "--duration", dur]
    buildings = [b for b in BUILDINGS if os.path.exists(os.path.join(args.maps, b[1]))]
    bdur = dur if args.quick else BUILDING_S
    for name, yaml, crop in buildings:
        for s in seeds[:3]:
            a = ["--room", os.path.join(args.maps, yaml), "--seed", s, "--duration", bdur]
            if crop:
                a += ["--crop"] + list(crop)
            jobs["building-%s-%d" % (name, s)] = a
    if args.faults_only:
        jobs = {n: a for n, a in jobs.items() if n.startswith(("fault-", "cell-50-"))}
    elif args.levels_only:
        jobs = {n: a for n, a in jobs.items() if n.startswith("level-")}
    jobs = {n: a + args.host_arg for n, a in jobs.items()}
    # The figure draws the odometry error of the acceleration runs from their trajectories.
    res = run_all(args.host_sim, base, jobs, args.jobs,
                  keep=lambda n: args.keep or n.startswith("accel-"))

    def group(prefix):
        return [res[n] for n in sorted(res) if n.startswith(prefix + "-")]

    if args.faults_only:
        touching = fault_table(group, len(seeds), dur)
        print("\n%d of %d runs touch%s" % (len(touching), len(res), ":" if touching else "."))
        for line in repeat_lines(touching, args.host_arg):
            print(line)
        if len(seeds) >= 10:
            floor_table(group)
        return
    if args.levels_only:
        touching = level_table(group, rooms, len(seeds), dur)
        print("\n%d of %d runs touch%s" % (len(touching), len(res), ":" if touching else "."))
        for line in repeat_lines(touching, args.host_arg, None):
            print(line)
        return

    def post_tables(title, prefix):
        print("### Post-processing, %s (mean of %d seeds, %d s each)\n" % (title, len(seeds), dur))
        for room in ("default", "obstacles"):
            ms = group(prefix % room)
            pm = post_means(ms)
            th, k, f1, p, r = tuned(ms)
            post = ms[0]["scenario"]["post"]
            print("`%s.room` — the run's TH = %d, K = %d; tuned TH = %d, K = %d\n"
                  % (room, post["threshold"], post["k"], th, k))
            print("| map | precision | recall | F1 |\n|---|---|---|---|")
            for s, label in zip(STEPS, ("raw OM (OM ≥ 1)", "after threshold", "after template",
                                        "after insert (final)")):
                print("| %s | %.3f | %.3f | %.3f |" % ((label,) + pm[s]))
            print("| tuned chain (TH %d, K %d) | %.3f | %.3f | %.3f |\n" % (th, k, p, r, f1))

    post_tables("the paper's method, `--paper`", "post-%s")
    post_tables("the evidence map, the default", "explore-" + MODES[0] + "-%s")

    print("### Acceleration and odometry (ten 1 m squares, %d seeds)\n" % len(seeds))
    print("| acceleration limit | final position error (m) | final heading error (°) |\n|---|---|---|")
    for acc in ACCELS:
        ms = group("accel-%d" % acc)
        print("| %g m/s² | %.3f | %.2f |" % (acc / 1000.0, mean(m["odometry"]["final_position_m"] for m in ms),
                                            mean(m["odometry"]["final_heading_deg"] for m in ms)))
    print()

    print("### Perfect odometry (`--ideal`)\n")
    print("| room | raw F1 | final F1 |\n|---|---|---|")
    for room in ("default", "obstacles"):
        pm = post_means(group("ideal-" + room))
        print("| %s | %.3f | %.3f |" % (room, pm["raw"][2], pm["insert"][2]))
    print()

    print("### Cell size (default room, %d seeds, %d s)\n" % (len(seeds), dur))
    print("| cell | F1 raw | F1 post | odometry error (m) | grid for the room | RAM of the maps |")
    print("|---|---|---|---|---|---|")
    for cell in (25, 50, 100):
        ms = group("cell-%d" % cell)
        pm = post_means(ms)
        ram = ms[0]["ram"]
        print("| %d mm | %.3f | %.3f | %.3f | %d × %d | %d B |" % (
            cell, pm["raw"][2], pm["insert"][2],
            mean(m["odometry"]["final_position_m"] for m in ms),
            ram["grid_a"], ram["grid_b"], ram["maps_bytes"]))
    print()

    def when(ms, key):
        ts = [m["exploration"][key] for m in ms]
        got = [x for x in ts if x is not None]
        if len(got) < len(ts):
            return "%d of %d runs%s" % (len(got), len(ts), ", mean %.0f" % mean(got) if got else "")
        return "%.0f" % mean(got)

    def f1(ms):
        return "%.3f / %.3f" % (mean(m["maps"]["odometry"]["raw"]["f1"] for m in ms),
                                mean(m["maps"]["perfect_odometry"]["raw"]["f1"] for m in ms))

    print("### Exploration (every shipped room, %d s, %d seeds each)\n" % (dur, len(seeds)))
    print("| mode | collisions | closest (m) | wall coverage | 50 % (s) | 80 % (s) | 90 % (s) "
          "| raw F1 (odometry / true poses) |\n|---|---|---|---|---|---|---|---|")
    for mode in MODES:
        ms = group("explore-" + mode)
        print("| %s | %d | %.3f | %.3f | %s | %s | %s | %s |" % (
            mode, sum(m["robot"]["collisions"] for m in ms),
            min(m["exploration"]["min_clearance_m"] for m in ms),
            mean(m["exploration"]["wall_coverage"] for m in ms),
            when(ms, "wall_time_to_50_s"), when(ms, "wall_time_to_80_s"),
            when(ms, "wall_time_to_90_s"), f1(ms)))
    print()

    print("### Wall coverage per room (%s, the default mode, %d s, %d seeds)\n"
          % (MODES[0], dur, len(seeds)))
    print("| room | wall cells | wall coverage | 90 % (s) | collisions | closest (m) "
          "| raw F1 (odometry / true poses) |\n|---|---|---|---|---|---|---|")
    for room in rooms:
        ms = group("explore-%s-%s" % (MODES[0], room))
        print("| %s | %d | %.3f | %s | %d | %.3f | %s |" % (
            room, ms[0]["exploration"]["wall_cells"],
            mean(m["exploration"]["wall_coverage"] for m in ms), when(ms, "wall_time_to_90_s"),
            sum(m["robot"]["collisions"] for m in ms),
            min(m["exploration"]["min_clearance_m"] for m in ms), f1(ms)))
    print()

    print("### Visiting the free cells (default room, 100 mm cells, %d s, %d seeds)\n"
          % (cover, len(seeds)))
    print("| mode | time to 50 % (s) | time to 80 % (s) | coverage at the end |\n|---|---|---|---|")
    for mode in MODES:
        ms = group("cover-" + mode)
        print("| %s | %s | %s | %.1f %% |" % (mode, when(ms, "time_to_50_s"), when(ms, "time_to_80_s"),
                                              100 * mean(m["exploration"]["coverage"] for m in ms)))
    print()

    if buildings:
        print("### Building maps (%s, the default mode, %d s, %d seeds)\n"
              % (MODES[0], bdur, len(seeds[:3])))
        print("| map | crop (m) | wall cells | wall coverage at 10 min | at the end | 90 % (s) "
              "| collisions | closest (m) | raw F1 (odometry / true poses) |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name, yaml, crop in buildings:
            ms = group("building-" + name)
            at10 = mean(next((p[1] for p in m["exploration"]["wall_series"] if p[0] >= 599.0),
                             m["exploration"]["wall_coverage"]) for m in ms)
            print("| %s | %s | %d | %.3f | %.3f | %s | %d | %.3f | %s |" % (
                name, " ".join("%g" % c for c in crop) if crop else "all",
                ms[0]["exploration"]["wall_cells"], at10,
                mean(m["exploration"]["wall_coverage"] for m in ms), when(ms, "wall_time_to_90_s"),
                sum(m["robot"]["collisions"] for m in ms),
                min(m["exploration"]["min_clearance_m"] for m in ms), f1(ms)))
        print()
    else:
        print("(no building maps at %s: that table is left out)\n" % args.maps)
    fault_table(group, len(seeds), dur)
    print()
    level_table(group, rooms, len(seeds), dur)
    if args.figure:
        figure(args, res, group, base)


def touch_words(t):
    """A run's first touch (metrics.json's exploration.first_touch) in words."""
    b = t["bearing_deg"]
    side = "ahead" if b == 0 else "%.0f° %s" % (abs(b), "left" if b > 0 else "right")
    return "at %.0f s, the obstacle %s, the pose %.2f m and %.1f° off" % (
        t["t_s"], side, t["position_error_m"], t["heading_error_deg"])


def repeat_lines(touching, extra=(), flag="--error"):
    """Each touching run, (values of @p flag, seed, first touch or None), as a Markdown item
    of the host_sim arguments that repeat it, and where and how it first touched when
    metrics.json says. With flag None the values are whole arguments."""
    more = "".join(" " + a for a in extra)
    return ["- `%s--seed %d%s`%s" % ("".join("%s%s " % (flag + " " if flag else "", e)
                                             for e in errors), seed, more,
                                     ": " + touch_words(t) if t else "")
            for errors, seed, t in touching]


def fault_table(group, nseeds, dur):
    """The faults' table; returns the touching runs, (--error values, seed, first touch or
    None) each."""
    print("### Faults (default room, %d s, %d seeds; each level on top of the default errors)\n"
          % (dur, nseeds))
    print("| fault | `--error` | F1 raw | F1 final | floor | collisions | smallest clearance |")
    print("|---|---|---|---|---|---|---|")
    touching = []
    for what, spec, ms in fault_rows(group, group("cell-50")):
        pm = post_means(ms)
        cols = [m["robot"]["collisions"] for m in ms]
        hit = sum(1 for c in cols if c > 0)
        cl = [clearance_of(m) for m in ms]
        clear = "%.3f m" % min(cl) if cl and None not in cl else "not measured"
        print("| %s | %s | %.3f | %.3f | %s | %d in %d of %d runs | %s |" % (
            what, "`%s`" % spec[0] if spec else "", pm["raw"][2], pm["insert"][2],
            "%.2f" % spec[1] if spec else "", sum(cols), hit, len(ms), clear))
        errors = tuple(spec[0].split()) if spec else ()
        touching += sorted(((errors, m["scenario"]["seed"], m["exploration"].get("first_touch"))
                            for m, c in zip(ms, cols) if c > 0), key=lambda k: k[:2])
    return touching


def spread(xs):
    """Mean, its standard error and the 5th percentile (nearest rank) of a sample."""
    xs = sorted(xs)
    n = len(xs)
    m = sum(xs) / n
    se = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n) if n > 1 else float("nan")
    return m, se, xs[max(0, math.ceil(0.05 * n) - 1)]


def level_table(group, rooms, nseeds, dur):
    """The sonar's levels over every shipped room; returns the touching runs, (host_sim
    arguments, seed, first touch or None) each."""
    print("### Sonar realism levels (every shipped room, %d s, %d seeds each)\n" % (dur, nseeds))
    print("| level | raw F1, own pose (mean ± se, 5th pct) | true poses | gap | final position "
          "error (m) | final heading error (°) | runs that touch | echoes by a mirror path "
          "| grazing timeouts | wall cells lowered by mirror echoes / by others |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    touching = []
    per_room = {}
    for level in SONAR_LEVELS:
        ms = group("level-" + level)
        own = [m["maps"]["odometry"]["raw"]["f1"] for m in ms]
        true = [m["maps"]["perfect_odometry"]["raw"]["f1"] for m in ms]
        om, ose, op5 = spread(own)
        tm = mean(true)
        pings = [m["pings"] for m in ms]
        n = sum(m["robot"]["pings"] for m in ms)
        hit = [m for m in ms if m["robot"]["collisions"] > 0]
        print("| %s | %.3f ± %.3f, %.3f | %.3f | %.3f | %.3f | %.2f | %d of %d | %.1f %% | %.1f %% "
              "| %.1f / %.1f a run |" % (
                  level, om, ose, op5, tm, tm - om,
                  mean(m["odometry"]["final_position_m"] for m in ms),
                  mean(m["odometry"]["final_heading_deg"] for m in ms), len(hit), len(ms),
                  100.0 * sum(p["multipath"] for p in pings) / n,
                  100.0 * sum(p["grazing"] for p in pings) / n,
                  mean(p["walls_lowered"]["multipath"] for p in pings),
                  mean(p["walls_lowered"]["other"] for p in pings)))
        touching += sorted(((("--sonar", level, "--room", os.path.relpath(
            m["scenario"]["room"], SRC)), m["scenario"]["seed"],
            m["exploration"].get("first_touch")) for m in hit), key=lambda k: k[:2])
        for room in rooms:
            per_room[(level, room)] = mean(m["maps"]["odometry"]["raw"]["f1"]
                                           for m in group("level-%s-%s" % (level, room)))
    print("\n| room | %s |\n|---|%s" % (" | ".join("raw F1 %s" % lv for lv in SONAR_LEVELS),
                                         "---|" * len(SONAR_LEVELS)))
    for room in rooms:
        print("| %s | %s |" % (room, " | ".join("%.3f" % per_room[(lv, room)]
                                                for lv in SONAR_LEVELS)))
    return touching


def floor_means(f1s_by_seed):
    """One level's mean raw F1 over seeds 1-10 and over all its seeds, from (seed, F1)."""
    first = [f for s, f in f1s_by_seed if s <= 10]
    every = [f for _, f in f1s_by_seed]
    return sum(first) / len(first), sum(every) / len(every)


def floor_by_rule(f1s_by_seed):
    """FAULTS' floor rule over one level's raw F1 by seed: the lower of the means over seeds
    1-10 and all, less 0.1, rounded down to 0.05, at least 0.03."""
    low = min(floor_means(f1s_by_seed))
    return max(0.03, math.floor(round((low - 0.1) / 0.05, 9)) * 0.05)


def floor_table(group):
    """Per fault level: the means over seeds 1-10 and all, the spread, and the floor the rule
    gives against the floor set (the rule needs seeds 1-10 at least)."""
    print("\n| fault level | F1 seeds 1-10 | F1 all seeds | σ | floor by the rule | floor |")
    print("|---|---|---|---|---|---|")
    for what, spec, ms in fault_rows(group, group("cell-50")):
        if not spec:
            continue
        f1s = [(m["scenario"]["seed"], m["maps"]["odometry"]["raw"]["f1"]) for m in ms]
        mean_first, mean_all = floor_means(f1s)
        sd = math.sqrt(sum((f - mean_all) ** 2 for _, f in f1s) / len(f1s))
        print("| %s | %.3f | %.3f | %.3f | %.2f | %.2f |" % (
            what, mean_first, mean_all, sd, floor_by_rule(f1s), spec[1]))


def figure(args, res, group, base):
    """Post-processing per room, odometry error over the squares, coverage over time."""
    import csv
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ToolError("%s (tools/install-deps.sh sim)" % e, 1)
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.6))
    ax = axes[0]
    labels = ("raw", "threshold", "template", "insert", "tuned")
    for i, room in enumerate(("default", "obstacles")):
        ms = group("post-" + room)
        pm = post_means(ms)
        th, k, f1, p, r = tuned(ms)
        vals = [pm[s][2] for s in STEPS] + [f1]
        prec = [pm[s][0] for s in STEPS] + [p]
        xs = [j + 0.38 * i for j in range(len(labels))]
        ax.bar(xs, vals, width=0.38, label="%s.room F1" % room)
        ax.plot(xs, prec, "k.", ms=8, label="precision" if i == 0 else None)
    ax.set_xticks([j + 0.19 for j in range(len(labels))])
    ax.set_xticklabels(["raw OM", "+threshold", "+template", "+insert", "tuned\nTH/K"])
    ax.set_ylim(0, 1)
    ax.set_xlabel("post-processing step")
    ax.set_ylabel("F1 (bars), precision (dots)")
    ax.set_title("post-processing at TH = 3 (mean of %d seeds)" % len(group("post-default")))
    ax.legend(fontsize=8, loc="lower left")

    ax = axes[1]
    for acc, color in zip(ACCELS, ("tab:blue", "tab:red")):
        for n in sorted(res):
            if not n.startswith("accel-%d-" % acc):
                continue
            t, e = [], []
            with open(os.path.join(base, n, "trajectory.csv")) as f:
                for row in csv.DictReader(f):
                    t.append(float(row["t_s"]))
                    e.append(((float(row["odom_x_m"]) - float(row["true_x_m"])) ** 2 +
                              (float(row["odom_y_m"]) - float(row["true_y_m"])) ** 2) ** 0.5)
            ax.plot(t, e, color=color, lw=0.8,
                    label="%g m/s²" % (acc / 1000.0) if n.endswith("-1") else None)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("odometry position error [m]")
    ax.set_title("ten 1 m squares: moderate vs great acceleration")
    ax.legend(fontsize=8)

    ax = axes[2]
    for mode, color in zip(MODES, ("tab:green", "tab:gray", "tab:orange")):
        for i, m in enumerate(group("explore-%s-default" % mode)):
            ser = m["exploration"]["wall_series"]
            ax.plot([p[0] for p in ser], [100 * p[1] for p in ser], color=color, lw=0.8,
                    label=mode if i == 0 else None)
    ax.axhline(90, color="k", lw=0.5, ls="--")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("wall cells in a ping's confidence sector [%]")
    ax.set_title("exploration: wall coverage, default room")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(args.figure, dpi=80, metadata={"Software": None})
    print("\n(figure: %s)" % args.figure)


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--host-sim", default=os.path.join(SRC, "build", "host", "host_sim", "host_sim"))
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(SRC, "out", "report"))
    ap.add_argument("--jobs", type=int, default=cores(),
                    help="runs at a time (default: every core, %d)" % cores())
    ap.add_argument("--quick", action="store_true", help="shorter runs, for a first look")
    ap.add_argument("--keep", action="store_true",
                    help="keep every run's logs and maps (by default each run keeps its "
                         "metrics.json and small files only: the report stays a few MB)")
    ap.add_argument("--figure", help="also draw the results into this PNG")
    ap.add_argument("--faults-only", action="store_true",
                    help="only the faults' table, and the runs that touch (many seeds in minutes)")
    ap.add_argument("--levels-only", action="store_true",
                    help="only the sonar levels' table, and the runs that touch")
    ap.add_argument("--maps", default=os.path.join(SRC, "host_sim", "maps"),
                    help="the building maps (default: host_sim/maps)")
    add_host_arg(ap, "--host-arg=--set --host-arg=sweep_stops=7")
    args = ap.parse_args()
    if not os.path.exists(args.host_sim):
        raise ToolError("%s not found: build it first (make sim)" % args.host_sim)
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs need a positive number")
    report(args)


if __name__ == "__main__":
    tool_main(main)
