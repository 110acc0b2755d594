#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""What going back to mapped structure would buy (active localization), estimated from the
logs where the robot happened to come back: for every return to a place (oracle.returns: a
0.5 m cell left at least 60 s before), the path driven since it was last there (the
excursion) and how far the firmware's pose error moved meanwhile (the relative error a
closure at that return must take out, and the map drawn on the way carries).

    tools/proto/excursions.py SET     # prints, per group, the relative error by excursion
"""
import sys

import numpy as np

import lpcommon as lp
import oracle

BINS = ((0, 10), (10, 20), (20, 40), (40, 80), (80, 1e9))


def main(setname):
    rows = {}
    for rd in lp.run_dirs(setname):
        if rd["group"] not in ("rooms", "flats", "buildings"):
            continue
        run = lp.Run(rd["dir"])
        path = np.r_[0.0, np.cumsum(np.hypot(np.diff(run.true[:, 0]), np.diff(run.true[:, 1])))]
        e = run.est[:, :2] - run.true[:, :2]
        eth = lp.wrap(run.est[:, 2] - run.true[:, 2])
        g = rd["group"] + (" %d min" % (rd["duration"] // 60) if rd["group"] == "rooms" else "")
        for i, _, last in oracle.returns(run, with_earlier=True):
            L = path[i] - path[last]
            rows.setdefault(g, []).append((L, float(np.hypot(*(e[i] - e[last]))),
                                           float(np.degrees(abs(lp.wrap(eth[i] - eth[last]))))))
    print("| group | excursion (m of path) | returns | share | relative position error: median | 90th pct | heading: median | 90th pct |")
    print("|---|---|---|---|---|---|---|---|")
    for g in sorted(rows):
        a = np.array(rows[g])
        for lo, hi in BINS:
            m = (a[:, 0] >= lo) & (a[:, 0] < hi)
            if m.sum() == 0:
                continue
            print("| %s | %g–%s | %d | %.2f | %.3f | %.3f | %.1f | %.1f |" % (
                g, lo, "%g" % hi if hi < 1e9 else "", m.sum(), m.mean(), np.median(a[m, 1]),
                np.percentile(a[m, 1], 90), np.median(a[m, 2]), np.percentile(a[m, 2], 90)))


if __name__ == "__main__":
    main(sys.argv[1])
