# SPDX-License-Identifier: MIT
"""Oracle closures (DESIGN §7's yardstick): what perfect information would buy. Not
methods: ceilings, each using the true pose.

- oracle_fwd: at every return to a place, the pose error is taken out from then on
  (relocalization: the map drawn before stays);
- oracle_rep: also spread linearly back to the previous return (a crude repair);
- oracle_first, oracle_last: a return set to the error the robot had at its first or
  last earlier visit (a perfect match that is only consistent with the old map);
- oracle_graph: a pose graph over the estimate with the true relative pose as a
  constraint at every return (to the first and last earlier visit), node 0 fixed;
  `noise_m`, `noise_deg` add noise to the constraints, `loop_sxy`, `loop_sth_deg` weigh
  them, `ev_gap` thins the returns, `node_every` coarsens the nodes;
- oracle_heading: odometry's distance increments integrated along the true heading (no
  position correction at all), with `white_deg`, `bias_deg` or `walk_deg` (σ per √min)
  of heading error added, or along the estimate's heading (`src` "est").

A return: a 0.5 m cell of the true path whose last visit was at least 60 s before
(`returns`). The figures of firmware/experiments_loop_closure.md:

    tools/proto/evaluate.py SET oracle_fwd oracle_rep oracle_first oracle_last \
        oracle_graph oracle_heading
    tools/proto/evaluate.py dev oracle_graph --tag noise --set noise_m=0.03 --set noise_deg=1
    tools/proto/evaluate.py dev oracle_graph --tag noisew --set noise_m=0.03 \
        --set noise_deg=1 --set loop_sxy=0.03 --set loop_sth_deg=1     # noisew2: 0.3°
    tools/proto/evaluate.py dev oracle_graph --tag gap30 --set ev_gap=30
    tools/proto/evaluate.py dev oracle_heading --tag b1 --set bias_deg=1   # w1: white_deg=1,
        # rw02 / rw05: walk_deg=0.2 / 0.5, est: src='"est"'
"""
import numpy as np

import lpcommon as lp


def returns(run, radius=0.5, away=60.0, with_earlier=False):
    """Indices of the readings at which the robot returns to a place left `away` s ago
    (with the index of the first and of the last earlier visit)."""
    last = {}
    first = {}
    events = []
    prev_ev_t = -1e9
    for i in range(0, run.n):
        x, y = run.true[i, 0], run.true[i, 1]
        key = (int(np.floor(x / radius)), int(np.floor(y / radius)))
        t = run.t[i]
        was = last.get(key)
        if was is not None and t - run.t[was] >= away and t - prev_ev_t >= 5.0:
            events.append((i, first[key], was))
            prev_ev_t = t
        last[key] = i
        first.setdefault(key, i)
    return events if with_earlier else [e[0] for e in events]


def corrections_at(run, idx):
    """The correction true∘est⁻¹ at the given readings."""
    return lp.compose(run.true[idx], lp.inverse(run.est[idx]))


def oracle(run, repair=False, radius=0.5, away=60.0):
    ev = returns(run, radius, away)
    corr = np.zeros((run.n, 3))
    if not ev:
        return run.est.copy(), {"closures": 0}
    cs = corrections_at(run, ev)
    for k, i in enumerate(ev):
        end = ev[k + 1] if k + 1 < len(ev) else run.n
        corr[i:end] = cs[k]
        if repair:
            i0 = ev[k - 1] if k > 0 else 0
            c0 = cs[k - 1] if k > 0 else np.zeros(3)
            w = (run.t[i0:i] - run.t[i0]) / max(run.t[i] - run.t[i0], 1e-9)
            d = cs[k] - c0
            d[2] = lp.wrap(d[2])
            corr[i0:i] = c0 + w[:, None] * d
    return lp.compose(corr, run.est), {"closures": len(ev)}


def oracle_fwd(run):
    return oracle(run, False)


def oracle_rep(run):
    return oracle(run, True)


def consistent(run, which=1, repair=True):
    """Closures that are perfect but only consistent: at a return, the pose error is set
    to the one the robot had at its first (which=1) or last (which=2) earlier visit of
    the place, as a match against the map drawn then would set it."""
    ev = returns(run, with_earlier=True)
    corr = np.zeros((run.n, 3))
    if not ev:
        return run.est.copy(), {"closures": 0}
    idx = [e[0] for e in ev]
    tgt = []
    for i, f, l in ev:
        j = f if which == 1 else l
        e = run.est[j] - run.true[j]
        p = run.true[i] + e
        tgt.append(p)
    cs = lp.compose(np.array(tgt), lp.inverse(run.est[idx]))
    for k, i in enumerate(idx):
        end = idx[k + 1] if k + 1 < len(idx) else run.n
        corr[i:end] = cs[k]
        if repair:
            i0 = idx[k - 1] if k > 0 else 0
            c0 = cs[k - 1] if k > 0 else np.zeros(3)
            w = (run.t[i0:i] - run.t[i0]) / max(run.t[i] - run.t[i0], 1e-9)
            d = cs[k] - c0
            d[2] = lp.wrap(d[2])
            corr[i0:i] = c0 + w[:, None] * d
    return lp.compose(corr, run.est), {"closures": len(idx)}


def oracle_first(run):
    return consistent(run, 1)


def oracle_last(run):
    return consistent(run, 2)


def graph(run, which=(1, 2), node_every=20, sxy=0.03, sth_deg=0.5, loop_sxy=0.02,
          loop_sth_deg=0.3, noise_m=0.0, noise_deg=0.0, ev_gap=5.0):
    """The ceiling of loop closure: a pose graph over the firmware's estimate (nodes
    every `node_every` readings, edges of its relative motion) with a perfect constraint
    (the true relative pose) at every return to a place, to its first (1) and/or last (2)
    earlier visit; node 0 fixed. Each reading takes its node's correction."""
    import posegraph
    ev = returns(run, with_earlier=True)
    keep, last_t = [], -1e9
    for e in ev:
        if run.t[e[0]] - last_t >= ev_gap:
            keep.append(e)
            last_t = run.t[e[0]]
    ev = keep
    rng = np.random.default_rng(1)
    nodes = np.arange(0, run.n, node_every)
    path = np.r_[0.0, np.cumsum(np.hypot(np.diff(run.est[:, 0]), np.diff(run.est[:, 1])))]
    x0 = run.est[nodes]
    edges = posegraph.odometry_edges(x0, path[nodes], sxy, sth_deg)
    info = np.array([1 / loop_sxy ** 2, 1 / loop_sxy ** 2, 1 / np.radians(loop_sth_deg) ** 2])
    for i, f, l in ev:
        for w, j in ((1, f), (2, l)):
            if w in which:
                ni, nj = i // node_every, j // node_every
                if ni != nj:
                    z = lp.between(run.true[nodes[nj]], run.true[nodes[ni]])
                    z = z + rng.normal(0, 1, 3) * [noise_m, noise_m, np.radians(noise_deg)]
                    edges.append((nj, ni, z, info))
    x = posegraph.solve(x0, edges)
    corr = lp.compose(x, lp.inverse(x0))
    seg = np.minimum(np.arange(run.n) // node_every, len(nodes) - 1)
    return lp.compose(corr[seg], run.est), {"closures": len(ev)}


def oracle_graph(run, **kw):
    if "which" in kw:
        kw["which"] = tuple(kw["which"])
    return graph(run, **kw)


def odom_true_heading(run, heading=None, **kw):
    """Odometry's distance increments integrated along the true heading: what a perfect
    heading alone (no position correction at all) would give."""
    o = run.odom
    ds = np.hypot(np.diff(o[:, 0]), np.diff(o[:, 1]))
    # sign: backwards motion (odometry moved against its heading)
    fwd = np.cos(np.arctan2(np.diff(o[:, 1]), np.diff(o[:, 0])) - o[:-1, 2])
    ds = ds * np.sign(np.where(np.abs(fwd) < 1e-9, 1.0, fwd))
    th = run.true[:, 2] if heading is None else heading
    mid = th[:-1] + lp.wrap(th[1:] - th[:-1]) / 2
    p = np.zeros((run.n, 3))
    p[0] = run.true[0]
    p[1:, 0] = p[0, 0] + np.cumsum(ds * np.cos(mid))
    p[1:, 1] = p[0, 1] + np.cumsum(ds * np.sin(mid))
    p[:, 2] = th
    return p, {}


def oracle_heading(run, white_deg=0.0, bias_deg=0.0, walk_deg=0.0, src="true", **kw):
    """Odometry distances along a heading: the true one with white noise, a constant bias
    or a random walk (σ per √minute) added; or the firmware's estimate (src "est")."""
    rng = np.random.default_rng(7)
    th = (run.true[:, 2] if src == "true" else run.est[:, 2]).copy()
    th += np.radians(bias_deg) + rng.normal(0, np.radians(white_deg) if white_deg else 0, run.n)
    if walk_deg:
        dt = np.diff(run.t, prepend=run.t[0])
        th += np.cumsum(rng.normal(0, 1, run.n) * np.radians(walk_deg) * np.sqrt(dt / 60.0))
    return odom_true_heading(run, th)
