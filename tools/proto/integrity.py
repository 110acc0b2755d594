#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Pose-integrity flags from what the firmware's own estimate does, scored against the
truth. The estimate's motion less odometry's, reading by reading, is what the filter
applied (its matches and its learned drift), seen from outside. Candidates, each over the
last `window` metres of path (2, 5 and 10 m):

- quiet: no step over 0.05° or 2 mm (the filter has nothing to hold on to);
- busy: the summed heading steps exceed 2, 4 or 8°, or the summed position steps 0.1,
  0.2 or 0.4 m (the filter is being pulled about);
- quiet or busy.

Scored per reading as the issue defines it: hit rate = share of the readings whose
estimated pose is > 0.3 m or > 5° off that the flag covers (goal ≥ 0.90); false alarm =
share of the others it covers (goal ≤ 0.05). The filter's covariance and innovations
are not in the logs, so these are the only statistics of the firmware a log shows.

    tools/proto/integrity.py SET [--only SUBSTRING]
"""
import argparse
import math

import numpy as np

import lpcommon as lp

WINDOWS = (2.0, 5.0, 10.0)
BUSY_DEG = (2.0, 4.0, 8.0)
BUSY_M = (0.1, 0.2, 0.4)


def flags(run):
    """Boolean flags per reading, by name; and the truth's 'off' per reading."""
    # The step applied between two readings, in the robot's frame: the estimate's motion
    # less odometry's (zero unless a match moved the pose).
    d = lp.between(run.est[:-1], run.est[1:]) - lp.between(run.odom[:-1], run.odom[1:])
    dth = np.abs(lp.wrap(d[:, 2]))
    dxy = np.hypot(d[:, 0], d[:, 1])
    step = np.r_[False, (dth > math.radians(0.05)) | (dxy > 0.002)]
    dth = np.r_[0.0, dth]
    dxy = np.r_[0.0, dxy]
    path = np.r_[0.0, np.cumsum(np.hypot(np.diff(run.est[:, 0]), np.diff(run.est[:, 1])))]
    cs_step = np.cumsum(step)
    cs_th = np.cumsum(dth)
    cs_xy = np.cumsum(dxy)
    out = {}
    for w in WINDOWS:
        j = np.searchsorted(path, path - w, side="left")
        n_step = cs_step - cs_step[j]
        s_th = np.degrees(cs_th - cs_th[j])
        s_xy = cs_xy - cs_xy[j]
        started = path >= w
        quiet = started & (n_step == 0)
        out["quiet %g m" % w] = quiet
        for b in BUSY_DEG:
            out["busy %g° / %g m" % (b, w)] = s_th > b
            out["quiet or busy %g° / %g m" % (b, w)] = quiet | (s_th > b)
        for b in BUSY_M:
            out["busy %g m / %g m" % (b, w)] = s_xy > b
    pe, he = lp.pose_err(run.est, run.true)
    off = (pe > 0.3) | (he > math.radians(5))
    return out, off


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("set")
    ap.add_argument("--only", default="")
    a = ap.parse_args()
    acc = {}
    for rd in lp.run_dirs(a.set):
        if a.only not in rd["name"]:
            continue
        run = lp.Run(rd["dir"])
        fl, off = flags(run)
        g = "rooms" if rd["group"] == "rooms" else rd["group"]
        for grp in (g, "all"):
            t = acc.setdefault(grp, {"off": 0, "on": 0, "f": {}})
            t["off"] += int(off.sum())
            t["on"] += int((~off).sum())
            for k, f in fl.items():
                h, fa = t["f"].get(k, (0, 0))
                t["f"][k] = (h + int((f & off).sum()), fa + int((f & ~off).sum()))
    # The three flags of each group with the largest hit rate less false alarm.
    print("| group | share off | flag | hit rate | false alarm |")
    print("|---|---|---|---|---|")
    for grp in sorted(acc):
        t = acc[grp]
        n = t["off"] + t["on"]
        best = sorted(t["f"].items(), key=lambda kv: -(kv[1][0] / max(t["off"], 1) -
                                                        kv[1][1] / max(t["on"], 1)))
        for k, (h, fa) in best[:3]:
            print("| %s | %.3f | %s | %.2f | %.2f |" % (
                grp, t["off"] / max(n, 1), k, h / max(t["off"], 1), fa / max(t["on"], 1)))


if __name__ == "__main__":
    main()
