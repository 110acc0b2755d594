#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Heading held by the directions of walls: a heading filter over odometry, measured by
straight runs of sonar hits against a small set of wall directions the robot has seen.

Why: odometry's distances are good and its heading is not. Integrated along the true
heading, odometry's own distance increments map every run of the corpus as well as the
true poses (oracle.py oracle_heading: flats 0.877 against 0.879, rooms gap 0.000), and a
heading with 1° of white noise still does (0.873); what ruins the maps is heading error
that wanders (0.5°/√min of random walk: flats 0.615). A wall seen again, anywhere, tells
the heading absolutely, with an error that does not accumulate.

How (causal, reading by reading):
1. hits in the odometry frame (the run's odometry poses), kept per servo stop;
2. a line fit: when a stop's hits span `fit_m` of path driven straight (odometry turned
   less than `straight_deg`), at least `fit_min` points, their line within `par_deg` of the
   path (a wall beside the path: its hits are parallel to it whatever the incidence),
   residual rms under `fit_rms`: its direction φ in the odometry frame;
3. association: the known wall direction D (mod 180°) nearest to φ + b̂ (b̂ the heading
   offset estimate); a measurement b = D − φ when within `gate_k`·σ_b + `gate0_deg`;
4. a new direction is learned when a line matches none (farther than `new_deg`) while σ_b
   is below `learn_deg`; with `ortho` its perpendicular comes with it (homes are mostly
   rectilinear; 0 learns every direction from its own wall, slanted rooms included);
5. a scalar Kalman filter over b: variance grows by `q_m` per metre driven and `q_rad` per
   radian turned; a measurement has variance `r_deg`²;
6. the pose: odometry's distance increments along odometry's heading + b̂; with
   `smooth`, b between two measurements is interpolated (the path since the last
   measurement re-drawn, as a loop closure re-draws its loop).

    tools/proto/evaluate.py dev walldir [--set key=value ...]
    tools/proto/walldir.py RUN_DIR [key=value ...]
"""
import math
import sys

import numpy as np

import lpcommon as lp

DEFAULTS = dict(
    fit_m=0.6, fit_min=8, straight_deg=3.0, par_deg=10.0, fit_rms=0.012,
    gate_k=3.0, gate0_deg=3.0, new_deg=6.0, learn_deg=1.0, ortho=1,
    q_m=0.3, q_rad=0.8, r_deg=3.0, smooth=1, stop_round=1.0,
    mode="hist", win_hits=64, every_hits=16, pair_min=0.15, pair_max=0.8, bin_deg=0.25,
    blur_deg=0.75, prom=5.0, peak_pairs=30, joint=1, huber=0.0,
)


def dominant(p, P, period):
    """The dominant direction (rad, modulo `period`) of the segments between nearby
    points, from a histogram of their directions; with its prominence (peak over mean) and
    the number of pairs within a degree of it."""
    i, j = np.triu_indices(len(p), 1)
    d = p[j] - p[i]
    L = np.hypot(d[:, 0], d[:, 1])
    m = (L >= P["pair_min"]) & (L <= P["pair_max"])
    if m.sum() < P["peak_pairs"]:
        return None
    a = np.arctan2(d[m, 1], d[m, 0]) % period
    nb = int(round(math.degrees(period) / P["bin_deg"]))
    h = np.bincount((a / period * nb).astype(int) % nb, minlength=nb).astype(float)
    k = np.arange(-int(4 * P["blur_deg"] / P["bin_deg"]), int(4 * P["blur_deg"] / P["bin_deg"]) + 1)
    g = np.exp(-0.5 * (k * P["bin_deg"] / P["blur_deg"]) ** 2)
    hs = np.zeros(nb)
    for kk, gg in zip(k, g):
        hs += gg * np.roll(h, kk)
    c = int(np.argmax(hs))
    # sub-bin peak by a parabola through three bins
    y0, y1, y2 = hs[c - 1], hs[c], hs[(c + 1) % nb]
    den = y0 - 2 * y1 + y2
    off = 0.5 * (y0 - y2) / den if den != 0 else 0.0
    peak = (c + 0.5 + off) * period / nb
    near = np.abs(((a - peak + period / 2) % period) - period / 2) <= math.radians(1.0)
    return peak, hs[c] / max(hs.mean(), 1e-9), int(near.sum())


def fit_line(p):
    """Direction (rad, mod π), rms residual and extent of a PCA line through points."""
    c = p.mean(axis=0)
    q = p - c
    cov = q.T @ q / len(p)
    w, v = np.linalg.eigh(cov)
    d = v[:, 1]
    rms = math.sqrt(max(w[0], 0.0))
    along = q @ d
    return math.atan2(d[1], d[0]), rms, float(along.max() - along.min())


def wrap_half(a):
    """An angle modulo π, in [−π/2, π/2)."""
    return (a + math.pi / 2) % math.pi - math.pi / 2


def heading_filter(run, P):
    o = run.odom
    n = run.n
    hit = run.hits_mask()
    pts = run.points(o)
    ds_vec = np.diff(o[:, :2], axis=0)
    ds = np.hypot(ds_vec[:, 0], ds_vec[:, 1])
    dth = lp.wrap(np.diff(o[:, 2]))
    path = np.r_[0.0, np.cumsum(ds)]
    stops = np.round(run.servo_deg / P["stop_round"]).astype(int)
    buf = {}
    dirs = []                       # known wall directions (rad, mod π)
    b = 0.0
    var = math.radians(0.2) ** 2    # the start pose is known
    b_hist = np.zeros(n)
    s_hist = np.zeros(n)
    meas = []                       # (index, b measured)
    q_m = math.radians(P["q_m"]) ** 2
    q_rad = math.radians(P["q_rad"]) ** 2
    r = math.radians(P["r_deg"]) ** 2
    stats = {"fits": 0, "accepted": 0, "refused": 0, "learned": 0}
    period = math.pi / 2 if P["ortho"] else math.pi
    m_dir = None
    Pm = None
    recent = []
    since = 0
    for i in range(n):
        if i:
            var += q_m * ds[i - 1] + q_rad * abs(dth[i - 1])
        if hit[i] and P["mode"] == "hist":
            recent.append(i)
            if len(recent) > P["win_hits"]:
                recent.pop(0)
            since += 1
            if since >= P["every_hits"] and len(recent) == P["win_hits"]:
                since = 0
                r_ = dominant(pts[recent], P, period)
                if r_ is not None and r_[1] >= P["prom"] and r_[2] >= P["peak_pairs"]:
                    stats["fits"] += 1
                    phi = r_[0]
                    if P["ortho"] and P["joint"]:
                        # Two states: b and the direction m of the home's walls (mod
                        # period); a line at φ in the odometry frame says m − b = φ.
                        if m_dir is None:
                            m_dir = (phi + b) % period
                            Pm = np.array([[var, 0.0], [0.0, r + var]])
                            stats["learned"] += 1
                        else:
                            Pm[0, 0] = var
                            pred = m_dir - b
                            innov = ((phi - pred + period / 2) % period) - period / 2
                            H = np.array([-1.0, 1.0])
                            S = H @ Pm @ H + r
                            if abs(innov) <= P["gate_k"] * math.sqrt(S) + math.radians(P["gate0_deg"]):
                                if P["huber"]:
                                    c = P["huber"] * math.sqrt(S)
                                    innov = max(-c, min(c, innov))
                                K = Pm @ H / S
                                b += K[0] * innov
                                m_dir += K[1] * innov
                                Pm = Pm - np.outer(K, H @ Pm)
                                var = Pm[0, 0]
                                meas.append((i, b))
                                stats["accepted"] += 1
                            else:
                                stats["refused"] += 1
                        b_hist[i] = b
                        s_hist[i] = math.sqrt(var)
                        continue
                    phi = r_[0]
                    world = phi + b
                    best = None
                    for D in dirs:
                        e = ((D - world + period / 2) % period) - period / 2
                        if best is None or abs(e) < abs(best):
                            best = e
                    sig = math.sqrt(var)
                    if best is not None and abs(best) <= P["gate_k"] * sig + math.radians(P["gate0_deg"]):
                        z = b + best
                        k = var / (var + r)
                        b += k * (z - b)
                        var *= (1 - k)
                        meas.append((i, z))
                        stats["accepted"] += 1
                    elif best is None or (not P["ortho"] and abs(best) > math.radians(P["new_deg"])
                                          and sig <= math.radians(P["learn_deg"])):
                        # The first direction is learned whatever σ says: the start pose
                        # is known and the heading has had little time to drift.
                        dirs.append(world % period)
                        stats["learned"] += 1
                    else:
                        stats["refused"] += 1
        if hit[i] and P["mode"] == "line":
            bb = buf.setdefault(stops[i], [])
            bb.append(i)
            j0 = bb[0]
            turned = abs(math.degrees(lp.wrap(o[i, 2] - o[j0, 2])))
            if turned > P["straight_deg"]:
                buf[stops[i]] = [i]
            elif path[i] - path[j0] >= P["fit_m"]:
                idx = np.array(bb)
                buf[stops[i]] = []
                if len(idx) >= P["fit_min"]:
                    phi, rms, ext = fit_line(pts[idx])
                    psi = math.atan2(o[i, 1] - o[j0, 1], o[i, 0] - o[j0, 0])
                    par = abs(math.degrees(wrap_half(phi - psi)))
                    if rms <= P["fit_rms"] and par <= P["par_deg"] and ext >= 0.5 * P["fit_m"]:
                        stats["fits"] += 1
                        world = phi + b
                        best = None
                        for D in dirs:
                            e = wrap_half(D - world)
                            if best is None or abs(e) < abs(best):
                                best = e
                        sig = math.sqrt(var)
                        if best is not None and abs(best) <= P["gate_k"] * sig + math.radians(P["gate0_deg"]):
                            z = b + best
                            k = var / (var + r)
                            b += k * (z - b)
                            var *= (1 - k)
                            meas.append((i, z))
                            stats["accepted"] += 1
                        elif (best is None or abs(best) > math.radians(P["new_deg"])) and \
                                sig <= math.radians(P["learn_deg"]):
                            dirs.append(wrap_half(world))
                            if P["ortho"]:
                                dirs.append(wrap_half(world + math.pi / 2))
                            stats["learned"] += 1
                        else:
                            stats["refused"] += 1
        b_hist[i] = b
        s_hist[i] = math.sqrt(var)
    return b_hist, s_hist, meas, stats, path


def integrate(run, b):
    """Odometry's distance increments along odometry's heading + b."""
    o = run.odom
    d = np.diff(o[:, :2], axis=0)
    ds = np.hypot(d[:, 0], d[:, 1])
    fwd = np.cos(np.arctan2(d[:, 1], d[:, 0]) - o[:-1, 2])
    ds = ds * np.where(fwd < 0, -1.0, 1.0)
    th = o[:, 2] + b
    mid = th[:-1] + lp.wrap(th[1:] - th[:-1]) / 2
    p = np.zeros((run.n, 3))
    p[0] = o[0]
    p[1:, 0] = o[0, 0] + np.cumsum(ds * np.cos(mid))
    p[1:, 1] = o[0, 1] + np.cumsum(ds * np.sin(mid))
    p[:, 2] = lp.wrap(th)
    return p


def smooth(b_causal, meas, n):
    """b between measurements drawn straight from one filtered value to the next (what a
    closure that re-draws the path since the last wall would give)."""
    out = b_causal.copy()
    idx = [0] + [m[0] for m in meas]
    for a, c in zip(idx[:-1], idx[1:]):
        if c > a + 1:
            w = np.linspace(0, 1, c - a + 1)[:-1]
            out[a:c] = b_causal[a] + w * (b_causal[c] - b_causal[a])
    return out


def run_method(run, **kw):
    P = dict(DEFAULTS)
    P.update(kw)
    b, s, meas, stats, _ = heading_filter(run, P)
    held = integrate(run, b)
    pose = integrate(run, smooth(b, meas, run.n)) if P["smooth"] else held
    pe, he = lp.pose_err(held, run.true)
    stats["held_pos_mean"] = float(pe.mean())
    stats["held_head_mean_deg"] = float(np.degrees(he.mean()))
    stats["accepted_closures"] = stats["accepted"]
    return pose, dict(stats, accepted=stats["accepted"], refused=stats["refused"], wrong=0)


def main(argv):
    run = lp.Run(argv[1])
    kw = {}
    for a in argv[2:]:
        k, v = a.split("=", 1)
        kw[k] = type(DEFAULTS[k])(v)
    P = dict(DEFAULTS)
    P.update(kw)
    b, s, meas, stats, _ = heading_filter(run, P)
    true_b = lp.wrap(run.true[:, 2] - run.odom[:, 2])
    eb = np.degrees(np.abs(lp.wrap(b - true_b)))
    print(stats)
    print("heading error of the filter: mean %.2f° p95 %.2f° max %.2f°; odometry's %.2f°" % (
        eb.mean(), np.percentile(eb, 95), eb.max(), np.degrees(np.abs(true_b)).mean()))
    pose = integrate(run, smooth(b, meas, run.n) if P["smooth"] else b)
    print("F1 own %.3f est %.3f walldir %.3f true %.3f" % (
        run.own_f1(), run.score(run.est)["f1"], run.score(pose)["f1"], run.true_f1()))


if __name__ == "__main__":
    main(sys.argv)
