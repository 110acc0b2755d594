#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Prints the tables of firmware/experiments_loop_closure.md from the results that
tools/proto/evaluate.py cached (out/proto/results/SET/*.json): per method and group, own
F1 (mean ± SE, 5th percentile), gap to the true poses (mean ± SE, 95th percentile),
closures accepted/refused/wrong; with --integrity the candidate pose-integrity flags of
loopclose.py (hit rate: share of the readings whose held pose is > 0.3 m or > 5° off
that the flag covers; false alarm: share of the others it covers); with --work the
matching work the MCU estimate starts from.

    tools/proto/report.py SET [RESULT ...] [--wide] [--integrity] [--work]

RESULT: a cached file's name without .json (own, est, lc-f2, ...); all when none.
"""
import argparse
import glob
import json
import math
import os

import lpcommon as lp

GROUPS = ("rooms 10 min <=45 m²", "rooms 30 min <=45 m²", "rooms 10 min >45 m²",
          "rooms 30 min >45 m²", "flats", "shipped", "buildings")


def load(setname, names):
    base = os.path.join(lp.OUT, "results", setname)
    if not names:
        names = [os.path.basename(p)[:-5] for p in
                 sorted(glob.glob(os.path.join(base, "*.json")), key=os.path.getmtime)]
    out = []
    for n in names:
        with open(os.path.join(base, n + ".json")) as f:
            c = json.load(f)
        out.append((n, c["params"], list(c["runs"].values())))
    return out


def by_group(runs):
    rows = {}
    for r in runs:
        for g in lp.groups_of(r):
            rows.setdefault(g, []).append(r)
    return rows


def fmt(x, nd=3):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else "%.*f" % (nd, x)


def scores(results):
    print("| method | group | runs | own F1 | F1 p5 | gap | gap p95 | acc/ref/wrong |")
    print("|---|---|---|---|---|---|---|---|")
    for name, params, runs in results:
        rows = by_group(runs)
        for g in GROUPS:
            rs = rows.get(g)
            if not rs:
                continue
            f1 = lp.stats(r["f1"] for r in rs)
            gap = lp.stats(r["f1_true"] - r["f1"] for r in rs)
            gp95 = lp.percentile([r["f1_true"] - r["f1"] for r in rs], 95)
            cl = "%d/%d/%d" % tuple(sum(r.get(k, 0) for r in rs)
                                    for k in ("accepted", "refused", "wrong")) \
                if any("accepted" in r for r in rs) else "–"
            print("| %s | %s | %d | %s ± %s | %s | %s ± %s | %s | %s |" % (
                name, g, len(rs), fmt(f1[0]), fmt(f1[1]), fmt(f1[2]), fmt(gap[0]),
                fmt(gap[1]), fmt(gp95), cl))


def wide(results):
    """One row a method, one column a group: own F1 mean ± SE (p5) / gap mean ± SE, and
    the closures accepted/refused/wrong over all its runs."""
    print("| method | " + " | ".join(GROUPS) + " | acc/ref/wrong |")
    print("|---|" + "---|" * (len(GROUPS) + 1))
    for name, params, runs in results:
        rows = by_group(runs)
        cells = []
        for g in GROUPS:
            rs = rows.get(g)
            if not rs:
                cells.append("")
                continue
            f1 = lp.stats(r["f1"] for r in rs)
            gap = lp.stats(r["f1_true"] - r["f1"] for r in rs)
            cells.append("%s ± %s (%s) / %s ± %s" % (fmt(f1[0]), fmt(f1[1]), fmt(f1[2]),
                                                    fmt(gap[0]), fmt(gap[1])))
        cl = "%d/%d/%d" % tuple(sum(r.get(k, 0) for r in runs)
                                for k in ("accepted", "refused", "wrong")) \
            if any("accepted" in r for r in runs) else "–"
        print("| %s | %s | %s |" % (name, " | ".join(cells), cl))


def integrity(results):
    print("| method | group | flag | hit rate | false alarm | readings bad |")
    print("|---|---|---|---|---|---|")
    for name, params, runs in results:
        if not any("integrity" in r for r in runs):
            continue
        rows = by_group(runs)
        for g in GROUPS:
            rs = [r for r in rows.get(g, []) if "integrity" in r]
            if not rs:
                continue
            bad = sum(r["integrity"]["bad"] for r in rs)
            good = sum(r["integrity"]["good"] for r in rs)
            for k in rs[0]["integrity"]:
                if k in ("bad", "good"):
                    continue
                h = sum(r["integrity"][k][0] for r in rs)
                fa = sum(r["integrity"][k][1] for r in rs)
                print("| %s | %s | %s | %s | %s | %.3f |" % (
                    name, g, k, fmt(h / bad if bad else math.nan, 2),
                    fmt(fa / good if good else math.nan, 2), bad / max(bad + good, 1)))


def work(results):
    print("| method | group | runs | segments a run (max) | match attempts a run | "
          "field reads an attempt | fields an attempt |")
    print("|---|---|---|---|---|---|---|")
    for name, params, runs in results:
        if not any("lookups" in r for r in runs):
            continue
        rows = by_group(runs)
        for g in GROUPS:
            rs = [r for r in rows.get(g, []) if "lookups" in r]
            if not rs:
                continue
            att = sum(r["attempts"] for r in rs)
            print("| %s | %s | %d | %.0f (%d) | %.0f | %.3g | %.2f |" % (
                name, g, len(rs), sum(r["segments"] for r in rs) / len(rs),
                max(r["segments"] for r in rs), att / len(rs),
                sum(r["lookups"] for r in rs) / max(att, 1),
                sum(r["fields"] for r in rs) / max(att, 1)))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("set")
    ap.add_argument("results", nargs="*")
    ap.add_argument("--integrity", action="store_true")
    ap.add_argument("--work", action="store_true")
    ap.add_argument("--wide", action="store_true", help="one row a method")
    a = ap.parse_args()
    res = load(a.set, a.results)
    (wide if a.wide else scores)(res)
    if a.integrity:
        print()
        integrity(res)
    if a.work:
        print()
        work(res)


if __name__ == "__main__":
    main()
