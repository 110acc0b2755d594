#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The evidence map (OM, om_mode 1) in Python, to measure how a closure can repair it.

The firmware's mapper (mapper.c, grid.c) with localize = 0, in floating point: a
timeout lowers the robot's cell; an echo inside rc lowers the last 0.5 m of its beam up to
one cell short of the echo and raises the echo's cell by om_hit, after the faces rule (an
echo from a cell held as a wall lowers the cell behind it, to unknown at most); a far echo
lowers the last 0.5 m before rc. Bytes saturate at 1 and 255 (128 unknown).

What it measures (`repair` of loopclose.py's closures, on a run's log):
- "final": every reading at its final pose (what re-mapping the whole log would give;
  checks this port against host_sim --replay);
- "hits": the rays where the robot drew them as it went (the pose it held), the hits at
  their final poses: a repair that moves only the stored hits, exactly;
- "incremental": as the robot would: the map drawn as it goes, and at every closure each
  moved segment's hits taken out where they were (−om_hit, saturating) and put back where
  the closure puts them (+om_hit, saturating); the rays stay. Saturation makes the take-out
  inexact; this says how much that costs.

    tools/proto/omrepair.py RUN_DIR [key=value ...]   # loopclose.py parameters
"""
import math
import sys

import numpy as np

import lpcommon as lp

LO, ZERO, HI = 1, 128, 255
RAY = 0.5


class OM:
    def __init__(self, run):
        c = run.cfg
        self.cell = run.cell
        self.A = self.B = 256
        half = self.cell / 2
        self.ox = int(c["start_x_um"]) * 1e-6 - int(c["start_cell_a"]) * self.cell - half
        self.oy = int(c["start_y_um"]) * 1e-6 - int(c["start_cell_b"]) * self.cell - half
        self.hit = int(c["om_hit"])
        self.miss = int(c["om_miss"])
        self.rc = run.rc
        self.rmin = run.rmin
        self.g = np.full((self.B, self.A), ZERO, dtype=np.int32)

    def cellof(self, x, y):
        return int(math.floor((x - self.ox) / self.cell)), int(math.floor((y - self.oy) / self.cell))

    def inside(self, a, b):
        return 0 <= a < self.A and 0 <= b < self.B

    def lower(self, a, b, floor=LO):
        if self.inside(a, b):
            v = self.g[b, a]
            self.g[b, a] = v - self.miss if v > floor + self.miss else floor

    def add(self, x, y, step):
        a, b = self.cellof(x, y)
        if self.inside(a, b):
            self.g[b, a] = max(LO, min(HI, self.g[b, a] + step))

    def ray(self, x0, y0, x1, y1):
        a, b = self.cellof(x0, y0)
        a1, b1 = self.cellof(x1, y1)
        da, db = abs(a1 - a), abs(b1 - b)
        sa, sb = (1 if a1 >= a else -1), (1 if b1 >= b else -1)
        along_a = da >= db
        major, minor = (da, db) if along_a else (db, da)
        err = major // 2
        for _ in range(major + 1):
            if not self.inside(a, b):
                break
            self.lower(a, b)
            if along_a:
                a += sa
            else:
                b += sb
            err -= minor
            if err < 0:
                err += major
                if along_a:
                    b += sb
                else:
                    a += sa

    def occupied(self, a, b):
        return self.inside(a, b) and self.g[b, a] > ZERO

    def reading(self, pose, sensor, bearing, rng, rays=True, hits=True):
        """One reading: pose (x, y) of the robot, sensor origin and bearing, range (nan
        on a timeout). rays/hits: draw that part."""
        x, y = pose
        if not np.isfinite(rng):
            if rays:
                self.lower(*self.cellof(x, y))
            return
        if rng < self.rmin:
            return
        far = rng >= self.rc
        c, s = math.cos(bearing), math.sin(bearing)
        if rays and not far:
            hx, hy = sensor[0] + rng * c, sensor[1] + rng * s
            ha, hb = self.cellof(hx, hy)
            if self.inside(ha, hb) and not (rng <= self.cell and not self.occupied(ha, hb)):
                if self.occupied(ha, hb):
                    na, nb = self.cellof(sensor[0] + (rng + self.cell) * c,
                                         sensor[1] + (rng + self.cell) * s)
                    if (na, nb) != (ha, hb) and self.inside(na, nb) and self.g[nb, na] > ZERO:
                        self.lower(na, nb, ZERO)
        if rays:
            reach = self.rc if far else (rng - self.cell if rng > self.cell else 0.0)
            xe, ye = sensor[0] + reach * c, sensor[1] + reach * s
            xs, ys = x, y
            if reach > RAY:
                self.lower(*self.cellof(x, y))
                xs, ys = sensor[0] + (reach - RAY) * c, sensor[1] + (reach - RAY) * s
            self.ray(xs, ys, xe, ye)
        if hits and not far:
            self.add(sensor[0] + rng * c, sensor[1] + rng * s, self.hit)

    def image(self):
        """Trinary as the firmware exports it: occupied 0 where > 128, free 254 where
        < 128, 205 unknown; rows flipped (first row = top)."""
        img = np.full(self.g.shape, 205, np.uint8)
        img[self.g > ZERO] = 0
        img[self.g < ZERO] = 254
        return img[::-1]


def draw(run, ray_pose, hit_pose, om=None):
    om = om or OM(run)
    sx, sy, b = run.beam(ray_pose)
    hx, hy, hb = run.beam(hit_pose)
    for i in range(run.n):
        om.reading(ray_pose[i, :2], (sx[i], sy[i]), b[i], run.range[i], True, False)
        om.reading(hit_pose[i, :2], (hx[i], hy[i]), hb[i], run.range[i], False, True)
    return om


def score(run, om):
    return lp.mapscore.score(om.image() == 0, run.truth_mask, run.obs_mask)


def incremental(run, c):
    """The map as the robot would keep it: drawn at the held poses as it goes; at every
    closure the moved segments' hits taken out and put back (saturating)."""
    om = OM(run)
    held = lp.compose(c.held, run.est)
    sx, sy, b = run.beam(held)
    hit = run.hits_mask()
    events = sorted(c.history, key=lambda e: e[0])
    placed = np.zeros((c.nseg, 3))          # the correction each segment's hits lie at
    drawn = np.zeros(c.nseg, bool)
    ev = 0
    for k in range(c.nseg):
        for i in range(c.starts[k], c.ends[k] + 1):
            om.reading(held[i, :2], (sx[i], sy[i]), b[i], run.range[i], True, True)
        placed[k] = c.held[c.starts[k]]
        drawn[k] = True
        while ev < len(events) and events[ev][0] == k:
            newC = events[ev][1]
            moved = np.nonzero(drawn & (np.abs(newC - placed).max(axis=1) > 1e-9))[0]
            for j in moved:
                idx = np.arange(c.starts[j], c.ends[j] + 1)
                idx = idx[hit[idx]]
                if len(idx) == 0:
                    continue
                old = run.points(lp.compose(placed[j], run.est[idx]), sel=idx)
                new = run.points(lp.compose(newC[j], run.est[idx]), sel=idx)
                for p in old:
                    om.add(p[0], p[1], -om.hit)
                for p in new:
                    om.add(p[0], p[1], om.hit)
                placed[j] = newC[j]
            ev += 1
    return om


def main(argv):
    import loopclose as L
    run = lp.Run(argv[1])
    kw = {}
    for a in argv[2:]:
        k, v = a.split("=", 1)
        kw[k] = type(L.DEFAULTS[k])(v) if not isinstance(L.DEFAULTS[k], str) else v
    final, held, info, c = L.close_loops(run, **kw)
    print("closures %d" % info["accepted"])
    print("replay (host_sim) est %.4f final %.4f" % (run.score(run.est)["f1"], run.score(final)["f1"]))
    print("python est %.4f" % score(run, draw(run, run.est, run.est))["f1"])
    print("python final %.4f" % score(run, draw(run, final, final))["f1"])
    print("python hits-only %.4f" % score(run, draw(run, held, final))["f1"])
    print("python incremental %.4f" % score(run, incremental(run, c))["f1"])


if __name__ == "__main__":
    main(sys.argv)
