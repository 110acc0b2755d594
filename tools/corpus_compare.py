#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Two builds over the same corpus runs, run by run: what a change moved, and whether it is
a change.

usage: tools/corpus_compare.py BEFORE AFTER [BEFORE AFTER]... [--json FILE]

BEFORE and AFTER are what tools/corpus_report.py wrote for two builds (its corpus.json, or
the --out folder that holds it) over the same runs: the same arguments but --host-sim (or
--host-arg). Each pair is one draw; give the usual corpus and a fresh draw (--shift-start,
other seeds) as two pairs. Runs are paired by name; a run that either build did not score
is left out and counted.

For each draw, one Markdown table: a row for every group and duration (shipped rooms,
generated rooms at each duration, flats, building maps), with the runs paired, own-pose
raw F1 before (mean ± its standard error), and the paired change after − before (mean ±
its standard error) of own-pose F1, of the gap to the true poses' F1 and of wall
coverage; then before → after for the runs that touch, the runs with a touch left in more
than 5 s (issue 29's goal), the runs 30 s or more without progress, the longest time
without progress, and the escapes (SLOW_S and STUCK_S of tools/corpus_report.py).

A figure of a group has changed when its mean change lies outside the group's standard
error before the change (host_sim/README.md's rule), on every draw, in the same direction.
The last lines name every such figure, or say that none moved. --json FILE writes every
table's figures and the verdict. Exit status: 0 done, 2 bad input (a file that is not a
corpus report, an odd count of reports, a pair that shares no scored run).
"""
import argparse
import json
import math
import os
import statistics

import corpus_report as cr
from slamtools.errors import ToolError, main as tool_main
from slamtools.runs import std_error

CHANGES = (("f1", "own-pose F1"), ("gap", "gap"), ("wall_coverage", "wall coverage"))
NEEDED = ("name", "group", "duration_s", "status")


def load(path):
    """The runs of one corpus report: {name: run}."""
    if os.path.isdir(path):
        path = os.path.join(path, "corpus.json")
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as e:
        raise ToolError("cannot read %s: %s" % (path, e.strerror or e)) from None
    except (ValueError, UnicodeDecodeError) as e:
        raise ToolError("%s is not JSON: %s" % (path, e)) from None
    runs = data.get("runs") if isinstance(data, dict) else None
    if not isinstance(runs, list) or not all(
            isinstance(r, dict) and all(k in r for k in NEEDED) for r in runs):
        raise ToolError("%s is not a corpus report of tools/corpus_report.py (no list of runs "
                        "with %s)" % (path, ", ".join(NEEDED)))
    return {r["name"]: r for r in runs}


def scored(r):
    return r["status"] == "ok" and isinstance(r.get("f1"), (int, float))


def mean_se(xs):
    return {"mean": statistics.mean(xs) if xs else math.nan, "se": std_error(xs)}


def counts(runs):
    """Before or after: the runs that touch, left in slowly, stuck; the longest time without
    progress; the escapes (None where a report predates them)."""
    escapes = [r.get("escapes") for r in runs]
    slow = None if any("recovery_s" not in r for r in runs) else \
        sum(1 for r in runs if (r["recovery_s"] or 0.0) > cr.SLOW_S)
    return {"touching": sum(1 for r in runs if r.get("touches", 0) > 0),
            "slow": slow,
            "stuck": sum(1 for r in runs if r.get("stuck_s", 0.0) >= cr.STUCK_S),
            "longest_s": max((r.get("stuck_s", 0.0) for r in runs), default=math.nan),
            "escapes": None if None in escapes else sum(escapes)}


def compare(before, after):
    """One draw: {(group, duration): figures} over the runs both builds scored, and how many
    runs were left out."""
    pairs, left_out = {}, 0
    for name, b in before.items():
        a = after.get(name)
        if a is None or not scored(b) or not scored(a):
            left_out += 1
            continue
        pairs.setdefault((b["group"], b["duration_s"]), []).append((b, a))
    left_out += sum(1 for name in after if name not in before)
    if not pairs:
        raise ToolError("the two reports share no run both scored: were they made with the "
                        "same arguments?")
    out = {}
    order = {g: i for i, g in enumerate(cr.GROUPS)}
    for key in sorted(pairs, key=lambda k: (order.get(k[0], len(order)), k[0], k[1])):
        ps = pairs[key]
        fig = {"runs": len(ps), "f1_before": mean_se([b["f1"] for b, _ in ps])}
        for k, _ in CHANGES:
            both = [(b[k], a[k]) for b, a in ps
                    if isinstance(b.get(k), (int, float)) and isinstance(a.get(k), (int, float))]
            fig[k] = {"before_se": std_error([x for x, _ in both]),
                      **mean_se([y - x for x, y in both])}
        fig["before"] = counts([b for b, _ in ps])
        fig["after"] = counts([a for _, a in ps])
        out[key] = fig
    return out, left_out


def label(key):
    group, duration = key
    return "%s, %s" % (cr.TITLES[group][0] if group in cr.TITLES else group,
                       cr.minutes(duration))


def pm(s, fmt):
    if math.isnan(s["mean"]):
        return "–"
    return (fmt + " ± " + fmt.replace("+", "")) % (s["mean"], s["se"])


def arrow(fig, k, fmt="%d"):
    b, a = fig["before"][k], fig["after"][k]
    if b is None or a is None or (isinstance(b, float) and math.isnan(b)):
        return "–"
    return (fmt + " → " + fmt) % (b, a)


HEAD = ("| group | runs | F1 own pose before | F1 change | gap change | wall coverage change "
        "| touching runs | touches left in over 5 s | runs stuck 30 s | longest without "
        "progress (s) | escapes |\n|---|---|---|---|---|---|---|---|---|---|---|")


def table(draw):
    lines = [HEAD]
    for key, fig in draw.items():
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            label(key), fig["runs"], pm(fig["f1_before"], "%.3f"), pm(fig["f1"], "%+.4f"),
            pm(fig["gap"], "%+.4f"), pm(fig["wall_coverage"], "%+.4f"),
            arrow(fig, "touching"), arrow(fig, "slow"), arrow(fig, "stuck"),
            arrow(fig, "longest_s", "%.0f"), arrow(fig, "escapes")))
    return "\n".join(lines)


def changed(draws):
    """The figures whose mean change lies outside the group's standard error before, on
    every draw, in one direction: [(key, figure, [changes])]; and the groups that are not
    in every draw, left unjudged."""
    out = []
    keys = [k for k in draws[0] if all(k in d for d in draws)]
    unjudged = sorted({k for d in draws for k in d} - set(keys))
    for key in keys:
        for k, _ in CHANGES:
            moves = [d[key][k]["mean"] for d in draws]
            ses = [d[key][k]["before_se"] for d in draws]
            if any(math.isnan(m) or math.isnan(s) for m, s in zip(moves, ses)):
                continue
            if all(abs(m) > s for m, s in zip(moves, ses)) and \
                    (all(m > 0 for m in moves) or all(m < 0 for m in moves)):
                out.append((key, k, moves))
    return out, unjudged


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("reports", nargs="+", metavar="BEFORE AFTER")
    ap.add_argument("--json", metavar="FILE", help="write the figures and the verdict here")
    args = ap.parse_args()
    if len(args.reports) % 2:
        ap.error("reports come in pairs, BEFORE AFTER: %d given" % len(args.reports))
    draws = []
    for i in range(0, len(args.reports), 2):
        before, after = args.reports[i], args.reports[i + 1]
        draw, left_out = compare(load(before), load(after))
        draws.append(draw)
        print("### Draw %d: %s → %s\n" % (i // 2 + 1, before, after))
        print(table(draw))
        if left_out:
            print("\n%d runs left out: not in both reports, or not scored by both." % left_out)
        print()
    moved, unjudged = changed(draws)
    names = dict(CHANGES)
    if moved:
        print("Changed on every draw (outside the group's standard error, one direction):")
        for key, k, moves in moved:
            print("- %s: %s %s" % (label(key), names[k],
                                   ", ".join("%+.4f" % m for m in moves)))
    else:
        print("No group's own-pose F1, gap or wall coverage moved outside its standard error "
              "on every draw.")
    if unjudged:
        print("Not judged, not in every draw: %s." % ", ".join(label(k) for k in unjudged))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(cr.no_nan({"draws": [[{"group": k[0], "duration_s": k[1], **fig}
                                             for k, fig in d.items()] for d in draws],
                                  "changed": [{"group": k[0], "duration_s": k[1],
                                               "figure": f, "changes": m}
                                              for k, f, m in moved]}),
                      f, indent=1, allow_nan=False)
    return 0


if __name__ == "__main__":
    tool_main(main)
