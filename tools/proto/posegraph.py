# SPDX-License-Identifier: MIT
"""A small 2-D pose graph: nodes are poses (x, y, th), edges relative poses with a
diagonal information; solved by Gauss-Newton on a sparse system, node 0 held fixed.

Used by oracle.py (perfect loop constraints: the ceiling of any loop closure given the
firmware's odometry) and loopclose.py (the matched constraints).
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.linalg import spsolve

import lpcommon as lp


def solve(x0, edges, iters=8, fixed=(0,), robust=None, robust_from=0, headings=None,
          period=np.pi / 2, head_huber=None):
    """x0: n×3 initial poses; edges: list of (i, j, z (3,), info (3,)) meaning
    between(x_i, x_j) ≈ z with information diag(info); headings: (idx (m,), target (m,),
    info (m,)), unary factors on θ_i modulo `period` (a wall seen at a known direction of
    the home's walls; Huber beyond head_huber σ). Returns the optimised poses."""
    x = np.array(x0, dtype=float)
    n = len(x)
    E = len(edges)
    I = np.array([e[0] for e in edges])
    J = np.array([e[1] for e in edges])
    Z = np.array([e[2] for e in edges], dtype=float)
    W = np.array([e[3] for e in edges], dtype=float)
    fixed = set(fixed)
    W0 = W.copy()
    use_m = headings is not None and len(headings[0]) > 0
    mvar = [headings[3] if use_m else 0.0]
    for _ in range(iters):
        xi, xj = x[I], x[J]
        c, s = np.cos(xi[:, 2]), np.sin(xi[:, 2])
        dx, dy = xj[:, 0] - xi[:, 0], xj[:, 1] - xi[:, 1]
        # predicted relative pose
        px = c * dx + s * dy
        py = -s * dx + c * dy
        pt = lp.wrap(xj[:, 2] - xi[:, 2])
        r = np.stack([px - Z[:, 0], py - Z[:, 1], lp.wrap(pt - Z[:, 2])], axis=1)
        if robust:
            # Huber: an edge whose Mahalanobis residual exceeds `robust` counts less
            # (edges before robust_from, the odometry, never).
            m = np.sqrt((W0 * r * r).sum(axis=1))
            f = np.where(m > robust, robust / np.maximum(m, 1e-12), 1.0)
            f[:robust_from] = 1.0
            W = W0 * f[:, None]
        # Jacobians (3×3 each) w.r.t. xi and xj
        Ji = np.zeros((E, 3, 3))
        Jj = np.zeros((E, 3, 3))
        Ji[:, 0, 0], Ji[:, 0, 1], Ji[:, 0, 2] = -c, -s, -s * dx + c * dy
        Ji[:, 1, 0], Ji[:, 1, 1], Ji[:, 1, 2] = s, -c, -c * dx - s * dy
        Ji[:, 2, 2] = -1.0
        Jj[:, 0, 0], Jj[:, 0, 1] = c, s
        Jj[:, 1, 0], Jj[:, 1, 1] = -s, c
        Jj[:, 2, 2] = 1.0
        rows, cols, vals = [], [], []
        b = np.zeros(3 * n + 1)
        bm = 0.0
        for (A, ia), (B, ib) in (((Ji, I), (Ji, I)), ((Ji, I), (Jj, J)), ((Jj, J), (Ji, I)),
                                 ((Jj, J), (Jj, J))):
            H = np.einsum("eki,ek,ekj->eij", A, W, B)
            for p in range(3):
                for q in range(3):
                    rows.append(3 * ia + p)
                    cols.append(3 * ib + q)
                    vals.append(H[:, p, q])
        for A, ia in ((Ji, I), (Jj, J)):
            g = np.einsum("eki,ek,ek->ei", A, W, r)
            for p in range(3):
                np.add.at(b, 3 * ia + p, g[:, p])
        rows = np.concatenate(rows)
        cols = np.concatenate(cols)
        vals = np.concatenate(vals)
        if headings is not None and len(headings[0]):
            # θ_i + ψ_i ≡ m (mod period): m, the home's wall direction, is one more
            # unknown (index 3n), solved with the poses, so that no early guess of it
            # turns the map.
            hi, psi, hw = headings[:3]
            rh = ((x[hi, 2] + psi - mvar[0] + period / 2) % period) - period / 2
            w = hw.copy()
            if head_huber:
                mm = np.abs(rh) * np.sqrt(hw)
                w = hw * np.where(mm > head_huber, head_huber / np.maximum(mm, 1e-12), 1.0)
            ti = 3 * hi + 2
            tm = np.full(len(hi), 3 * n)
            rows = np.concatenate([rows, ti, tm, ti, tm])
            cols = np.concatenate([cols, ti, tm, tm, ti])
            vals = np.concatenate([vals, w, w, -w, -w])
            np.add.at(b, ti, w * rh)
            bm = -(w * rh).sum()
        # fix nodes: strong prior
        for f in fixed:
            for p in range(3):
                rows = np.append(rows, 3 * f + p)
                cols = np.append(cols, 3 * f + p)
                vals = np.append(vals, 1e12)
        b[3 * n] = bm
        rows = np.append(rows, 3 * n)
        cols = np.append(cols, 3 * n)
        vals = np.append(vals, 1e-6)
        H = coo_matrix((vals, (rows, cols)), shape=(3 * n + 1, 3 * n + 1)).tocsc()
        dxv = spsolve(H, -b)
        mvar[0] += dxv[3 * n]
        dxv = dxv[:3 * n]
        x += dxv.reshape(n, 3)
        x[:, 2] = lp.wrap(x[:, 2])
        if np.abs(dxv).max() < 1e-6:
            break
    if use_m:
        solve.last_m = mvar[0]
    return x


def odometry_edges(poses, path, sxy=0.02, sth_deg=0.3, floor_m=0.05):
    """Edges between consecutive poses, their information falling with the path between
    them (σ² = s² · max(d, floor))."""
    out = []
    for i in range(len(poses) - 1):
        d = max(path[i + 1] - path[i], floor_m)
        z = lp.between(poses[i], poses[i + 1])
        info = np.array([1.0 / (sxy ** 2 * d), 1.0 / (sxy ** 2 * d),
                         1.0 / (np.radians(sth_deg) ** 2 * d)])
        out.append((i, i + 1, z, info))
    return out


def solve_lin(p0, path, loops, sxy=0.03, floor_m=0.05, robust=None, iters=3):
    """Positions only: nodes p (n×2) linked by their estimated displacements (σ² = sxy² ·
    path between them) and by loop edges (j, k, m (2,), σ): p_k − p_j ≈ m, in the world
    frame, p_0 held. The heading of the estimate is corrected by its own filter and hardly
    couples into its positions (a wall fixes the position across it whatever the heading
    did), so the chain is a linear least-squares problem, x and y apart. With `robust`,
    loop edges whose residual exceeds that many σ are down-weighted (Huber, iterated)."""
    n = len(p0)
    d = np.diff(p0, axis=0)
    w_odo = 1.0 / (sxy ** 2 * np.maximum(np.diff(path), floor_m))
    L = len(loops)
    J = np.array([l[0] for l in loops], dtype=np.int64)
    K = np.array([l[1] for l in loops], dtype=np.int64)
    M = np.array([l[2] for l in loops], dtype=float).reshape(L, 2)
    w_loop0 = np.array([1.0 / l[3] ** 2 for l in loops], dtype=float)
    w_loop = w_loop0.copy()
    idx = np.arange(n - 1)
    p = np.array(p0, dtype=float)
    for _ in range(iters if robust else 1):
        rows = np.concatenate([idx, idx + 1, idx, idx + 1, J, K, J, K, [0]])
        cols = np.concatenate([idx, idx + 1, idx + 1, idx, J, K, K, J, [0]])
        vals = np.concatenate([w_odo, w_odo, -w_odo, -w_odo, w_loop, w_loop, -w_loop, -w_loop,
                               [1e12]])
        H = coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsc()
        for ax in range(2):
            b = np.zeros(n)
            np.add.at(b, idx, -w_odo * d[:, ax])
            np.add.at(b, idx + 1, w_odo * d[:, ax])
            if L:
                np.add.at(b, J, -w_loop * M[:, ax])
                np.add.at(b, K, w_loop * M[:, ax])
            b[0] += 1e12 * p0[0, ax]
            p[:, ax] = spsolve(H, b)
        if not robust or not L:
            break
        r = np.hypot(*(p[K] - p[J] - M).T) * np.sqrt(w_loop0)
        w_loop = w_loop0 * np.where(r > robust, robust / np.maximum(r, 1e-12), 1.0)
    return p
