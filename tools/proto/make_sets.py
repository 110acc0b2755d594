#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Makes the runs the loop-closure prototypes work on: a development set and a held-out
set of other seeds (lpcommon.SETS), each run with --scoring so that its log, the
firmware's own pose estimate and the scoring masks are kept.

    tools/proto/make_sets.py dev|held [--jobs 2]

Runs go to out/proto/<set>/<name>/ with runs.json listing them; a run whose folder
already holds metrics.json is not run again. Build host_sim first
(cmake --preset host && cmake --build --preset host -j2 --target host_sim).
"""
import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import lpcommon as lp


def plan(setname):
    base = os.path.join(lp.OUT, setname)
    gen = os.path.join(base, "rooms")
    os.makedirs(gen, exist_ok=True)
    area = {}
    for group, dur, kind, seeds in lp.SETS[setname]:
        if kind in ("room", "flat"):
            subprocess.run([os.path.join(lp.TOOLS, "roomgen.py"), "corpus",
                            "--rooms" if kind == "room" else "--flats", str(len(seeds)),
                            "--flats" if kind == "room" else "--rooms", "0",
                            "--first-seed", str(seeds[0]), "--out", gen], check=True)
            with open(os.path.join(gen, "index.json")) as f:
                area.update({e["file"]: e["area_m2"] for e in json.load(f)["files"]})
    jobs = []
    for group, dur, kind, seeds in lp.SETS[setname]:
        for seed in seeds:
            if kind in ("room", "flat"):
                path = os.path.join(gen, "%s_%d.room" % (kind, seed))
                jobs.append({"name": "%s-%d-%s%d" % (group, dur, kind, seed), "group": group,
                             "duration": dur, "area_m2": area[os.path.basename(path)],
                             "args": ["--room", path, "--seed", str(seed)]})
            elif kind == "shipped":
                for room in lp.SHIPPED:
                    jobs.append({"name": "shipped-%s-%d" % (room, seed), "group": group,
                                 "duration": dur, "area_m2": None, "args": [
                                     "--room", os.path.join(lp.SRC, "host_sim", "rooms",
                                                            room + ".room"),
                                     "--seed", str(seed)]})
            else:
                for name, yaml, crop in lp.BUILDINGS:
                    a = ["--room", os.path.join(lp.MAPS, yaml), "--seed", str(seed)]
                    if crop:
                        a += ["--crop"] + ["%g" % v for v in crop]
                    jobs.append({"name": "building-%s-%d" % (name, seed), "group": group,
                                 "duration": dur, "area_m2": None, "args": a})
    for j in jobs:
        j["args"] += ["--duration", str(j["duration"])]
    return base, jobs


def run(base, j):
    out = os.path.join(base, j["name"])
    if os.path.exists(os.path.join(out, "metrics.json")):
        return 0
    p = subprocess.run([lp.HOST_SIM, "--quiet", "--no-plot", "--scoring", "--out", out] +
                       j["args"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode:
        print("%s: exit %d %s" % (j["name"], p.returncode, p.stderr), file=sys.stderr)
    return p.returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("set", choices=sorted(lp.SETS))
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    base, jobs = plan(a.set)
    with ThreadPoolExecutor(a.jobs) as ex:
        rcs = list(ex.map(lambda j: run(base, j), sorted(jobs, key=lambda j: -j["duration"])))
    ok = [j for j, rc in zip(sorted(jobs, key=lambda j: -j["duration"]), rcs) if rc == 0]
    with open(os.path.join(base, "runs.json"), "w") as f:
        json.dump([{k: v for k, v in j.items()} for j in ok], f, indent=1)
    print("%s: %d of %d runs" % (a.set, len(ok), len(jobs)))
    return 0 if len(ok) == len(jobs) else 1


if __name__ == "__main__":
    sys.exit(main())
