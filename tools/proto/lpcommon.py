# SPDX-License-Identifier: MIT
"""What the loop-closure prototypes share: the run sets, loading a run's log, re-mapping
corrected poses through the firmware's own mapper (host_sim --replay, localize = 0) and
scoring the map as metrics.json does (tools/mapscore.py).

Not a program: tools/proto/make_sets.py makes the runs, the other tools/proto scripts use
them. Paths: the runs live in out/proto/<set>/<name>/ of the worktree (git ignores out/).
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.dirname(HERE)
SRC = os.path.dirname(TOOLS)
OUT = os.path.join(SRC, "out", "proto")
HOST_SIM = os.path.join(SRC, "build", "host", "host_sim", "host_sim")
MAPS = os.path.join(os.path.dirname(os.path.dirname(SRC)), "shared", "maps")


# The tools' shared modules (tools/slamtools): the scoring of metrics.json and PGM reading.
if TOOLS not in sys.path:
    sys.path.insert(0, TOOLS)
from slamtools import mapscore, pgm  # noqa: E402

# The two sets: tuned on "dev", reported on "held" (other seeds; the held-out rooms and
# flats are the first of the corpus report's own, so its figures predict the report's).
# (group, duration s, kind, seeds)
SETS = {
    "dev": [("rooms", 600, "room", range(1001, 1031)),
            ("rooms", 1800, "room", range(1001, 1031)),
            ("flats", 3600, "flat", range(1001, 1007)),
            ("shipped", 600, "shipped", range(101, 104)),
            ("buildings", 1800, "building", range(101, 102))],
    "held": [("rooms", 600, "room", range(1, 31)),
             ("rooms", 1800, "room", range(1, 31)),
             ("flats", 3600, "flat", range(1, 7)),
             ("shipped", 600, "shipped", range(1, 6)),
             ("buildings", 1800, "building", range(1, 4))],
}
SHIPPED = ("clutter", "default", "flat", "narrow", "obstacles", "slanted")
BUILDINGS = (
    ("edu_room", "edu_room/edu_room_cropped.yaml", None),
    ("intel_lab", "intel_lab/intel.yaml", (5.0, 5.0, 12.0, 10.0)),
    ("willow_garage", "willow_garage/willow-2010-02-18-0.10.yaml", (20.0, 20.0, 12.0, 12.0)),
    ("utexas_gdc_3ne", "utexas_gdc_3ne/3ne.yaml", (-20.0, -10.0, 12.0, 10.0)),
)
AREA_BANDS = ((0, 12, "<12"), (12, 25, "12-25"), (25, 40, "25-40"), (40, 45, "40-45"),
              (45, 1e9, ">45"))


def band_of(area):
    return next(lbl for lo, hi, lbl in AREA_BANDS if lo <= area < hi)


def run_dirs(setname):
    """Every run of a set: list of dicts (dir, group, duration, name, area_m2)."""
    base = os.path.join(OUT, setname)
    with open(os.path.join(base, "runs.json")) as f:
        runs = json.load(f)
    for r in runs:
        r["dir"] = os.path.join(base, r["name"])
    return runs


class Run:
    """A run's log as numpy arrays: every reading (time, servo angle, range, status), the
    odometry, true and estimated pose of its ping, the scoring masks and the config."""

    def __init__(self, d):
        self.dir = d
        cols = None
        rows = []
        with open(os.path.join(d, "readings.csv")) as f:
            cols = f.readline().strip().split(",")
            for line in f:
                rows.append(line.rstrip("\n").split(","))
        ix = {c: i for i, c in enumerate(cols)}
        n = len(rows)
        self.n = n
        self.t = np.array([float(r[ix["t_s"]]) for r in rows])
        self.servo_deg = np.array([float(r[ix["servo_deg"]]) for r in rows])
        self.range = np.array([float(r[ix["range_m"]]) if r[ix["range_m"]] else np.nan
                               for r in rows])
        self.status = np.array([r[ix["status"]] for r in rows])
        self.odom = np.array([[float(r[ix[k]]) for k in ("odom_x_m", "odom_y_m", "odom_th_rad")]
                              for r in rows])
        self.true = np.array([[float(r[ix[k]]) for k in ("true_x_m", "true_y_m", "true_th_rad")]
                              for r in rows])
        self._rows, self._cols = rows, cols
        est = np.loadtxt(os.path.join(d, "scoring_estimate.csv"), delimiter=",", skiprows=1,
                         ndmin=2)
        assert est.shape[0] == n, d
        self.est = est[:, 1:4].copy()
        self.cfg = {}
        with open(os.path.join(d, "config.txt")) as f:
            for line in f:
                line = line.split("#")[0].strip()
                if "=" in line:
                    k, v = (s.strip() for s in line.split("=", 1))
                    self.cfg[k] = v
        self.mount_x = int(self.cfg["mount_x_um"]) * 1e-6
        self.mount_y = int(self.cfg["mount_y_um"]) * 1e-6
        self.mount_yaw = math.radians(int(self.cfg["mount_yaw_mdeg"]) * 1e-3)
        self.rc = int(self.cfg["confidence_radius_um"]) * 1e-6
        self.rmin = int(self.cfg["range_min_um"]) * 1e-6
        self.cell = int(self.cfg["cell_um"]) * 1e-6
        with open(os.path.join(d, "metrics.json")) as f:
            self.metrics = json.load(f)
        self.truth_mask, self.obs_mask = mapscore.load_truth(d)

    def beam(self, pose, sel=None):
        """Sensor position and beam bearing for poses (n×3) of the pings (Eq. 3: servo 90°
        straight ahead, larger to the right; the sensor sits at the mount offset)."""
        x, y, th = pose[:, 0], pose[:, 1], pose[:, 2]
        c, s = np.cos(th), np.sin(th)
        sx = x + c * self.mount_x - s * self.mount_y
        sy = y + s * self.mount_x + c * self.mount_y
        servo = self.servo_deg if sel is None else self.servo_deg[sel]
        bearing = th + math.pi / 2 - np.radians(servo) + self.mount_yaw
        return sx, sy, bearing

    def points(self, pose, mask=None, sel=None):
        """Echo points (n×2) of the readings under the given ping poses (of the readings
        `sel`, all when None)."""
        sx, sy, b = self.beam(pose, sel)
        r = np.nan_to_num(self.range if sel is None else self.range[sel])
        p = np.stack([sx + r * np.cos(b), sy + r * np.sin(b)], axis=1)
        return p if mask is None else p[mask]

    def hits_mask(self):
        """Readings that map a hit: an echo inside the confidence sector."""
        r = self.range
        return np.isfinite(r) & (r >= self.rmin) & (r < self.rc)

    def write_log(self, path, pose):
        """A copy of readings.csv with the given poses in the odometry columns."""
        ix = {c: i for i, c in enumerate(self._cols)}
        ox, oy, oth = ix["odom_x_m"], ix["odom_y_m"], ix["odom_th_rad"]
        with open(path, "w") as f:
            f.write(",".join(self._cols) + "\n")
            for r, p in zip(self._rows, pose):
                r = list(r)
                r[ox], r[oy] = "%.6f" % p[0], "%.6f" % p[1]
                th = math.atan2(math.sin(p[2]), math.cos(p[2]))
                r[oth] = "%.10f" % th
                f.write(",".join(r) + "\n")

    def remap(self, pose, keep=None):
        """OM of the log with the readings at the given poses, mapped by the firmware's own
        mapper (host_sim --replay, localize = 0); returns the trinary image."""
        with tempfile.TemporaryDirectory(dir=os.path.join(OUT, "tmp")) as tmp:
            log = os.path.join(tmp, "readings.csv")
            self.write_log(log, pose)
            cfg = os.path.join(tmp, "config.txt")
            with open(os.path.join(self.dir, "config.txt")) as f, open(cfg, "w") as g:
                for line in f:
                    g.write("localize = 0\n" if line.startswith("localize") else line)
            subprocess.run([HOST_SIM, "--quiet", "--replay", log, "--config", cfg, "--out",
                            os.path.join(tmp, "map")], check=True)
            img = pgm.read(os.path.join(tmp, "map", "om.pgm"))
            if keep:
                with open(os.path.join(tmp, "map", "om.pgm"), "rb") as f, open(keep, "wb") as g:
                    g.write(f.read())
        return img

    def score(self, pose, keep=None):
        """F1 (and the rest of mapscore's figures) of OM re-mapped at these poses."""
        img = self.remap(pose, keep)
        return mapscore.score(img == 0, self.truth_mask, self.obs_mask)

    def own_f1(self):
        return self.metrics["maps"]["odometry"]["raw"]["f1"]

    def true_f1(self):
        return self.metrics["maps"]["perfect_odometry"]["raw"]["f1"]


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def pose_err(pose, true):
    """Position (m) and heading (rad, absolute) error of each pose."""
    return np.hypot(pose[:, 0] - true[:, 0], pose[:, 1] - true[:, 1]), \
        np.abs(wrap(pose[:, 2] - true[:, 2]))


def percentile(xs, q):
    xs = sorted(xs)
    if not xs:
        return math.nan
    pos = (len(xs) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def stats(xs):
    """(mean, standard error, 5th percentile)."""
    xs = list(xs)
    n = len(xs)
    if n == 0:
        return (math.nan, math.nan, math.nan)
    m = sum(xs) / n
    se = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n) if n > 1 else math.nan
    return (m, se, percentile(xs, 5))


def groups_of(r):
    """The table rows a run falls in."""
    g = r["group"]
    if g == "rooms":
        out = ["rooms %d min" % (r["duration"] // 60), "rooms %d min %s m²" % (
            r["duration"] // 60, band_of(r["area_m2"]))]
        if r["area_m2"] <= 45:
            out.append("rooms %d min <=45 m²" % (r["duration"] // 60))
        return out
    return [g]


# --- SE(2): a pose or a correction is (x, y, th); compose(a, b) is a∘b (b in a's frame).

def compose(a, b):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    return np.stack([a[..., 0] + c * b[..., 0] - s * b[..., 1],
                     a[..., 1] + s * b[..., 0] + c * b[..., 1],
                     wrap(a[..., 2] + b[..., 2])], axis=-1)


def inverse(a):
    a = np.asarray(a, dtype=float)
    c, s = np.cos(a[..., 2]), np.sin(a[..., 2])
    return np.stack([-c * a[..., 0] - s * a[..., 1], s * a[..., 0] - c * a[..., 1],
                     -a[..., 2]], axis=-1)


def between(a, b):
    """a⁻¹∘b: b seen from a."""
    return compose(inverse(a), b)
