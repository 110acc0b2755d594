#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Pose-integrity flags from the firmware's own statistics, scored against the truth.
scoring_estimate.csv holds, for every reading, what the pose correction knew once it had
processed that reading: the covariance of its correction over x, y, θ, its match counters
(tried, applied, refused), the wall measurements of the last match and the increment that
match wanted. Every statistic below uses only those rows up to the reading (causal):

- sth: σθ, the covariance's heading deviation (°);
- sxy: √(σx² + σy²) (m);
- path / time: metres of the estimated path / seconds since the last applied match;
- refused N: share of the last N matches refused (both kinds);
- blind N: share of the last N matches refused for too few walls (< LOC_MIN_POINTS);
- big N: share of the last N matches refused for too large a step (enough walls);
- nis N: mean over the last N matches of the step each wanted, applied or refused,
  against the covariance the match ran on (dᵀ P⁻¹ d over x, y, θ; P is the row before
  the match's, one reading's growth short of its prior), a normalised innovation squared;
- nismax N: the largest of those over the last N matches;
- nth N: the mean of the heading's part alone, dθ² / σθ².

A flag is "statistic over a threshold"; combinations are two flags or'ed. Scored per
reading as the issue defines it: off = the estimated pose is > 0.3 m or > 5° from the
truth; hit rate = share of the off readings flagged (goal ≥ 0.90), false alarm = share of
the others flagged (goal ≤ 0.05). Groups: shipped rooms, generated rooms at 10 and 30
min, flats, buildings.

Thresholds are tuned on the tuning set (dev) and applied unchanged to the reporting set:

- one rule for every group: the threshold with the largest hit rate at a false alarm
  ≤ 0.05 over all readings pooled, and the one with the largest hit rate less false alarm;
- a rule per group: the same, the group's own readings only.

    tools/proto/integrity_fw.py [--tune dev] [--report held] [--only SUBSTRING]
    tools/proto/integrity_fw.py --runs SET [--only SUBSTRING]   (one line a run)

Runs come from tools/proto/make_sets.py SET (host_sim --scoring).
"""
import argparse
import math
import os

import numpy as np

import lpcommon as lp

LOC_MIN_POINTS = 10  # firmware/src/localize/loc_match.h
WINDOWS = (4, 8, 16, 32)  # matches
GROUPS = ("shipped", "rooms 10 min", "rooms 30 min", "flats", "buildings")
FA_GOAL = 0.05
HIT_GOAL = 0.90


def group_of(rd):
    if rd["group"] == "rooms":
        return "rooms %d min" % (rd["duration"] // 60)
    return rd["group"]


def load(d):
    """A run's estimate log (every column by name) and the true pose of every reading."""
    with open(os.path.join(d, "scoring_estimate.csv")) as f:
        cols = f.readline().strip().split(",")
    est = np.loadtxt(os.path.join(d, "scoring_estimate.csv"), delimiter=",", skiprows=1,
                     ndmin=2)
    with open(os.path.join(d, "readings.csv")) as f:
        rcols = f.readline().strip().split(",")
    true = np.loadtxt(os.path.join(d, "readings.csv"), delimiter=",", skiprows=1, ndmin=2,
                      usecols=[rcols.index(k) for k in ("true_x_m", "true_y_m", "true_th_rad")])
    assert est.shape[0] == true.shape[0], d
    return {c: est[:, i] for i, c in enumerate(cols)}, true


def window_share(event_cum, k, n):
    """Per reading, the share of the last n matches (k matches so far) an event took: the
    event's count after each match is event_cum (index = match number)."""
    j = np.maximum(k - n, 0)
    got = event_cum[k] - event_cum[j]
    return np.where(k >= n, got / n, np.nan)


def statistics(e, true):
    """The candidate statistics per reading (larger = more doubt), and the truth's off."""
    n = e["t_s"].shape[0]
    out = {}
    out["sth"] = np.degrees(np.sqrt(e["cov_thth_urad2"]) * 1e-6)
    out["sxy"] = np.sqrt(e["cov_xx_um2"] + e["cov_yy_um2"]) * 1e-6
    pose = np.stack([e["est_x_m"], e["est_y_m"], e["est_th_rad"]], axis=1)
    path = np.r_[0.0, np.cumsum(np.hypot(np.diff(pose[:, 0]), np.diff(pose[:, 1])))]
    applied = e["match_applied"].astype(np.int64)
    tried = e["match_tried"].astype(np.int64)
    refused = e["match_refused"].astype(np.int64)
    # The reading of the last applied match (before any, the start).
    new_app = np.r_[False, np.diff(applied) > 0]
    last = np.maximum.accumulate(np.where(new_app, np.arange(n), 0))
    out["path"] = path - path[last]
    out["time"] = e["t_s"] - e["t_s"][last]
    # Each match: the reading it ran in (one reading brings at most one hit, so at most
    # one match), whether it was refused, for too few walls or for too large a step, and
    # its normalised step.
    rows = np.nonzero(np.r_[tried[0] > 0, np.diff(tried) > 0])[0]
    m = rows.shape[0]
    was_ref = np.r_[refused[0] > 0, np.diff(refused) > 0][rows]
    blind = was_ref & (e["match_points"][rows] < LOC_MIN_POINTS)
    big = was_ref & ~blind
    d = np.stack([e["step_x_m"][rows] * 1e6, e["step_y_m"][rows] * 1e6,
                  e["step_th_rad"][rows] * 1e6], axis=1)
    prev = np.maximum(rows - 1, 0)
    P = np.empty((m, 3, 3))
    P[:, 0, 0] = e["cov_xx_um2"][prev]
    P[:, 0, 1] = P[:, 1, 0] = e["cov_xy_um2"][prev]
    P[:, 1, 1] = e["cov_yy_um2"][prev]
    P[:, 0, 2] = P[:, 2, 0] = e["cov_xth_um_urad"][prev]
    P[:, 1, 2] = P[:, 2, 1] = e["cov_yth_um_urad"][prev]
    P[:, 2, 2] = e["cov_thth_urad2"][prev]
    nis = np.einsum("mi,mi->m", d, np.linalg.solve(P, d[:, :, None])[:, :, 0]) if m else \
        np.zeros(0)
    nth = d[:, 2] ** 2 / P[:, 2, 2]
    # Matches so far at each reading, and the cumulative counts by match number.
    k = np.searchsorted(rows, np.arange(n), side="right")
    cum = lambda x: np.r_[0.0, np.cumsum(x.astype(float))]  # noqa: E731
    c_ref, c_blind, c_big, c_nis = cum(was_ref), cum(blind), cum(big), cum(nis)
    c_nth = cum(nth)
    for w in WINDOWS:
        out["refused %d" % w] = window_share(c_ref, k, w)
        out["blind %d" % w] = window_share(c_blind, k, w)
        out["big %d" % w] = window_share(c_big, k, w)
        out["nis %d" % w] = window_share(c_nis, k, w)
        out["nth %d" % w] = window_share(c_nth, k, w)
        # The largest of the last w: a running maximum over a sliding window of matches.
        if m >= w:
            mx = np.lib.stride_tricks.sliding_window_view(nis, w).max(axis=1)
            by_k = np.r_[np.full(w, np.nan), mx]  # by_k[k]: matches k-w .. k-1
        else:
            by_k = np.full(m + 1, np.nan)
        out["nismax %d" % w] = by_k[k]
    pe, he = lp.pose_err(pose, true)
    off = (pe > 0.3) | (he > math.radians(5))
    return out, off


def collect(setname, only):
    """Per group: the statistics of every reading, concatenated, and off."""
    acc = {}
    for rd in lp.run_dirs(setname):
        if only not in rd["name"]:
            continue
        e, true = load(rd["dir"])
        st, off = statistics(e, true)
        g = acc.setdefault(group_of(rd), {"off": [], "st": {}})
        g["off"].append(off)
        for k, v in st.items():
            g["st"].setdefault(k, []).append(v.astype(np.float32))
    out = {}
    for g, t in acc.items():
        out[g] = {"off": np.concatenate(t["off"]),
                  "st": {k: np.concatenate(v) for k, v in t["st"].items()}}
    return out


def pooled(data, groups):
    gs = [g for g in groups if g in data]
    return {"off": np.concatenate([data[g]["off"] for g in gs]),
            "st": {k: np.concatenate([data[g]["st"][k] for g in gs])
                   for k in data[gs[0]]["st"]}}


def rates(flag, off):
    """(hit rate, false alarm) of a boolean flag; NaN statistics never flag."""
    h = flag[off].mean() if off.any() else math.nan
    fa = flag[~off].mean() if (~off).any() else math.nan
    return h, fa


def flag_of(st, rule):
    """A rule is ((statistic, threshold), ...), or'ed."""
    f = np.zeros(next(iter(st.values())).shape[0], dtype=bool)
    for k, t in rule:
        f |= np.nan_to_num(st[k], nan=-np.inf) > t
    return f


def thresholds(v):
    v = v[np.isfinite(v)]
    if v.size == 0:
        return np.zeros(0)
    return np.unique(np.quantile(v, np.linspace(0.0, 0.999, 400)))


def curve(v, off, ts):
    """Hit rate and false alarm of 'v > t' for every t of ts, at once."""
    v = np.nan_to_num(v, nan=-np.inf)
    on = np.sort(v[off])
    other = np.sort(v[~off])
    hit = 1.0 - np.searchsorted(on, ts, side="right") / max(on.size, 1)
    fa = 1.0 - np.searchsorted(other, ts, side="right") / max(other.size, 1)
    return hit, fa


def tune(d):
    """Per statistic: the threshold of the largest hit at FA <= 0.05 ('fa5') and of the
    largest hit less false alarm ('youden')."""
    best = {}
    for k, v in d["st"].items():
        ts = thresholds(v)
        if ts.size == 0 or not d["off"].any():
            continue
        hit, fa = curve(v, d["off"], ts)
        ok = fa <= FA_GOAL
        i5 = int(np.argmax(np.where(ok, hit, -1.0))) if ok.any() else None
        iy = int(np.argmax(hit - fa))
        best[k] = {"fa5": (float(ts[i5]), hit[i5], fa[i5]) if i5 is not None else None,
                   "youden": (float(ts[iy]), hit[iy], fa[iy])}
    return best


def combos(d, best, how, top=6):
    """Two single flags or'ed, over the top singles of the tuning data: each pair with its
    own thresholds, the pair's thresholds searched over the singles' curves (coarsely)."""
    singles = sorted((k for k in best if best[k][how] is not None),
                     key=lambda k: -(best[k][how][1] - best[k][how][2]))
    fam = []
    for k in singles:  # one of a family (its best window)
        f = k.split()[0]
        if f not in [x.split()[0] for x in fam]:
            fam.append(k)
    fam = fam[:top]
    out = []
    for i, a in enumerate(fam):
        for b in fam[i + 1:]:
            ta = thresholds(d["st"][a])[::20]
            tb = thresholds(d["st"][b])[::20]
            fa_ = np.nan_to_num(d["st"][a], nan=-np.inf)
            fb_ = np.nan_to_num(d["st"][b], nan=-np.inf)
            res = None
            for x in ta:
                fx = fa_ > x
                for y in tb:
                    h, fa = rates(fx | (fb_ > y), d["off"])
                    score = h if how == "fa5" else h - fa
                    if how == "fa5" and fa > FA_GOAL:
                        continue
                    if res is None or score > res[0]:
                        res = (score, ((a, float(x)), (b, float(y))), h, fa)
            if res is not None:
                out.append(res)
    out.sort(key=lambda r: -r[0])
    return [(r[1], r[2], r[3]) for r in out[:3]]


def rule_name(rule):
    units = {"sth": "°", "sxy": " m", "path": " m", "time": " s"}
    return " or ".join("%s > %s%s" % (k, ("%.3g" % t), units.get(k, "")) for k, t in rule)


def cell(h, fa):
    """hit / false alarm; a dash where the group has no off reading."""
    mark = " ✓" if h >= HIT_GOAL and fa <= FA_GOAL else ""
    return ("—" if math.isnan(h) else "%.2f" % h) + " / %.2f%s" % (fa, mark)


def table(title, rules, data_sets):
    print("\n%s\n" % title)
    hdr = "| rule | set |" + "".join(" %s |" % g for g in GROUPS) + " all |"
    print(hdr)
    print("|" + "---|" * (len(GROUPS) + 3))
    for rule in rules:
        for sname, data in data_sets:
            cells = []
            for g in GROUPS + ("all",):
                d = pooled(data, GROUPS) if g == "all" else data.get(g)
                if d is None:
                    cells.append("")
                    continue
                cells.append(cell(*rates(flag_of(d["st"], rule), d["off"])))
            print("| %s | %s |" % (rule_name(rule), sname) + "".join(" %s |" % c for c in cells))


def per_run(setname, only):
    """One line a run: how much of it is off, how far, and what the filter believed."""
    print("| run | share off | heading error when off, median (°) | position error when off, "
          "median (m) | σθ off / not (°) | σxy off / not (m) |")
    print("|---|---|---|---|---|---|")
    for rd in lp.run_dirs(setname):
        if only not in rd["name"]:
            continue
        e, true = load(rd["dir"])
        st, off = statistics(e, true)
        pose = np.stack([e["est_x_m"], e["est_y_m"], e["est_th_rad"]], axis=1)
        pe, he = lp.pose_err(pose, true)
        med = lambda v, m: np.median(v[m]) if m.any() else math.nan  # noqa: E731
        print("| %s | %.2f | %.1f | %.2f | %.2f / %.2f | %.3f / %.3f |" % (
            rd["name"], off.mean(), math.degrees(med(he, off)), med(pe, off),
            med(st["sth"], off), med(st["sth"], ~off), med(st["sxy"], off),
            med(st["sxy"], ~off)))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tune", default="dev")
    ap.add_argument("--report", default="held")
    ap.add_argument("--only", default="")
    ap.add_argument("--runs", metavar="SET")
    a = ap.parse_args()
    if a.runs:
        per_run(a.runs, a.only)
        return
    dev = collect(a.tune, a.only)
    held = collect(a.report, a.only)
    sets = [(a.tune, dev), (a.report, held)]
    print("| set | share of readings off |" + "".join(" %s |" % g for g in GROUPS) + " all |")
    print("|" + "---|" * (len(GROUPS) + 2))
    for sname, data in sets:
        cells = ["%.3f (%d)" % (data[g]["off"].mean(), data[g]["off"].size) if g in data
                 else "" for g in GROUPS]
        allp = pooled(data, GROUPS)["off"]
        print("| %s | off |" % sname + "".join(" %s |" % c for c in cells) +
              " %.3f (%d) |" % (allp.mean(), allp.size))

    # Does the filter's doubt go with the truth's at all? The medians, off against not.
    keys = ("sth", "sxy", "time", "refused 32", "nis 16")
    print("\nMedians of the statistics over the off readings / the others\n")
    print("| set | group |" + "".join(" %s |" % k for k in keys))
    print("|" + "---|" * (len(keys) + 2))
    for sname, data in sets:
        for g in GROUPS:
            if g not in data or not data[g]["off"].any():
                continue
            off = data[g]["off"]
            cells = ["%.3g / %.3g" % (np.nanmedian(data[g]["st"][k][off]),
                                      np.nanmedian(data[g]["st"][k][~off])) for k in keys]
            print("| %s | %s |" % (sname, g) + "".join(" %s |" % c for c in cells))

    # One rule for every group, tuned on the tuning set's pooled readings.
    allb = tune(pooled(dev, GROUPS))
    for how, label in (("fa5", "largest hit at false alarm ≤ 0.05"),
                       ("youden", "largest hit less false alarm")):
        singles = sorted((k for k in allb if allb[k][how] is not None),
                         key=lambda k: -(allb[k][how][1] - allb[k][how][2]))
        rules = []
        seen = set()
        for k in singles:
            if allb[k][how][1] < 0.02:
                continue  # flags (almost) nothing: no rule
            if k.split()[0] not in seen:
                seen.add(k.split()[0])
                rules.append(((k, allb[k][how][0]),))
        rules += [r for r, _, _ in combos(pooled(dev, GROUPS), allb, how)]
        table("One rule for every group, tuned on %s pooled (%s); hit / false alarm, ✓ = "
              "goal met" % (a.tune, label), rules, sets)

    # A rule per group, each tuned on the group's own readings of the tuning set.
    print("\nA rule per group, tuned on %s (the group's readings): the best three of "
          "hit less false alarm, and the best at false alarm ≤ 0.05\n" % a.tune)
    print("| group | rule | %s hit / false | %s hit / false |" % (a.tune, a.report))
    print("|---|---|---|---|")
    for g in GROUPS:
        if g not in dev or not dev[g]["off"].any():
            continue
        b = tune(dev[g])
        top = sorted(b, key=lambda k: -(b[k]["youden"][1] - b[k]["youden"][2]))[:3]
        rules = [((k, b[k]["youden"][0]),) for k in top]
        ok = [k for k in b if b[k]["fa5"] is not None]
        if ok:
            k = max(ok, key=lambda k: b[k]["fa5"][1])
            rules.append(((k, b[k]["fa5"][0]),))
        rules += [r for r, _, _ in combos(dev[g], b, "fa5")[:1]]
        for rule in rules:
            cells = []
            for data in (dev, held):
                if g not in data:
                    cells.append("")
                    continue
                cells.append(cell(*rates(flag_of(data[g]["st"], rule), data[g]["off"])))
            print("| %s | %s | %s | %s |" % (g, rule_name(rule), cells[0], cells[1]))


if __name__ == "__main__":
    main()
