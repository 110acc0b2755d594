#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Loop closure on a run's log, causal: what the robot could have done as it went.

The firmware's own estimate (scoring_estimate.csv, with its Kalman wall matching) is the
odometry of this method. The path is cut into segments of `seg_hits` hits; a segment is
moved as one rigid piece by a correction C (map = C ∘ estimate). Each segment carries an
uncertainty u, in metres of path since the pose was last fixed (u grows with the path; a
closure sets it from the visit it matched). Every `every` segments:

1. the scan: the hits of the last `scan_segs` segments (with `far_max`, also the echoes
   beyond rc up to that range, for matching only), placed with their corrections;
2. the visits: the older segments whose hits fall near the scan and that ended at least
   `d_min` metres of path before the scan began, grouped into runs of consecutive
   segments (a visit: one pass of the robot by this place); the `max_visits` most
   certain (lowest u) with at least `visit_min_pts` hits near the scan are matched, each
   on its own, so that two passes drawn apart never blur one reference;
3. for each: a likelihood field of the visit's hits (Gaussian of the distance to the
   nearest hit cell, σ `field_sigma`) and a correlative search of the scan's pose over
   ±window (the pose's uncertainty relative to that visit: `gate_xy0` + `gate_xy1`·√d
   metres, `gate_th0` + `gate_th1`·√d degrees, d the path between them through the
   anchors, clipped to `max_xy`, `max_th`), coarse then fine, turning about the robot;
4. gates: mean field value at least `min_score`; the peak sharp (score-weighted spread
   of the pose under `max_spread_m`, `max_spread_deg`); not at the window's edge;
5. confirmation (`confirm`): two matches that agree within `agree_m`/`agree_deg`, from
   two visits in one attempt or from consecutive attempts;
6. the correction (`spread`): "graph" (the default) adds the match as an edge between the
   visit's node nearest the robot and the newest node of a pose graph whose other edges
   are the estimate's own relative motion (posegraph.solve), and takes every node's new
   pose; "lin" the same with positions only (posegraph.solve_lin); "path" spreads the
   step along the path since the later of the last closure and the visit, "none" moves
   only what follows. A confirmed step smaller than `sig_m` and `sig_deg` (both 0: none
   is) moves nothing and is kept as an edge for the next solve (`keep_small`); a larger
   one whose visit lies less than `d_accept` m of path back is refused as uncertain;
7. `manhattan`: the home taken as rectilinear. Each node gets the walls' direction in
   its own frame (walldir.dominant over its and the previous segment's hits, modulo 90°);
   the home's direction is learned from the first `m_learn_s` seconds; every `m_every`
   segments, while `manhattan_check` finds at least `m_check_share` of the nodes within
   `m_check_deg` of it, the graph is solved with a unary heading factor on every such node
   (σ `m_sigma`°, Huber beyond `m_huber` σ), the home's direction one more unknown.

Every reading's final pose is its segment's final correction ∘ its estimate; the pose
the robot held then (for counting wrong closures and for the integrity flag) is the
correction of that moment ∘ its estimate. A closure is wrong when it moves the robot's
pose away from the truth by more than `wrong_m` or `wrong_deg`.

Diagnostics, not methods: `truth_z` takes a closure's edge from the truth (a perfect
match at the same moment), `est_truth` runs on the true poses, `base` "odom" on the
odometry instead of the estimate.

The work of the matches is counted (`lookups`: likelihood-field reads; `fields`: fields
built) for the MCU estimate; `integrity` scores candidate pose-integrity flags.

    tools/proto/evaluate.py dev lc [--set key=value ...] [--tag NAME]
    tools/proto/loopclose.py RUN_DIR [key=value ...] [noscore]
        # one run: its closures, and how well the matches measure the relative pose

The figures of firmware/experiments_loop_closure.md, for SET dev and held (`--only` picks
groups): `evaluate.py SET lc --tag f2 --set sig_m=0.08 --set sig_deg=2.5 --set d_accept=30`;
the same with `--set manhattan=1` (tag g1c), with `--set theta=0 --set loop_sth=30` (h1) or
`--set theta=0 --set spread='"lin"'` (h2). Rows a–e and v3, v4 of the page were made with
earlier states of this file (their parameters are in out/proto/results/dev/lc-*.json).
The match precision: `loopclose.py RUN_DIR sig_m=0.08 sig_deg=2.5 d_accept=30
scan_segs=6|12 noscore`.
"""
import math
import sys

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree

import lpcommon as lp
import posegraph

DEFAULTS = dict(
    seg_hits=32, scan_segs=6, every=1, d_min=15.0, far_max=0.0,
    field_sigma=0.06, margin=0.3, overlap=0.6,
    max_visits=2, visit_min_pts=40, min_pts=60, visit_segs=8, visit_pick="first,last",
    gate_xy0=0.10, gate_xy1=0.05, gate_th0=1.5, gate_th1=0.4, max_xy=0.8, max_th=8.0,
    min_score=0.7, max_spread_m=0.04, max_spread_deg=99.0,
    dead_m=0.03, dead_deg=0.5,
    confirm=1, agree_m=0.05, agree_deg=1.0,
    spread="graph", pick="u",
    odo_sxy=0.03, odo_sth=0.5, loop_sxy=0.04, loop_sth=3.0, gn_iters=3,
    coarse_xy=0.05, coarse_th=1.0, fine_xy=0.0125, fine_th=0.25,
    wrong_m=0.05, wrong_deg=1.0, truth_z=0, est_truth=0, robust=0.0, theta=1, base="est",
    sig_m=0.0, sig_deg=0.0, keep_small=1, d_accept=0.0,
    manhattan=0, m_prom=5.0, m_learn_s=60.0, m_sigma=3.0, m_huber=1.5, m_every=10,
    m_check_deg=3.0, m_check_share=0.5, m_check_win=15,
)


def transform_pts(C, p):
    """Points p (n×2) under the correction C (x, y, th)."""
    c, s = math.cos(C[2]), math.sin(C[2])
    return np.stack([c * p[:, 0] - s * p[:, 1] + C[0], s * p[:, 0] + c * p[:, 1] + C[1]], axis=1)


def turn_about(p, pivot, d):
    c, s = math.cos(d[2]), math.sin(d[2])
    q = p - pivot
    return np.stack([c * q[:, 0] - s * q[:, 1], s * q[:, 0] + c * q[:, 1]], axis=1) + pivot + d[:2]


class Field:
    """A likelihood field of reference points over a local window."""

    def __init__(self, ref, lo, hi, cell, sigma):
        self.o = lo
        self.cell = cell
        self.shape = (int((hi[1] - lo[1]) / cell) + 1, int((hi[0] - lo[0]) / cell) + 1)
        occ = np.zeros(self.shape, bool)
        r, c = self.idx(ref)
        occ[r, c] = True
        d = ndimage.distance_transform_edt(~occ)
        self.f = np.exp(-0.5 * (d * cell / sigma) ** 2)
        self.f[0, :] = self.f[-1, :] = 0.0
        self.f[:, 0] = self.f[:, -1] = 0.0

    def idx(self, p):
        c = np.floor((p - self.o) / self.cell).astype(np.int64)
        return (np.clip(c[..., 1], 0, self.shape[0] - 1), np.clip(c[..., 0], 0, self.shape[1] - 1))

    def score(self, p):
        r, c = self.idx(p)
        return self.f[r, c]


def search(field, pts, pivot, win_xy, win_th, P):
    """Best (dx, dy, dth) of pts over the field, coarse then fine; the score there, the
    score of the unmoved scan, and the score-weighted spread of the coarse poses."""
    H, W = field.shape
    flat = field.f.ravel()
    cell = field.cell

    def scores(dxs, dys, dths):
        out = np.empty((len(dths), len(dys), len(dxs)))
        ux, uy = dxs / cell, dys / cell
        ix, fx = np.floor(ux).astype(np.int64), ux - np.floor(ux)
        iy, fy = np.floor(uy).astype(np.int64), uy - np.floor(uy)
        fxs = np.unique(np.round(fx, 6))
        fys = np.unique(np.round(fy, 6))
        for k, th in enumerate(dths):
            q = (turn_about(pts, pivot, (0.0, 0.0, th)) - field.o) / cell
            for a in fxs:
                sx = np.nonzero(np.abs(fx - a) < 1e-6)[0]
                bx = np.floor(q[:, 0] + a).astype(np.int64)
                for b in fys:
                    sy = np.nonzero(np.abs(fy - b) < 1e-6)[0]
                    by = np.floor(q[:, 1] + b).astype(np.int64)
                    base = by * W + bx
                    off = (iy[sy] * W)[:, None] + ix[sx][None, :]
                    idx = np.clip(base[None, None, :] + off[:, :, None], 0, H * W - 1)
                    out[k][np.ix_(sy, sx)] = flat[idx].mean(axis=-1)
        return out

    n_xy = max(1, int(round(win_xy / P["coarse_xy"])))
    n_th = max(1, int(round(win_th / math.radians(P["coarse_th"])))) if P["theta"] else 0
    cx = np.arange(-n_xy, n_xy + 1) * P["coarse_xy"]
    cth = np.arange(-n_th, n_th + 1) * math.radians(P["coarse_th"])
    sc = scores(cx, cx, cth)
    k, j, i = np.unravel_index(np.argmax(sc), sc.shape)
    fx = cx[i] + np.arange(-4, 5) * P["fine_xy"]
    fy = cx[j] + np.arange(-4, 5) * P["fine_xy"]
    fth = cth[k] + np.arange(-4, 5) * math.radians(P["fine_th"]) if P["theta"] else cth[:1]
    sf = scores(fx, fy, fth)
    k2, j2, i2 = np.unravel_index(np.argmax(sf), sf.shape)
    best = np.array([fx[i2], fy[j2], fth[k2]])
    zero = float(field.score(pts).mean())
    w = np.exp((sc - sc.max()) / 0.02)
    W = w.sum()
    TH, Y, X = np.meshgrid(cth, cx, cx, indexing="ij")
    mx, my, mt = (w * X).sum() / W, (w * Y).sum() / W, (w * TH).sum() / W
    cov = np.array([[(w * (X - mx) ** 2).sum(), (w * (X - mx) * (Y - my)).sum()],
                    [(w * (X - mx) * (Y - my)).sum(), (w * (Y - my) ** 2).sum()]]) / W
    ev = np.linalg.eigvalsh(cov)
    ctt = (w * (TH - mt) ** 2).sum() / W
    edge = abs(i) == len(cx) - 1 or i == 0 or j == 0 or j == len(cx) - 1 or \
        (n_th > 1 and (k == 0 or k == len(cth) - 1))
    return {"step": best, "score": float(sf.max()), "zero": zero,
            "spread_m": math.sqrt(max(ev[1], 0.0)), "spread_deg": math.degrees(math.sqrt(ctt)),
            "edge": bool(edge), "poses": int(sc.size + sf.size + 1)}


def spread_loop(C, anchors, a, b, delta, pivot, mode):
    """New corrections of nodes a..b (inclusive) so that node b moves by delta (turned
    about pivot, then shifted) and node a stays; later nodes take node b's."""
    P = lp.compose(C[a:b + 1], anchors[a:b + 1])
    Pb = P[-1].copy()
    tgt_xy = turn_about(Pb[None, :2], pivot, delta)[0]
    tgt = np.array([tgt_xy[0], tgt_xy[1], lp.wrap(Pb[2] + delta[2])])
    if mode == "none" or b == a:
        C[b:] = lp.compose(tgt, lp.inverse(anchors[b]))
        return
    s = np.r_[0.0, np.cumsum(np.hypot(np.diff(P[:, 0]), np.diff(P[:, 1])))]
    w = s / s[-1] if s[-1] > 1e-6 else np.linspace(0, 1, len(s))
    Q = P.copy()
    for i in range(1, len(P)):
        Q[i] = lp.compose(Q[i - 1], lp.between(P[i - 1], P[i]))
        Q[i, 2] = lp.wrap(Q[i, 2] + (w[i] - w[i - 1]) * delta[2])
    Q[:, :2] += w[:, None] * (tgt[:2] - Q[-1, :2])[None, :]
    Q[-1] = tgt
    C[a:b + 1] = lp.compose(Q, lp.inverse(anchors[a:b + 1]))
    C[b + 1:] = C[b]


class Closer:
    """The state of the method over one run."""

    def __init__(self, run, P):
        self.run, self.P = run, P
        if P["est_truth"]:
            run.est = run.true.copy()
        if P["base"] == "odom":
            run.est = run.odom.copy()
        est = run.est
        hit = run.hits_mask()
        hit_idx = np.nonzero(hit)[0]
        nseg = max(1, len(hit_idx) // P["seg_hits"])
        ends = hit_idx[np.minimum(np.arange(1, nseg + 1) * P["seg_hits"] - 1, len(hit_idx) - 1)]
        ends[-1] = run.n - 1
        self.starts = np.r_[0, ends[:-1] + 1]
        self.ends = ends
        self.nseg = nseg
        self.seg_of = np.repeat(np.arange(nseg), self.ends - self.starts + 1)
        self.anchors = est[self.ends]
        self.C = np.zeros((nseg, 3))
        self.held = np.zeros((run.n, 3))
        pts = run.points(est)
        far = np.isfinite(run.range) & (run.range >= run.rc) & (run.range < P["far_max"]) \
            if P["far_max"] > 0 else np.zeros(run.n, bool)
        self.hit_pts = [pts[s:e + 1][hit[s:e + 1]] for s, e in zip(self.starts, self.ends)]
        self.scan_pts = [pts[s:e + 1][(hit | far)[s:e + 1]] for s, e in zip(self.starts, self.ends)]
        self.path = np.r_[0.0, np.cumsum(np.hypot(np.diff(est[:, 0]), np.diff(est[:, 1])))]
        self.p_start = self.path[self.starts]
        self.p_end = self.path[self.ends]
        seg_len = self.p_end - self.p_start
        self.seg_len = np.r_[self.p_start[1:] - self.p_start[:-1], seg_len[-1]]
        self.u = np.cumsum(self.seg_len)
        # Walls' direction in each node's frame (modulo 90°), from the node's and the
        # previous segment's hits: a unary heading factor once the home's direction is
        # known (`manhattan`).
        self.wdir = np.full(nseg, np.nan)
        if P["manhattan"]:
            import walldir
            WP = dict(walldir.DEFAULTS)
            WP.update(prom=P["m_prom"])
            for k in range(nseg):
                p_ = np.concatenate([self.hit_pts[j] for j in range(max(0, k - 1), k + 1)])
                if len(p_) < 32:
                    continue
                r_ = walldir.dominant(p_, WP, math.pi / 2)
                if r_ is not None and r_[1] >= P["m_prom"] and r_[2] >= WP["peak_pairs"]:
                    self.wdir[k] = (r_[0] - self.anchors[k, 2]) % (math.pi / 2)
            # The home's direction: the robust mean of the first m_learn_s seconds' walls,
            # where the estimate's heading is still right.
            early = [k for k in range(nseg) if run.t[self.ends[k]] <= P["m_learn_s"] and
                     np.isfinite(self.wdir[k])]
            if early:
                w = np.array([(self.wdir[k] + self.anchors[k, 2]) % (math.pi / 2) for k in early])
                ang = w * 4
                self.theta_m = (math.atan2(np.sin(ang).mean(), np.cos(ang).mean()) / 4) % (math.pi / 2)
            else:
                self.theta_m = None
        self.m_on = False
        self.m_share = 0.0
        self.bbox = np.zeros((nseg, 4))
        for j in range(nseg):
            self.update_bbox(j)
        self.last_closure = 0
        self.pending = None
        self.generation = 0
        self.history = []               # (segment, corrections after each closure)
        self.loops = []
        self.odo = posegraph.odometry_edges(self.anchors, self.p_end, P["odo_sxy"], P["odo_sth"])
        self.log = []
        self.counts = {"attempts": 0, "accepted": 0, "consistent": 0, "wrong": 0,
                       "refused_score": 0, "refused_spread": 0, "refused_edge": 0,
                       "refused_uncertain": 0,
                       "refused_confirm": 0, "no_visit": 0, "lookups": 0, "fields": 0}
        self.attempt_log = []

    def update_bbox(self, j):
        p = self.hit_pts[j]
        if len(p) == 0:
            self.bbox[j] = (np.inf, np.inf, -np.inf, -np.inf)
            return
        q = transform_pts(self.C[j], p)
        self.bbox[j] = (q[:, 0].min(), q[:, 1].min(), q[:, 0].max(), q[:, 1].max())

    def placed(self, j, which="hit"):
        return transform_pts(self.C[j], (self.hit_pts if which == "hit" else self.scan_pts)[j])

    def visits(self, k0, lo, hi, scan_tree, R):
        """Passes of the robot by the scan that ended d_min of path before segment k0:
        runs of consecutive old segments with hits within R of the scan's points, each
        cut to the visit_segs segments that hold most such hits."""
        P = self.P
        jmax = int(np.searchsorted(self.p_end, self.p_start[k0] - P["d_min"], side="right"))
        if jmax <= 0:
            return []
        b = self.bbox[:jmax]
        near = (b[:, 0] <= hi[0]) & (b[:, 2] >= lo[0]) & (b[:, 1] <= hi[1]) & (b[:, 3] >= lo[1])
        js = np.nonzero(near)[0]
        cnt = {}
        for j in js:
            if len(self.hit_pts[j]):
                dist, _ = scan_tree.query(self.placed(j), distance_upper_bound=R)
                cnt[j] = int(np.isfinite(dist).sum())
        js = [j for j in js if cnt.get(j, 0) > 0]
        runs = []
        for j in js:
            if runs and j - runs[-1][-1] <= 2:
                runs[-1].append(j)
            else:
                runs.append([j])
        out = []
        for r in runs:
            r = list(range(r[0], r[-1] + 1))
            if len(r) > P["visit_segs"]:
                c = np.array([cnt.get(j, 0) for j in r])
                win = np.convolve(c, np.ones(P["visit_segs"]), "valid")
                i = int(np.argmax(win))
                r = r[i:i + P["visit_segs"]]
            out.append(r)
        return out

    def attempt(self, k):
        P, run = self.P, self.run
        k0 = k - P["scan_segs"] + 1
        scan = np.concatenate([self.placed(j, "scan") for j in range(k0, k + 1)])
        if len(scan) < P["min_pts"]:
            return
        pose_now = lp.compose(self.C[k], run.est[self.ends[k]])
        pivot = pose_now[:2]
        m = P["max_xy"] + P["margin"]
        lo, hi = scan.min(axis=0) - m, scan.max(axis=0) + m
        tree = cKDTree(scan)
        R = min(P["max_xy"], P["gate_xy0"] + P["gate_xy1"] * math.sqrt(max(self.u[k], 0.0))) + 0.05
        cands = []
        for v in self.visits(k0, lo, hi, tree, R):
            ref = np.concatenate([self.placed(j) for j in v])
            inside = np.all((ref >= lo) & (ref <= hi), axis=1)
            if inside.sum() < P["visit_min_pts"]:
                continue
            d = min(self.u[k] + float(self.u[v].min()), self.p_end[k] - self.p_end[v[-1]])
            win_xy = min(P["max_xy"], P["gate_xy0"] + P["gate_xy1"] * math.sqrt(d))
            dist, _ = cKDTree(ref[inside]).query(scan, distance_upper_bound=win_xy + 0.05)
            if np.isfinite(dist).mean() < P["overlap"]:
                continue
            cands.append((v, ref[inside], d))
        if not cands:
            self.counts["no_visit"] += 1
            return
        self.counts["attempts"] += 1
        pick = []
        for how in P["visit_pick"].split(","):
            c = cands[0] if how == "first" else cands[-1] if how == "last" else \
                min(cands, key=lambda c: float(self.u[c[0]].min()))
            if all(c is not q for q in pick):
                pick.append(c)
        good = []
        for v, ref, d in pick[:P["max_visits"]]:
            win_xy = min(P["max_xy"], P["gate_xy0"] + P["gate_xy1"] * math.sqrt(d))
            win_th = math.radians(min(P["max_th"], P["gate_th0"] + P["gate_th1"] * math.sqrt(d)))
            f = Field(ref, lo, hi, run.cell, P["field_sigma"])
            r = search(f, scan, pivot, win_xy, win_th, P)
            self.counts["fields"] += 1
            self.counts["lookups"] += r["poses"] * len(scan)
            why = None
            if r["score"] < P["min_score"]:
                why = "score"
            elif r["spread_m"] > P["max_spread_m"] or r["spread_deg"] > P["max_spread_deg"]:
                why = "spread"
            elif r["edge"]:
                why = "edge"
            # What the truth says of this match (diagnostics only): the constraint it
            # would add against the true relative pose.
            x = lp.compose(self.C, self.anchors)
            j = self.nearest(x, v, k)
            txy = turn_about(x[k][None, :2], pivot, r["step"])[0]
            xk = np.array([txy[0], txy[1], lp.wrap(x[k, 2] + r["step"][2])])
            zt = lp.between(run.true[self.ends[j]], run.true[self.ends[k]])
            ez = lp.between(zt, lp.between(x[j], xk))
            ez0 = lp.between(zt, lp.between(x[j], x[k]))
            self.attempt_log.append((k, v[0], v[-1], d, r["step"].tolist(), r["score"], r["zero"],
                                     r["spread_m"], r["spread_deg"], why, ez.tolist(), ez0.tolist(),
                                     len(scan), len(ref)))
            if why:
                self.counts["refused_" + why] += 1
                continue
            good.append((v, r, d))
        if not good:
            return
        confirmed = [] if P["confirm"] else [good[0]]
        for g2 in good[1:]:
            if self.agree(good[0][1]["step"], g2[1]["step"]):
                confirmed = [good[0], g2]
        if not confirmed and self.pending is not None and self.pending[0] >= k - P["every"] \
                and self.agree(good[0][1]["step"], self.pending[1][1]["step"]):
            confirmed = [good[0]] + ([self.pending[1]] if self.pending[2] == self.generation else [])
        if not confirmed:
            self.pending = (k, good[0], self.generation)
            self.counts["refused_confirm"] += 1
            return
        self.pending = None
        step = confirmed[0][1]["step"]
        small = math.hypot(step[0], step[1]) < P["sig_m"] and abs(math.degrees(step[2])) < P["sig_deg"]
        if small or confirmed[0][2] < P["d_accept"]:
            # Consistent, or a step the pose's uncertainty does not allow yet: an edge for
            # the next solve (keep_small), nothing moves now.
            self.counts["consistent" if small else "refused_uncertain"] += 1
            if P["keep_small"] and small:
                x = lp.compose(self.C, self.anchors)
                for v, r, d in confirmed:
                    j = self.nearest(x, v, k)
                    if P["spread"] == "lin":
                        self.loops.append((j, k, x[k, :2] + r["step"][:2] - x[j, :2],
                                           max(P["loop_sxy"], r["spread_m"])))
                    else:
                        txy = turn_about(x[k][None, :2], pivot, r["step"])[0]
                        xk = np.array([txy[0], txy[1], lp.wrap(x[k, 2] + r["step"][2])])
                        sxy = max(P["loop_sxy"], r["spread_m"])
                        sth = math.radians(max(P["loop_sth"], r["spread_deg"]))
                        self.loops.append((j, k, lp.between(x[j], xk),
                                           np.array([1 / sxy ** 2, 1 / sxy ** 2, 1 / sth ** 2])))
            return
        if P["spread"] != "off":
            self.apply(k, confirmed, pivot, pose_now)

    def heading_factors(self, n):
        """Unary heading factors of nodes 0..n-1 (the wall direction ψ seen in the node's
        frame: θ + ψ is the home's direction, modulo 90°), with the current guess of it;
        none until the home is found rectilinear (manhattan_check)."""
        if not self.P["manhattan"] or self.theta_m is None or not self.m_on:
            return None
        idx = np.nonzero(np.isfinite(self.wdir[:n]))[0]
        return idx, self.wdir[idx], np.full(len(idx), 1.0 / math.radians(self.P["m_sigma"]) ** 2), \
            self.theta_m

    def manhattan_solve(self, k):
        """Solve the graph with the heading factors (every m_every segments)."""
        P = self.P
        x = lp.compose(self.C, self.anchors)
        n = k + 1
        xs = posegraph.solve(x[:n], self.odo[:k] + self.loops, iters=P["gn_iters"],
                             robust=P["robust"] or None, robust_from=k,
                             headings=self.heading_factors(n), head_huber=P["m_huber"] or None)
        if self.heading_factors(n) is not None:
            self.theta_m = posegraph.solve.last_m
        self.C[:n] = lp.compose(xs, lp.inverse(self.anchors[:n]))
        self.C[n:] = self.C[k]
        self.generation += 1
        self.history.append((k, self.C.copy()))
        for j in range(n):
            self.update_bbox(j)

    def manhattan_check(self, k):
        """Whether the walls seen so far share one direction modulo 90° (a rectilinear
        home): the share of the nodes' wall directions, at their current headings,
        within m_check_deg of the home's. Checked again at every solve."""
        x = lp.compose(self.C, self.anchors)
        idx = np.nonzero(np.isfinite(self.wdir[:k + 1]))[0]
        if len(idx) < 10:
            return False
        r = ((x[idx, 2] + self.wdir[idx] - self.theta_m + math.pi / 4) % (math.pi / 2)) - math.pi / 4
        # Against the median of the neighbours (±m_check_win nodes): a heading that
        # drifted slowly does not hide a rectilinear home, walls at every angle do.
        h = self.P["m_check_win"]
        loc = np.array([np.median(r[max(0, i - h):i + h + 1]) for i in range(len(r))])
        share = float((np.abs(r - loc) <= math.radians(self.P["m_check_deg"])).mean())
        self.m_share = share
        return share >= self.P["m_check_share"]

    @staticmethod
    def nearest(x, v, k):
        """The visit's node nearest the robot: a constraint to it has the shortest lever
        arm, so the heading of either end hardly moves the other's position."""
        v = np.asarray(v)
        return int(v[np.argmin(np.hypot(x[v, 0] - x[k, 0], x[v, 1] - x[k, 1]))])

    def agree(self, a, b):
        P = self.P
        return math.hypot(a[0] - b[0], a[1] - b[1]) <= P["agree_m"] and \
            abs(math.degrees(a[2] - b[2])) <= P["agree_deg"]

    def apply(self, k, matches, pivot, pose_now):
        P, run = self.P, self.run
        before = lp.pose_err(pose_now[None, :], run.true[self.ends[k]][None, :])
        v, r, d = matches[0]
        step = r["step"]
        if P["spread"] == "lin":
            x = lp.compose(self.C, self.anchors)
            for v, r, d in matches:
                j = self.nearest(x, v, k)
                m = x[k, :2] + r["step"][:2] - x[j, :2]
                if P["truth_z"]:
                    m = run.true[self.ends[k], :2] - run.true[self.ends[j], :2]
                sxy = max(P["loop_sxy"], r["spread_m"])
                self.loops.append((j, k, m, sxy))
            n = k + 1
            p = posegraph.solve_lin(x[:n, :2], self.p_end[:n], self.loops, P["odo_sxy"],
                                    robust=P["robust"] or None)
            self.C[:n] = 0.0
            self.C[:n, :2] = p - self.anchors[:n, :2]
            self.C[n:] = self.C[k]
            self.generation += 1
            a = 0
        elif P["spread"] == "graph":
            x = lp.compose(self.C, self.anchors)
            for v, r, d in matches:
                tgt_xy = turn_about(x[k][None, :2], pivot, r["step"])[0]
                xk = np.array([tgt_xy[0], tgt_xy[1], lp.wrap(x[k, 2] + r["step"][2])])
                j = self.nearest(x, v, k)
                z = lp.between(x[j], xk)
                if P["truth_z"]:
                    z = lp.between(run.true[self.ends[j]], run.true[self.ends[k]])
                sxy = max(P["loop_sxy"], r["spread_m"])
                sth = math.radians(max(P["loop_sth"], r["spread_deg"]))
                self.loops.append((j, k, z, np.array([1 / sxy ** 2, 1 / sxy ** 2, 1 / sth ** 2])))
            n = k + 1
            edges = self.odo[:k] + self.loops
            xs = posegraph.solve(x[:n], edges, iters=P["gn_iters"],
                                 robust=P["robust"] or None, robust_from=k,
                                 headings=self.heading_factors(n),
                                 head_huber=P["m_huber"] or None)
            if self.heading_factors(n) is not None:
                self.theta_m = posegraph.solve.last_m
            self.C[:n] = lp.compose(xs, lp.inverse(self.anchors[:n]))
            self.C[n:] = self.C[k]
            self.generation += 1
            a = 0
        else:
            a = max(self.last_closure, v[-1])
            spread_loop(self.C, self.anchors, a, k, step, pivot, P["spread"])
        self.history.append((k, self.C.copy()))
        after_pose = lp.compose(self.C[k], run.est[self.ends[k]])
        after = lp.pose_err(after_pose[None, :], run.true[self.ends[k]][None, :])
        bad = (after[0][0] > before[0][0] + P["wrong_m"]) or \
            (math.degrees(after[1][0] - before[1][0]) > P["wrong_deg"])
        self.counts["accepted"] += 1
        self.counts["wrong"] += int(bad)
        self.log.append({"t": float(run.t[self.ends[k]]), "seg": k, "from": int(a),
                         "visit": [int(v[0]), int(v[-1])], "d_m": float(d),
                         "step": [float(step[0]), float(step[1]), float(math.degrees(step[2]))],
                         "score": r["score"], "zero": r["zero"],
                         "spread": [r["spread_m"], r["spread_deg"]],
                         "err_before": [float(before[0][0]), float(math.degrees(before[1][0]))],
                         "err_after": [float(after[0][0]), float(math.degrees(after[1][0]))],
                         "wrong": bool(bad), "n": len(matches)})
        for j in range(a, k + 1):
            self.update_bbox(j)
        uv = float(self.u[v].min())
        s = self.p_end[k] - self.p_end[a:k + 1]
        self.u[a:k + 1] = np.minimum(self.u[a:k + 1], uv + s)
        self.u[k + 1:] = self.u[k] + np.cumsum(self.seg_len[k + 1:])
        self.last_closure = k

    def run_all(self):
        P = self.P
        self.sig_u = np.zeros(self.nseg)        # path since the last closure, as held then
        self.sig_step = np.zeros(self.nseg)     # the last good match's step (m)
        last_step = 0.0
        for k in range(self.nseg):
            self.held[self.starts[k]:self.ends[k] + 1] = self.C[k]
            self.sig_u[k] = self.p_end[k] - self.p_end[self.last_closure] if self.last_closure else self.p_end[k]
            n_log = len(self.attempt_log)
            if k >= P["scan_segs"] - 1 and k % P["every"] == 0:
                self.attempt(k)
            if P["manhattan"] and self.theta_m is not None and k % P["m_every"] == 0 and \
                    self.run.t[self.ends[k]] > P["m_learn_s"]:
                self.m_on = self.manhattan_check(k)
                if self.m_on:
                    self.manhattan_solve(k)
            for a in self.attempt_log[n_log:]:
                if a[9] is None or a[9] == "spread":
                    last_step = math.hypot(a[4][0], a[4][1])
            self.sig_step[k] = last_step
        final = lp.compose(self.C[self.seg_of], self.run.est)
        held = lp.compose(self.held, self.run.est)
        return final, held


def close_loops(run, **kw):
    P = dict(DEFAULTS)
    P.update(kw)
    c = Closer(run, P)
    final, held = c.run_all()
    info = dict(c.counts)
    info["refused"] = sum(v for k, v in c.counts.items() if k.startswith("refused_"))
    info["segments"] = c.nseg
    return final, held, info, c


def integrity(run, c, held):
    """Hit and false-alarm counts of candidate integrity flags against the truth (the pose
    the robot held is > 0.3 m or > 5° off): per reading, for thresholds of the path since
    the last closure and of the last good match's step."""
    pe, he = lp.pose_err(held, run.true)
    bad = (pe > 0.3) | (he > math.radians(5))
    u = c.sig_u[c.seg_of]
    st = c.sig_step[c.seg_of]
    out = {"bad": int(bad.sum()), "good": int((~bad).sum())}
    for U in (10, 20, 40, 80):
        f = u > U
        out["u%d" % U] = [int((f & bad).sum()), int((f & ~bad).sum())]
    for S in (0.05, 0.1, 0.15):
        f = st > S
        out["s%g" % S] = [int((f & bad).sum()), int((f & ~bad).sum())]
        f = (st > S) | (u > 40)
        out["s%g_u40" % S] = [int((f & bad).sum()), int((f & ~bad).sum())]
    return out


def run_method(run, **kw):
    final, held, info, c = close_loops(run, **kw)
    info["integrity"] = integrity(run, c, held)
    pe, he = lp.pose_err(held, run.true)
    info["held_pos_mean"] = float(pe.mean())
    info["held_bad_share"] = float(((pe > 0.3) | (he > math.radians(5))).mean())
    return final, info


def precision(c):
    """How well the matches measure the relative pose, against the truth: the median and
    90th percentile of the constraint's error (position m, heading °) for the matches that
    passed every gate and for those the scan's unmoved pose would have given."""
    ok = [a for a in c.attempt_log if a[9] is None]
    if not ok:
        return "no match passed the gates"
    ez = np.array([a[10] for a in ok])
    ez0 = np.array([a[11] for a in ok])

    def fig(e):
        xy = np.hypot(e[:, 0], e[:, 1])
        th = np.degrees(np.abs(lp.wrap(e[:, 2])))
        return "%.3f / %.3f m, %.2f / %.2f°" % (np.median(xy), np.percentile(xy, 90),
                                                  np.median(th), np.percentile(th, 90))
    return "%d matches passed the gates; error of the match's constraint (median / p90) %s;" \
        " of the unmoved scan's %s" % (len(ok), fig(ez), fig(ez0))


def main(argv):
    run = lp.Run(argv[1])
    kw = {}
    for a in argv[2:]:
        k, v = (a.split("=", 1) + [""])[:2]
        if k in DEFAULTS:
            kw[k] = type(DEFAULTS[k])(v) if not isinstance(DEFAULTS[k], str) else v
    final, held, info, c = close_loops(run, **kw)
    for e in c.log:
        print("t %7.1f seg %4d from %4d visit %d-%d d %6.1f m step %+.3f %+.3f %+.2f° score %.2f "
              "(%.2f) spread %.3f %.2f err %.3f/%.1f° -> %.3f/%.1f°%s" % (
                  e["t"], e["seg"], e["from"], *e["visit"], e["d_m"], *e["step"], e["score"],
                  e["zero"], *e["spread"], *e["err_before"], *e["err_after"],
                  " WRONG" if e["wrong"] else ""))
    print(info)
    print(precision(c))
    if "noscore" in sys.argv[2:]:
        return
    s_est = run.score(run.est)["f1"]
    s = run.score(final)["f1"]
    pe, _ = lp.pose_err(held, run.true)
    print("F1 own %.3f est %.3f lc %.3f true %.3f; held pos err mean %.3f (est %.3f)" % (
        run.own_f1(), s_est, s, run.true_f1(), pe.mean(), lp.pose_err(run.est, run.true)[0].mean()))


if __name__ == "__main__":
    main(sys.argv)
