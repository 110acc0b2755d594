#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Loop closure on a run's log, causal: what the robot could have done as it went.

The firmware's own estimate (scoring_estimate.csv, with its Kalman wall matching) is the
odometry of this method. The path is cut into segments of `seg_hits` hits; a segment is
moved as one rigid piece by a correction C (map = C ∘ estimate). At the end of every
segment:

1. the scan: the hits of the last `scan_segs` segments (and, with `far_max`, echoes beyond
   rc up to that range, for matching only), placed with their segments' corrections;
2. the reference: the hits of the segments that ended at least `min_age` seconds before
   the scan began, as a likelihood field (Gaussian of the distance to the nearest cell
   holding `ref_min` hits, σ `field_sigma`);
3. a revisit: at least `overlap` of the scan's points lie within `overlap_m` of the
   reference; otherwise nothing is tried;
4. a correlative search of the scan's pose over ±window (the pose's uncertainty since the
   loop's start: `gate_xy0` + `gate_xy1`·√d metres, `gate_th0` + `gate_th1`·√d degrees,
   d the path since then, clipped to `max_xy`, `max_th`), coarse then fine, rotating about
   the robot;
5. gates: the best mean field value at least `min_score` and above the uncorrected pose's
   by `min_gain`; the peak sharp (the score-weighted spread of the pose `max_spread_m`,
   `max_spread_deg`); the step outside a dead band (`dead_m`, `dead_deg`), else nothing to do;
6. confirmation: the next attempt, within `confirm_within` segments, finds the same step
   within `agree_m`/`agree_deg` (`confirm` = 0 applies the first);
7. the correction: the loop runs from the later of the last closure and the youngest
   reference segment the scan matched, to now; the heading step is spread along it by path
   length, then the remaining shift (`spread` = "path"; "none": only from now on).

Every reading's final pose is its segment's final correction ∘ its estimate; the pose
the robot held then (for counting wrong closures and for the integrity flag) is the
correction of that moment ∘ its estimate.

    tools/proto/evaluate.py dev lc [--set key=value ...]
    tools/proto/loopclose.py RUN_DIR [key=value ...]   # one run, with the closures listed
"""
import math
import sys

import numpy as np
from scipy import ndimage

import lpcommon as lp

DEFAULTS = dict(
    seg_hits=32, scan_segs=6, min_age=60.0, far_max=0.0,
    field_sigma=0.06, ref_min=1,
    overlap=0.5, overlap_m=0.3,
    gate_xy0=0.10, gate_xy1=0.04, gate_th0=1.5, gate_th1=0.4, max_xy=0.5, max_th=8.0,
    min_score=0.45, min_gain=0.05, max_spread_m=0.06, max_spread_deg=1.5,
    dead_m=0.0, dead_deg=0.0,
    confirm=1, confirm_within=2, agree_m=0.06, agree_deg=1.0,
    spread="path", min_pts=60, ref_truth=0, u_margin=-1.0, u_frac=1.0, u_close=1.0,
    coarse_xy=0.05, coarse_th=1.0, fine_xy=0.0125, fine_th=0.25,
    wrong_m=0.05, wrong_deg=1.0,
)


class Grid:
    """A raster over the run's whole area, at the map's cell size."""

    def __init__(self, pts, cell):
        lo = pts.min(axis=0) - 3.0
        hi = pts.max(axis=0) + 3.0
        self.cell = cell
        self.o = lo
        self.shape = (int((hi[1] - lo[1]) / cell) + 1, int((hi[0] - lo[0]) / cell) + 1)

    def idx(self, p):
        """(row, col) of points, clipped to the raster."""
        c = np.floor((p - self.o) / self.cell).astype(np.int64)
        return (np.clip(c[..., 1], 0, self.shape[0] - 1), np.clip(c[..., 0], 0, self.shape[1] - 1))


def transform_about(p, pivot, d):
    """Points turned by d[2] about pivot, then shifted by d[:2]."""
    c, s = math.cos(d[2]), math.sin(d[2])
    q = p - pivot
    return np.stack([c * q[:, 0] - s * q[:, 1], s * q[:, 0] + c * q[:, 1]], axis=1) + pivot + d[:2]


def search(field, grid, pts, pivot, win_xy, win_th, P):
    """Best (dx, dy, dth) of pts over the field, coarse then fine; with the score of the
    uncorrected pose and the score-weighted spread of the fine grid's poses."""
    def scores(dxs, dys, dths):
        out = np.empty((len(dths), len(dys), len(dxs)))
        for k, th in enumerate(dths):
            q = transform_about(pts, pivot, (0.0, 0.0, th))
            qx = q[:, 0][None, None, :] + dxs[None, :, None]
            qy = q[:, 1][None, None, :] + dys[:, None, None]
            r, c = grid.idx(np.stack(np.broadcast_arrays(qx, qy), axis=-1))
            out[k] = field[r, c].mean(axis=-1)
        return out

    n_xy = max(1, int(round(win_xy / P["coarse_xy"])))
    n_th = max(1, int(round(win_th / math.radians(P["coarse_th"]))))
    cx = np.arange(-n_xy, n_xy + 1) * P["coarse_xy"]
    cth = np.arange(-n_th, n_th + 1) * math.radians(P["coarse_th"])
    sc = scores(cx, cx, cth)
    k, j, i = np.unravel_index(np.argmax(sc), sc.shape)
    fx = cx[i] + np.arange(-4, 5) * P["fine_xy"]
    fy = cx[j] + np.arange(-4, 5) * P["fine_xy"]
    fth = cth[k] + np.arange(-4, 5) * math.radians(P["fine_th"])
    sf = scores(fx, fy, fth)
    k2, j2, i2 = np.unravel_index(np.argmax(sf), sf.shape)
    best = np.array([fx[i2], fy[j2], fth[k2]])
    zero = scores(np.array([0.0]), np.array([0.0]), np.array([0.0]))[0, 0, 0]
    # Spread: poses of the coarse grid weighted by how close their score is to the best
    # (a ridge along a lone wall spreads along it).
    w = np.exp((sc - sc.max()) / 0.02)
    W = w.sum()
    TH, Y, X = np.meshgrid(cth, cx, cx, indexing="ij")
    mx, my, mt = (w * X).sum() / W, (w * Y).sum() / W, (w * TH).sum() / W
    cxx = (w * (X - mx) ** 2).sum() / W
    cyy = (w * (Y - my) ** 2).sum() / W
    cxy = (w * (X - mx) * (Y - my)).sum() / W
    ctt = (w * (TH - mt) ** 2).sum() / W
    ev = np.linalg.eigvalsh(np.array([[cxx, cxy], [cxy, cyy]]))
    return best, float(sf.max()), float(zero), math.sqrt(max(ev[1], 0)), math.sqrt(ctt), \
        int(sc.size + sf.size)


def spread_loop(C, anchors, a, b, delta, pivot, mode):
    """New corrections of nodes a..b (inclusive) so that node b moves by delta (turned
    about pivot, then shifted) and node a stays; later nodes take node b's."""
    P = lp.compose(C[a:b + 1], anchors[a:b + 1])          # corrected anchor poses
    Pb = P[-1].copy()
    tgt_xy = transform_about(Pb[None, :2], pivot, delta)[0]
    tgt = np.array([tgt_xy[0], tgt_xy[1], lp.wrap(Pb[2] + delta[2])])
    if mode == "none" or b == a:
        newC = lp.compose(tgt, lp.inverse(anchors[b]))
        C[b:] = newC
        return
    seg = np.hypot(np.diff(P[:, 0]), np.diff(P[:, 1]))
    s = np.r_[0.0, np.cumsum(seg)]
    w = s / s[-1] if s[-1] > 1e-6 else np.linspace(0, 1, len(s))
    Q = P.copy()
    for i in range(1, len(P)):
        u = lp.between(P[i - 1], P[i])
        Q[i] = lp.compose(Q[i - 1], u)
        Q[i, 2] = lp.wrap(Q[i, 2] + (w[i] - w[i - 1]) * delta[2])
    r = tgt[:2] - Q[-1, :2]
    Q[:, :2] += w[:, None] * r[None, :]
    Q[-1] = tgt
    C[a:b + 1] = lp.compose(Q, lp.inverse(anchors[a:b + 1]))
    C[b + 1:] = C[b]


def close_loops(run, **kw):
    P = dict(DEFAULTS)
    P.update(kw)
    est = run.est
    hit = run.hits_mask()
    hit_idx = np.nonzero(hit)[0]
    far = np.isfinite(run.range) & (run.range >= run.rc) & (run.range < P["far_max"]) \
        if P["far_max"] > 0 else np.zeros(run.n, bool)
    # Segments: every seg_hits hits; a reading belongs to the segment of the next hit.
    nseg = max(1, len(hit_idx) // P["seg_hits"])
    ends = hit_idx[np.minimum((np.arange(1, nseg + 1) * P["seg_hits"]) - 1, len(hit_idx) - 1)]
    ends[-1] = run.n - 1
    starts = np.r_[0, ends[:-1] + 1]
    seg_of = np.zeros(run.n, np.int64)
    for k in range(nseg):
        seg_of[starts[k]:ends[k] + 1] = k
    anchors = est[starts]
    C = np.zeros((nseg, 3))                       # correction of each segment, now
    held = np.zeros((run.n, 3))                   # correction the robot held at each reading
    # Local points of each hit in the estimate frame (placed by C of its segment later).
    pts_est = run.points(est)
    path = np.r_[0.0, np.cumsum(np.hypot(np.diff(est[:, 0]), np.diff(est[:, 1])))]
    grid = Grid(pts_est[hit | far], run.cell)
    cell = run.cell
    sig_cells = P["field_sigma"] / cell
    last_closure = 0
    pending = None
    log = []
    acc = ref_cnt = wrong = 0
    refused = {"score": 0, "gain": 0, "spread": 0, "gate": 0, "confirm": 0}
    ops = 0
    attempts = 0
    ref_valid_upto = -1
    seg_len = np.r_[path[starts[1:]] - path[starts[:-1]], path[-1] - path[starts[-1]]]
    u = np.cumsum(seg_len)                        # uncertainty: path since an anchor
    ref_u = np.full(grid.shape, np.inf)
    ref_count = np.zeros(grid.shape, np.int32)
    ref_young = np.full(grid.shape, -1, np.int64)
    field = None

    def place(ks, mask, truth=False):
        """World points of the readings of segments ks selected by mask, with the
        segment ids."""
        sel = np.concatenate([np.arange(starts[k], ends[k] + 1) for k in ks])
        sel = sel[mask[sel]]
        corr = C[seg_of[sel]]
        p = run.true[sel] if truth else lp.compose(corr, est[sel])
        sx, sy, b = run.beam(p, sel)
        r = run.range[sel]
        return np.stack([sx + r * np.cos(b), sy + r * np.sin(b)], axis=1), seg_of[sel]

    def rebuild(upto, u_max):
        nonlocal ref_count, ref_young, field
        ref_count[:] = 0
        ref_young[:] = -1
        ref_u[:] = np.inf
        ks = [j for j in range(upto + 1) if u[j] <= u_max]
        if ks:
            p, sid = place(ks, hit, bool(P["ref_truth"]))
            r, c = grid.idx(p)
            np.add.at(ref_count, (r, c), 1)
            np.maximum.at(ref_young, (r, c), sid)
            np.minimum.at(ref_u, (r, c), u[sid])
        occ = ref_count >= P["ref_min"]
        if occ.any():
            d = ndimage.distance_transform_edt(~occ)
            field = np.exp(-0.5 * (d / sig_cells) ** 2)
        else:
            field = None

    for k in range(nseg):
        held[starts[k]:ends[k] + 1] = C[k]
        t_now = run.t[ends[k]]
        k0 = max(0, k - P["scan_segs"] + 1)
        t_scan = run.t[starts[k0]]
        # The reference: every segment that ended min_age before the scan began.
        upto = int(np.searchsorted(run.t[ends], t_scan - P["min_age"], side="right")) - 1
        u_max = np.inf if P["u_margin"] < 0 else min(u[k] - P["u_margin"], u[k] * P["u_frac"])
        rebuild(upto, u_max)
        ref_valid_upto = upto
        if field is None or k - k0 + 1 < P["scan_segs"]:
            continue
        pts, _ = place(range(k0, k + 1), hit | far)
        if len(pts) < P["min_pts"]:
            continue
        rr, cc = grid.idx(pts)
        near = field[rr, cc] > math.exp(-0.5 * (P["overlap_m"] / P["field_sigma"]) ** 2)
        if near.mean() < P["overlap"]:
            continue
        attempts += 1
        # The loop's start: the later of the last closure and the youngest reference
        # segment near the scan.
        young = ref_young[rr, cc]
        youngest = int(young.max()) if (young >= 0).any() else 0
        a = max(last_closure, youngest)
        d = path[ends[k]] - path[starts[a]]
        win_xy = min(P["max_xy"], P["gate_xy0"] + P["gate_xy1"] * math.sqrt(max(d, 0)))
        win_th = math.radians(min(P["max_th"], P["gate_th0"] + P["gate_th1"] * math.sqrt(max(d, 0))))
        pose_now = lp.compose(C[k], est[ends[k]])
        pivot = pose_now[:2]
        best, s_best, s_zero, spr_xy, spr_th, nops = search(field, grid, pts, pivot, win_xy,
                                                             win_th, P)
        ops += nops * len(pts)
        why = None
        if s_best < P["min_score"]:
            why = "score"
        elif s_best - s_zero < P["min_gain"] and (abs(best[0]) > 1e-9 or abs(best[1]) > 1e-9 or abs(best[2]) > 1e-9):
            why = "gain"
        elif spr_xy > P["max_spread_m"] or math.degrees(spr_th) > P["max_spread_deg"]:
            why = "spread"
        elif math.hypot(best[0], best[1]) > 0.9 * win_xy or abs(best[2]) > 0.9 * win_th:
            why = "gate"  # at the edge of the window: the peak may lie outside it
        if why:
            refused[why] += 1
            pending = None
            continue
        if math.hypot(best[0], best[1]) < P["dead_m"] and abs(math.degrees(best[2])) < P["dead_deg"]:
            pending = None
            continue
        if P["confirm"]:
            if pending is None or k - pending[0] > P["confirm_within"] or \
                    math.hypot(*(best[:2] - pending[1][:2])) > P["agree_m"] or \
                    abs(math.degrees(best[2] - pending[1][2])) > P["agree_deg"]:
                if pending is not None:
                    refused["confirm"] += 1
                pending = (k, best)
                continue
        pending = None
        # Apply.
        before = lp.pose_err(pose_now[None, :], run.true[ends[k]][None, :])
        spread_loop(C, anchors, a, k, best, pivot, P["spread"])
        after_pose = lp.compose(C[k], est[ends[k]])
        after = lp.pose_err(after_pose[None, :], run.true[ends[k]][None, :])
        bad = (after[0][0] > before[0][0] + P["wrong_m"]) or \
            (math.degrees(after[1][0] - before[1][0]) > P["wrong_deg"])
        acc += 1
        wrong += bool(bad)
        log.append({"t": float(t_now), "seg": k, "from": a, "d_m": float(d),
                    "step": [float(best[0]), float(best[1]), float(math.degrees(best[2]))],
                    "score": s_best, "gain": s_best - s_zero, "spread": [spr_xy, math.degrees(spr_th)],
                    "err_before": [float(before[0][0]), float(math.degrees(before[1][0]))],
                    "err_after": [float(after[0][0]), float(math.degrees(after[1][0]))],
                    "wrong": bool(bad)})
        last_closure = k
        # The loop's segments are now as certain as its two ends make them.
        matched = ref_u[rr, cc][np.isfinite(ref_u[rr, cc])]
        u_ref = float(np.median(matched)) if len(matched) else u[a]
        s_loop = np.cumsum(seg_len[a:k + 1])
        s_loop = s_loop[-1] - s_loop
        u[a:k + 1] = np.minimum(u[a:k + 1], u_ref * P["u_close"] + s_loop)
        u[k + 1:] = u[k] + np.cumsum(seg_len[k + 1:])
    final = lp.compose(C[seg_of], est)
    held_pose = lp.compose(held, est)
    info = {"accepted": acc, "refused": sum(refused.values()), "wrong": wrong,
            "refused_by": refused, "attempts": attempts, "segments": nseg,
            "lookups": ops}
    return final, held_pose, info, log


def run_method(run, **kw):
    final, held, info, log = close_loops(run, **kw)
    pe, he = lp.pose_err(held, run.true)
    info["held_pos_mean"] = float(pe.mean())
    info["held_bad_share"] = float(((pe > 0.3) | (he > math.radians(5))).mean())
    return final, info


def main(argv):
    run = lp.Run(argv[1])
    kw = {}
    for a in argv[2:]:
        k, v = a.split("=", 1)
        kw[k] = type(DEFAULTS[k])(v) if not isinstance(DEFAULTS[k], str) else v
    final, held, info, log = close_loops(run, **kw)
    for e in log:
        print("t %7.1f seg %4d from %4d d %6.1f m step %+.3f %+.3f %+.2f° score %.2f gain %.2f "
              "spread %.3f %.2f err %.3f/%.1f° -> %.3f/%.1f°%s" % (
                  e["t"], e["seg"], e["from"], e["d_m"], *e["step"], e["score"], e["gain"],
                  *e["spread"], *e["err_before"], *e["err_after"], " WRONG" if e["wrong"] else ""))
    print(info)
    s_est = run.score(run.est)["f1"]
    s = run.score(final)["f1"]
    print("F1 own %.3f est %.3f lc %.3f true %.3f" % (run.own_f1(), s_est, s, run.true_f1()))


if __name__ == "__main__":
    main(sys.argv)
