#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Scores pose-correction methods over a run set: each method's poses of every reading are
re-mapped through the firmware's own mapper (host_sim --replay, localize = 0) and scored as
metrics.json scores a map; prints per group mean ± standard error and 5th percentile of
F1, of the gap to the true poses, the pose errors and the closures.

    tools/proto/evaluate.py SET METHOD [METHOD...] [--jobs 2] [--only SUBSTRING]
                            [--set KEY=VALUE ...] [--tag NAME]

METHOD: own (the run's own map, metrics.json), est (its estimated poses re-mapped), odom,
true, oracle_fwd, oracle_rep, oracle_first, oracle_last, oracle_graph, oracle_heading
(tools/proto/oracle.py), lc (tools/proto/loopclose.py), walldir (tools/proto/walldir.py);
--set passes the method's parameters.
Results are cached in out/proto/results/SET/<method>[-tag].json, run by run, and reused
when the parameters match.
"""
import argparse
import json
import math
import os
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import lpcommon as lp


def method_fn(name):
    if name in ("est", "odom", "true"):
        return lambda run, **kw: (getattr(run, name).copy(), {})
    if name.startswith("oracle"):
        import oracle
        return getattr(oracle, name)
    if name == "lc":
        import loopclose
        return loopclose.run_method
    if name == "walldir":
        import walldir
        return walldir.run_method
    raise SystemExit("unknown method %s" % name)


def error_figures(run, pose):
    pe, he = lp.pose_err(pose, run.true)
    bad = (pe > 0.3) | (he > np.radians(5))
    return {"pos_final": float(pe[-1]), "head_final_deg": float(np.degrees(he[-1])),
            "pos_mean": float(pe.mean()), "head_mean_deg": float(np.degrees(he.mean())),
            "bad_share": float(bad.mean())}


def one(args):
    rd, name, params = args
    run = lp.Run(rd["dir"])
    out = {"name": rd["name"], "group": rd["group"], "duration": rd["duration"],
           "area_m2": rd["area_m2"], "f1_true": run.true_f1(), "f1_own": run.own_f1()}
    if name == "own":
        out["f1"] = run.own_f1()
        out.update(error_figures(run, run.est))
        return out
    pose, info = method_fn(name)(run, **params)
    s = run.score(pose)
    out["f1"] = s["f1"]
    out.update(error_figures(run, pose))
    out.update(info)
    return out


def table(results):
    rows = {}
    for r in results:
        for g in lp.groups_of(r):
            rows.setdefault(g, []).append(r)
    print("| group | runs | F1 | F1 p5 | gap | gap p95 | pos final (m) | head final (°) "
          "| bad share | closures acc/ref/wrong |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    order = sorted(rows, key=lambda g: (g.split()[0], g))
    for g in order:
        rs = rows[g]
        f1 = lp.stats(r["f1"] for r in rs)
        gap = lp.stats(r["f1_true"] - r["f1"] for r in rs)
        gp95 = lp.percentile([r["f1_true"] - r["f1"] for r in rs], 95)
        pos = lp.stats(r["pos_final"] for r in rs)
        hd = lp.stats(r["head_final_deg"] for r in rs)
        bad = lp.stats(r["bad_share"] for r in rs)
        cl = "%d/%d/%d" % (sum(r.get("accepted", 0) for r in rs),
                           sum(r.get("refused", 0) for r in rs),
                           sum(r.get("wrong", 0) for r in rs))
        print("| %s | %d | %.3f ± %.3f | %.3f | %.3f ± %.3f | %.3f | %.2f | %.1f | %.2f | %s |" % (
            g, len(rs), f1[0], f1[1] if not math.isnan(f1[1]) else 0, f1[2], gap[0],
            gap[1] if not math.isnan(gap[1]) else 0, gp95, pos[0], hd[0], bad[0], cl))


def save(path, params, cache):
    with open(path + ".tmp", "w") as f:
        json.dump({"params": params, "runs": cache}, f, indent=0)
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("set")
    ap.add_argument("methods", nargs="+")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--set", dest="params", action="append", default=[])
    ap.add_argument("--tag", default="")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args()
    params = {}
    for kv in a.params:
        k, v = kv.split("=", 1)
        params[k] = json.loads(v)
    runs = [r for r in lp.run_dirs(a.set) if a.only in r["name"]]
    os.makedirs(os.path.join(lp.OUT, "results", a.set), exist_ok=True)
    for m in a.methods:
        path = os.path.join(lp.OUT, "results", a.set, m + ("-" + a.tag if a.tag else "") + ".json")
        cache = {}
        if os.path.exists(path):
            with open(path) as f:
                c = json.load(f)
            if c.get("params") == params:
                cache = c["runs"]
        todo = [r for r in runs if r["name"] not in cache]
        with ProcessPoolExecutor(a.jobs) as ex:
            for res in ex.map(one, [(r, m, params) for r in todo]):
                cache[res["name"]] = res
                if not a.quiet:
                    print("%s %s f1 %.3f (est-true gap %.3f) acc %s wrong %s" % (
                        m, res["name"], res["f1"], res["f1_true"] - res["f1"],
                        res.get("accepted", "-"), res.get("wrong", "-")), file=sys.stderr)
                # Saved as it goes: an interrupted evaluation resumes where it stopped.
                save(path, params, cache)
        save(path, params, cache)
        print("\n### %s on %s %s\n" % (m, a.set, json.dumps(params) if params else ""))
        table([cache[r["name"]] for r in runs])


if __name__ == "__main__":
    main()
