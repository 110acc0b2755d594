# SPDX-License-Identifier: MIT
"""Oracle closures (DESIGN §7's yardstick): at every return to a place after an excursion,
the pose error is known and taken out. Not a method: what perfect closures would buy.

- "fwd": from the return on, the corrected pose is the truth's correction of that moment
  applied to the firmware's estimate (relocalization: the map drawn before stays).
- "rep": also between the previous return and this one the correction is spread linearly
  over time (a pose graph with perfect constraints, crudely smoothed).

A return: the true position comes within `radius` of where the robot was at least `away`
seconds earlier, while it has not been within that radius of there in the last `away`
seconds... simplified: a place (a cell of `radius`) whose last visit ended `away` seconds
or more ago. tools/proto/evaluate.py runs it: `evaluate.py dev oracle_fwd oracle_rep`.
"""
import numpy as np

import lpcommon as lp


def returns(run, radius=0.5, away=60.0):
    """Indices of the readings at which the robot returns to a place left `away` s ago."""
    last = {}
    events = []
    prev_ev_t = -1e9
    for i in range(0, run.n):
        x, y = run.true[i, 0], run.true[i, 1]
        key = (int(np.floor(x / radius)), int(np.floor(y / radius)))
        t = run.t[i]
        was = last.get(key)
        if was is not None and t - was >= away and t - prev_ev_t >= 5.0:
            events.append(i)
            prev_ev_t = t
        last[key] = t
    return events


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
