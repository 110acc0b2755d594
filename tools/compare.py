#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The firmware's mapper beside OctoMap and HIMM on the same sonar logs (`make compare`).

usage: tools/compare.py [--rooms ROOM...] [--seeds 1-10] [--generated N] [--count-all]
                        [--duration S] [--out DIR] [--jobs N] [--no-variants]
                        [--host-sim BIN] [--octomap BIN]

For every shipped room (host_sim/rooms/*.room) and seed, host_sim explores for --duration
seconds and logs its readings; with --generated N, the household rooms 1..N of
tools/roomgen.py instead, each with its own seed. Each log is mapped twice by each mapper:
  - from the TRUE pose of every ping (mapping apart from localization): the firmware's
    mapper is `host_sim --replay` of the log with the true poses in the odometry columns
    and the localizer off (its map must equal the run's om_ideal.pgm byte for byte);
  - from the firmware's ESTIMATED pose (odometry and its pose correction): the firmware's
    map is the run's own om.pgm; OctoMap gets the estimate of every ping as the run
    believed it (host_sim --scoring's scoring_estimate.csv).
OctoMap is tools/octomap/octomap_replay, each reading a fan of rays across the cone; HIMM
(slamtools/himm.py) the histogramic in-motion map, the beam's axis alone, occupied at one
reading's increment (3).
The true-pose mapping of both runs inside valgrind's callgrind on each room's first seed
(every run with --count-all),
counting only the insertion of readings: the firmware's mapper_free, sonar_obstacle,
mapper_hit and mapper_timeout; OctoMap's insert_reading (the fan and
OcTree::insertPointCloud). One scorer (tools/mapscore.py) scores both maps; it must
reproduce host_sim's metrics.json for the firmware's own maps to 4 decimals on every run.
Prints a Markdown table per room (means over the seeds) and, unless --no-variants, the
OctoMap settings tried (from the true poses). Writes the tables to DIR/compare.md, one
line per run to DIR/compare.csv and every figure to DIR/compare.json.
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import threading
from concurrent.futures import ThreadPoolExecutor

from slamtools import himm, mapscore, pgm, roomgen
from slamtools.errors import FAILED, ToolError, main as tool_main

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The firmware's insertion of one reading as host_sim --replay runs it (readq_map() with
# the localizer off, as robot_idle() maps it); none of these calls another of them.
FIRMWARE_FUNCTIONS = ("mapper_free", "sonar_obstacle", "mapper_hit", "mapper_timeout")
OCTOMAP_FUNCTION = "*insert_reading*"

# OctoMap's settings: the chosen one first, then the others tried. Probabilities are
# OctoMap's hit/miss, clamping its default (0.1192, 0.971) unless named.
CHOSEN = "fan 15°, 1 m, hit 0.6 / miss 0.45"
REACH_M = 1.0  # the chosen setting's and HIMM's: echoes beyond are free rays this long
VARIANTS = (
    (CHOSEN, ["--max-range", "%g" % REACH_M, "--hit", "0.6", "--miss", "0.45"]),
    ("fan 15°, 1 m, OctoMap's defaults (0.7 / 0.4)", ["--max-range", "1"]),
    ("fan 15°, 4 m (HC-SR04), 0.6 / 0.45", ["--max-range", "4", "--hit", "0.6", "--miss", "0.45"]),
    ("fan 15°, 4 m, 0.7 / 0.4", ["--max-range", "4"]),
    ("fan 15°, 1 m, 0.6 / 0.45, timeouts free to 1 m",
     ["--max-range", "1", "--hit", "0.6", "--miss", "0.45", "--timeouts", "free"]),
    ("fan 15°, 1 m, 0.6 / 0.45, clamping 0.2 / 0.8",
     ["--max-range", "1", "--hit", "0.6", "--miss", "0.45", "--clamp", "0.2", "0.8"]),
    ("fan 15°, 1 m, 0.6 / 0.45, lazy evaluation (inner nodes once, at the end)",
     ["--max-range", "1", "--hit", "0.6", "--miss", "0.45", "--lazy"]),
    ("fan 15°, 1 m, 0.6 / 0.45, discretized (a ray per endpoint cell)",
     ["--max-range", "1", "--hit", "0.6", "--miss", "0.45", "--discretize"]),
    ("fan of 5 rays, 1 m, 0.6 / 0.45", ["--max-range", "1", "--rays", "5", "--hit", "0.6",
                                        "--miss", "0.45"]),
    ("fan 7.5° (the cone's central half), 1 m, 0.6 / 0.45",
     ["--max-range", "1", "--cone", "7.5", "--hit", "0.6", "--miss", "0.45"]),
    ("axis only (1 ray, as the firmware), 1 m, 0.6 / 0.45",
     ["--max-range", "1", "--rays", "1", "--hit", "0.6", "--miss", "0.45"]),
)


def score_file(path, truth, observable):
    """mapscore's score of a map this comparison made: one it cannot read is a failure of
    the comparison (exit 1), not bad input."""
    try:
        return mapscore.score_file(path, truth, observable)
    except ToolError as e:
        raise ToolError(str(e), FAILED) from None


def load_truth(run_dir):
    try:
        return mapscore.load_truth(run_dir)
    except ToolError as e:
        raise ToolError(str(e), FAILED) from None


def parse_seeds(text):
    """'1-5' or '1,3,7' as a list of ints."""
    m = re.fullmatch(r"(\d+)-(\d+)", text)
    try:
        seeds = list(range(int(m.group(1)), int(m.group(2)) + 1)) if m else \
            [int(s) for s in text.split(",")]
    except ValueError:
        seeds = []
    if not seeds:
        raise argparse.ArgumentTypeError("'%s' is not a seed list like 1-5 or 1,3" % text)
    return seeds


def run(cmd, what):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("%s failed (exit %d): %s\n%s%s" % (what, p.returncode, " ".join(cmd),
                                                             p.stdout, p.stderr),
                           2 if p.returncode == 2 else 1)
    return p


def callgrind(cmd, toggles, out_file, what):
    """Runs cmd under callgrind, collecting inside `toggles` only; the instructions."""
    vg = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out_file]
    vg += ["--toggle-collect=" + f for f in toggles]
    run(vg + cmd, what)
    with open(out_file) as f:
        for line in f:
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise ToolError("%s: no instruction total in %s" % (what, out_file), FAILED)


POSE_KEYS = ("x_m", "y_m", "th_rad")


def read_csv(path):
    """A CSV's header and rows, as lists of fields."""
    with open(path) as f:
        head = f.readline().rstrip("\n").split(",")
        return head, [line.rstrip("\n").split(",") for line in f]


def write_log(path, head, rows, poses):
    """The log `rows` with poses[i] (x, y, th as written) in row i's odometry columns."""
    cols = [head.index("odom_" + k) for k in POSE_KEYS]
    with open(path, "w") as f:
        f.write(",".join(head) + "\n")
        for r, pose in zip(rows, poses):
            for c, v in zip(cols, pose):
                r[c] = v
            f.write(",".join(r) + "\n")


def true_pose_log(run_dir, out_dir):
    """A copy of the run's log with the true poses in the odometry columns, and its
    configuration with the localizer off: what the firmware's mapper maps from the truth
    (it must reproduce om_ideal.pgm). Returns the number of readings."""
    os.makedirs(out_dir, exist_ok=True)
    head, rows = read_csv(os.path.join(run_dir, "readings.csv"))
    cols = [head.index("true_" + k) for k in POSE_KEYS]
    write_log(os.path.join(out_dir, "readings.csv"), head, rows,
              [[r[c] for c in cols] for r in rows])
    with open(os.path.join(run_dir, "config.txt")) as f:
        cfg = f.read()
    cfg, n = re.subn(r"(?m)^localize\s*=.*$", "localize = 0", cfg)
    if n == 0:
        cfg += "localize = 0\n"
    with open(os.path.join(out_dir, "config.txt"), "w") as f:
        f.write(cfg)
    return len(rows)


def config_value(run_dir, key):
    with open(os.path.join(run_dir, "config.txt")) as f:
        m = re.search(r"(?m)^%s\s*=\s*(\S+)" % re.escape(key), f.read())
    if m is None:
        raise ToolError("%s/config.txt: no %s" % (run_dir, key), FAILED)
    return float(m.group(1))


def estimate_log(run_dir, out_path):
    """A copy of the run's log with the firmware's estimated pose of every ping in the
    odometry columns (scoring_estimate.csv, row for row)."""
    head, rows = read_csv(os.path.join(run_dir, "readings.csv"))
    est_path = os.path.join(run_dir, "scoring_estimate.csv")
    ehead, est = read_csv(est_path)
    if len(est) != len(rows):
        raise ToolError("%s: %d rows, readings.csv has %d" % (est_path, len(est), len(rows)), FAILED)
    t = ehead.index("t_s")
    for r, e in zip(rows, est):
        if r[0] != e[t]:
            raise ToolError("%s: a row of t_s %s, readings.csv's is %s" % (est_path, e[t], r[0]), FAILED)
    cols = [ehead.index("est_" + k) for k in POSE_KEYS]
    write_log(out_path, head, rows, [[e[c] for c in cols] for e in est])


def geometry(run_dir):
    """A run's grid (a, b, origin x, origin y, cell; m), sonar mount (x, y m, yaw °) and
    minimum range (m), as every mapper reads its log."""
    with open(os.path.join(run_dir, "metrics.json")) as f:
        sc = json.load(f)["scenario"]
    g = sc["grid"]
    grid = (g["a"], g["b"], g["origin"][0], g["origin"][1], sc["cell_mm"] / 1000.0)
    mount = [config_value(run_dir, k) / s for k, s in
             (("mount_x_um", 1e6), ("mount_y_um", 1e6), ("mount_yaw_mdeg", 1e3))]
    return grid, mount, config_value(run_dir, "range_min_um") / 1e6


def octomap_cmd(bin_, run_dir, args, out_pgm, readings=None, poses="true"):
    """octomap_replay on a run's log (or `readings`, a copy of it) with the run's geometry;
    the true_* poses, or with poses="odom" the odom_* columns."""
    grid, mount, min_range = geometry(run_dir)
    return [bin_, "--readings", readings or os.path.join(run_dir, "readings.csv"), "--out", out_pgm,
            "--grid"] + [str(v) if isinstance(v, int) else repr(v) for v in grid] + \
        ["--mount"] + [repr(v) for v in mount] + \
        ["--poses", poses, "--min-range", repr(min_range)] + args


HIMM_THRESHOLD = himm.INCREMENT  # one reading's hit, not taken back since


def himm_score(run_dir, readings, poses, out_pgm, truth, observable):
    """HIMM's map of a run's log (or a copy of it) with the run's geometry, scored."""
    grid, mount, min_range = geometry(run_dir)
    pgm.write(out_pgm, himm.himm_map(readings, grid, mount, poses, min_range, REACH_M,
                                     HIMM_THRESHOLD))
    return score_file(out_pgm, truth, observable)


def same_4(a, b):
    """Whether two scores agree as metrics.json prints them."""
    keys4 = ("precision", "recall", "f1")
    return all("%.4f" % a[k] == "%.4f" % b[k] for k in keys4) and \
        all(a[k] == b[k] for k in ("mapped", "true_positive", "observable", "matched"))


def check_scorer(run_dir, truth, observable):
    """The scorer must give host_sim's own figures for the firmware's maps."""
    with open(os.path.join(run_dir, "metrics.json")) as f:
        maps = json.load(f)["maps"]
    for pgm, which in (("om.pgm", "odometry"), ("om_ideal.pgm", "perfect_odometry")):
        mine = score_file(os.path.join(run_dir, pgm), truth, observable)
        if not same_4(mine, maps[which]["raw"]):
            raise ToolError("%s/%s: the scorer gives %s, metrics.json %s" % (
                run_dir, pgm, mine, maps[which]["raw"]), FAILED)


def one_run(a, room, seed, variants, count):
    """Everything for one room and seed; a dict of figures. With `count`, both insertions
    run inside callgrind and their instructions are kept."""
    name = "%s-%d" % (os.path.splitext(os.path.basename(room))[0], seed)
    d = os.path.join(a.out, name)
    run([a.host_sim, "--room", room, "--seed", str(seed), "--duration", str(a.duration),
         "--out", d, "--no-plot", "--quiet", "--scoring"], "host_sim " + name)
    truth, observable = load_truth(d)
    check_scorer(d, truth, observable)
    res = {"room": name.rsplit("-", 1)[0], "seed": seed, "variants": {}}

    fw_dir = os.path.join(d, "firmware_true")
    res["readings"] = true_pose_log(d, fw_dir)
    cmd = [a.host_sim, "--replay", os.path.join(fw_dir, "readings.csv"), "--out", fw_dir, "--quiet"]
    what = "the firmware's replay of " + name
    if count:
        res["firmware_ir"] = callgrind(cmd, FIRMWARE_FUNCTIONS,
                                       os.path.join(fw_dir, "callgrind.out"), what)
    else:
        run(cmd, what)
    with open(os.path.join(fw_dir, "om.pgm"), "rb") as f1, \
            open(os.path.join(d, "om_ideal.pgm"), "rb") as f2:
        if f1.read() != f2.read():
            raise ToolError("%s: the replay from the true poses differs from om_ideal.pgm" % d, FAILED)
    res["firmware"] = score_file(os.path.join(fw_dir, "om.pgm"), truth, observable)

    om_pgm = os.path.join(d, "octomap.pgm")
    cmd = octomap_cmd(a.octomap, d, VARIANTS[0][1], om_pgm)
    what = "OctoMap on " + name
    if count:
        res["octomap_ir"] = callgrind(cmd, [OCTOMAP_FUNCTION],
                                      os.path.join(d, "octomap.callgrind.out"), what)
    else:
        run(cmd, what)
    res["octomap"] = score_file(om_pgm, truth, observable)
    res["himm"] = himm_score(d, os.path.join(d, "readings.csv"), "true",
                             os.path.join(d, "himm.pgm"), truth, observable)

    # From the estimated poses: the run's own map, and OctoMap from the same estimate.
    res["firmware_est"] = score_file(os.path.join(d, "om.pgm"), truth, observable)
    est = os.path.join(d, "readings_estimate.csv")
    estimate_log(d, est)
    om_pgm = os.path.join(d, "octomap_estimate.pgm")
    run(octomap_cmd(a.octomap, d, VARIANTS[0][1], om_pgm, est, "odom"),
        "OctoMap on %s from the estimated poses" % name)
    res["octomap_est"] = score_file(om_pgm, truth, observable)
    res["himm_est"] = himm_score(d, est, "odom", os.path.join(d, "himm_estimate.pgm"), truth,
                                 observable)
    for k, (label, args) in enumerate(variants):
        if label == CHOSEN:
            res["variants"][label] = res["octomap"]
            continue
        om_pgm = os.path.join(d, "variant%d.pgm" % k)
        run(octomap_cmd(a.octomap, d, args, om_pgm), "OctoMap (%s) on %s" % (label, name))
        res["variants"][label] = score_file(om_pgm, truth, observable)
    return res


def variant_instructions(a, run_dir, k):
    """Instructions of OctoMap setting k on one run."""
    label, args = VARIANTS[k]
    pgm = os.path.join(run_dir, "variant%d.counted.pgm" % k)
    out = os.path.join(run_dir, "variant%d.callgrind.out" % k)
    return callgrind(octomap_cmd(a.octomap, run_dir, args, pgm), [OCTOMAP_FUNCTION], out,
                     "OctoMap (%s)" % label)


def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs) if xs else float("nan")


def prf(s):
    return "%.3f / %.3f / %.3f" % (s["precision"], s["recall"], s["f1"])


def mean_score(scores):
    scores = list(scores)
    return {k: mean(s[k] for s in scores) for k in ("precision", "recall", "f1")}


def rows_by_room(results, rooms):
    """(label, runs) per room with runs, then all rooms."""
    for room in rooms + ["all"]:
        rs = [r for r in results if room in ("all", r["room"])]
        if rs:
            yield ("**all rooms**" if room == "all" else room), rs


def table(results, rooms):
    """The main table: per room, means over seeds; instructions as totals over readings."""
    lines = ["| room | runs | poses | firmware P / R / F1 | OctoMap P / R / F1 | HIMM P / R / F1 "
             "| firmware's F1 ≥ OctoMap's, HIMM's | firmware instr./reading "
             "| OctoMap instr./reading | OctoMap / firmware |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for label, rs in rows_by_room(results, rooms):
        counted = [r for r in rs if "firmware_ir" in r]
        n = sum(r["readings"] for r in counted)
        ir = "| |"
        if n:
            fw_ir = sum(r["firmware_ir"] for r in counted) / n
            om_ir = sum(r["octomap_ir"] for r in counted) / n
            ir = "%.0f | %.0f | %.0f×" % (fw_ir, om_ir, om_ir / fw_ir)
        for poses, sfx in (("true", ""), ("estimated", "_est")):
            fw, om, hm = "firmware" + sfx, "octomap" + sfx, "himm" + sfx
            wins = [sum(r[fw]["f1"] >= r[k]["f1"] for r in rs) for k in (om, hm)]
            lines.append("| %s | %d | %s | %s | %s | %s | %d, %d of %d | %s |" % (
                label, len(rs), poses, prf(mean_score(r[fw] for r in rs)),
                prf(mean_score(r[om] for r in rs)), prf(mean_score(r[hm] for r in rs)),
                wins[0], wins[1], len(rs), ir if poses == "true" else "| |"))
    return "\n".join(lines)


CSV_COLUMNS = ("room", "seed", "readings", "poses", "mapper", "precision", "recall", "f1",
               "mapped", "true_positive", "observable", "matched", "instructions_per_reading")


def write_csv(path, results):
    """One line per run, poses and mapper; instructions where counted."""
    with open(path, "w") as f:
        f.write(",".join(CSV_COLUMNS) + "\n")
        for r in results:
            for poses, key, mapper in (("true", "firmware", "firmware"),
                                       ("true", "octomap", "octomap"),
                                       ("true", "himm", "himm"),
                                       ("estimated", "firmware_est", "firmware"),
                                       ("estimated", "octomap_est", "octomap"),
                                       ("estimated", "himm_est", "himm")):
                s = r[key]
                ir = r.get(key + "_ir") if poses == "true" else None
                f.write("%s,%d,%d,%s,%s,%.4f,%.4f,%.4f,%d,%d,%d,%d,%s\n" % (
                    r["room"], r["seed"], r["readings"], poses, mapper, s["precision"],
                    s["recall"], s["f1"], s["mapped"], s["true_positive"], s["observable"],
                    s["matched"], "%.1f" % (ir / r["readings"]) if ir is not None else ""))


def variants_table(results, irs):
    fw = mean_score(r["firmware"] for r in results)
    lines = ["| OctoMap setting | P / R / F1 (mean of %d runs) | firmware's F1 ≥ in | "
             "instr./reading (%s) |" % (len(results), irs["run"]),
             "|---|---|---|---|",
             "| *the firmware's mapper* | %s | | %.0f |" % (prf(fw), irs["firmware"])]
    for label, _ in VARIANTS:
        ss = [r["variants"][label] for r in results]
        wins = sum(r["firmware"]["f1"] >= r["variants"][label]["f1"] for r in results)
        lines.append("| %s%s | %s | %d of %d | %s |" % (
            label, " (chosen)" if label == CHOSEN else "", prf(mean_score(ss)), wins,
            len(results), "%.0f" % irs[label] if label in irs else "–"))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rooms", nargs="+", default=sorted(glob.glob(
        os.path.join(SRC, "host_sim", "rooms", "*.room"))))
    ap.add_argument("--seeds", type=parse_seeds, default=parse_seeds("1-10"),
                    help="seeds of every room (default 1-10)")
    ap.add_argument("--generated", type=int, default=0, metavar="N",
                    help="tools/roomgen.py's rooms 1..N, each with its own seed, instead of "
                         "--rooms and --seeds")
    ap.add_argument("--count-all", action="store_true",
                    help="count instructions on every run, not on each room's first seed")
    ap.add_argument("--duration", type=float, default=600.0, help="simulated s a run")
    ap.add_argument("--out", default=os.path.join(SRC, "out", "compare"))
    ap.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1))
    ap.add_argument("--no-variants", action="store_true",
                    help="only the chosen OctoMap setting")
    ap.add_argument("--host-sim", default=os.path.join(SRC, "build", "host", "host_sim", "host_sim"))
    ap.add_argument("--octomap", default=os.path.join(SRC, "build", "compare", "octomap_replay"))
    a = ap.parse_args()
    for path in [a.host_sim, a.octomap] + a.rooms:
        if not os.path.exists(path):
            ap.error("%s does not exist (make compare builds the programs)" % path)
    if shutil.which("valgrind") is None:
        ap.error("valgrind is missing (tools/install-deps.sh compare)")
    if a.jobs < 1 or a.duration <= 0 or a.generated < 0:
        ap.error("--jobs and --duration must be positive, --generated not negative")

    variants = [] if a.no_variants else list(VARIANTS)
    # The runs whose instructions are counted first: they take the longest.
    work = [(room, seed, a.count_all or seed == a.seeds[0]) for room in a.rooms for seed in a.seeds]
    if a.generated:
        gen = os.path.join(a.out, "generated")
        roomgen.write_corpus(gen, a.generated, 0, 1)
        a.rooms = [os.path.join(gen, "room_%d.room" % k) for k in range(1, a.generated + 1)]
        a.seeds = list(range(1, a.generated + 1))
        work = [(room, k, a.count_all or k == 1) for k, room in zip(a.seeds, a.rooms)]
    work.sort(key=lambda w: not w[2])
    print("compare: %d runs (%s), %.0f s each, %d at a time, in %s" % (
        len(work), "generated rooms 1-%d, each with its seed" % a.generated if a.generated
        else "%d rooms x %d seeds" % (len(a.rooms), len(a.seeds)), a.duration, a.jobs, a.out),
        file=sys.stderr)
    lock = threading.Lock()
    done = [0]

    def job(w):
        r = one_run(a, w[0], w[1], variants, w[2])
        with lock:
            done[0] += 1
            ir = ""
            if w[2]:
                ir = "; instructions a reading %.0f and %.0f" % (
                    r["firmware_ir"] / r["readings"], r["octomap_ir"] / r["readings"])
            print("  [%2d/%d] %-10s seed %d: F1 firmware %.3f, OctoMap %.3f, HIMM %.3f%s" % (
                done[0], len(work), r["room"], r["seed"], r["firmware"]["f1"],
                r["octomap"]["f1"], r["himm"]["f1"], ir), file=sys.stderr, flush=True)
        return r

    irs = {}
    with ThreadPoolExecutor(max_workers=a.jobs) as ex:
        results = list(ex.map(job, work))
    results.sort(key=lambda r: (r["room"], r["seed"]))
    if variants:
        first = next(r for r in results if "octomap_ir" in r)
        d = os.path.join(a.out, "%s-%d" % (first["room"], first["seed"]))
        irs = {"run": "%s, seed %d" % (first["room"], first["seed"]),
               "firmware": first["firmware_ir"] / first["readings"],
               CHOSEN: first["octomap_ir"] / first["readings"]}
        print("  counting the instructions of every OctoMap setting on %s" % irs["run"],
              file=sys.stderr, flush=True)
        ks = [k for k, (label, _) in enumerate(VARIANTS) if label != CHOSEN]
        with ThreadPoolExecutor(max_workers=a.jobs) as ex:
            for k, ir in zip(ks, ex.map(lambda k: variant_instructions(a, d, k), ks)):
                irs[VARIANTS[k][0]] = ir / first["readings"]
    # Generated rooms are one group: a row each would be a hundred rows of one run.
    rooms = [] if a.generated else [os.path.splitext(os.path.basename(r))[0] for r in a.rooms]
    with open(os.path.join(a.out, "compare.json"), "w") as f:
        json.dump({"octomap": {"setting": CHOSEN, "args": VARIANTS[0][1]}, "runs": results,
                   "variant_instructions_per_reading": irs, "duration": a.duration,
                   "seeds": a.seeds}, f, indent=1)
    counted = "every run" if a.count_all else \
        "room 1" if a.generated else "seed %d of each room" % a.seeds[0]
    text = ("%.0f s a run, seeds %s; instructions (callgrind, from the true poses) counted "
            "on %s.\nThe scorer reproduced host_sim's metrics.json on all %d runs. OctoMap: "
            "%s.\n\n" % (a.duration, ",".join(map(str, a.seeds)), counted, len(results),
                         CHOSEN)) + table(results, rooms) + "\n"
    if variants:
        text += "\nOctoMap settings tried, from the true poses:\n\n" + \
            variants_table(results, irs) + "\n"
    print("\n" + text, end="")
    with open(os.path.join(a.out, "compare.md"), "w") as f:
        f.write(text)
    write_csv(os.path.join(a.out, "compare.csv"), results)
    print("\nWritten: %s, compare.csv and compare.json beside it" %
          os.path.join(a.out, "compare.md"))
    return 0


if __name__ == "__main__":
    tool_main(main)
