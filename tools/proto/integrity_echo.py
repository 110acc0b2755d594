#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A pose-integrity flag from evidence the matcher does not use: echoes that end where OM
holds free space. A lost pose puts its echoes inside rooms it has mapped; a good one puts
them on walls, or where nothing was mapped yet. From `scoring_estimate.csv`'s `om_at_echo`
(OM's byte where each echo within rc ends, seen from the estimate; 128 unknown, one less
for each beam that crossed the cell), a reading is flagged when at least a share S of the
last N such echoes ended in a cell F or more below 128.

Scored per reading as issue 34 defines it, the readings of each group pooled: hit rate =
share of the readings whose estimate is > 0.3 m or > 5° off that are flagged (goal
>= 0.90), false alarm = share of the others flagged (goal <= 0.05). F, N and S are tuned
on the first corpus folder (all groups pooled), then applied unchanged to the second.

    tools/corpus_report.py --keep --host-arg=--scoring --out DIR_A
    tools/corpus_report.py --keep --host-arg=--scoring --out DIR_B --seeds 40 \
        --first-seed 5000 --shift-start 0.1 --maps /nonexistent
    tools/proto/integrity_echo.py DIR_A DIR_B
"""
import csv, glob, math, os, sys
import numpy as np

def load(run):
    rd = list(csv.DictReader(open(run + '/readings.csv')))
    es = list(csv.DictReader(open(run + '/scoring_estimate.csv')))
    n = min(len(rd), len(es))
    rd, es = rd[:n], es[:n]
    tx = np.array([float(r['true_x_m']) for r in rd]); ty = np.array([float(r['true_y_m']) for r in rd])
    tt = np.array([float(r['true_th_rad']) for r in rd])
    ex = np.array([float(r['est_x_m']) for r in es]); ey = np.array([float(r['est_y_m']) for r in es])
    et = np.array([float(r['est_th_rad']) for r in es])
    dth = np.abs((et - tt + math.pi) % (2 * math.pi) - math.pi)
    off = (np.hypot(ex - tx, ey - ty) > 0.3) | (dth > math.radians(5))
    st = [r['status'] for r in rd]
    om = np.array([float(r['om_at_echo']) if r['om_at_echo'] != '' else np.nan for r in es])
    ok = np.array([s == 'ok' for s in st]) & ~np.isnan(om)
    return off, ok, om

def group(run):
    b = os.path.basename(run)
    return b.split('-')[0] + b.split('-')[1]

def flags(ok, om, F, N, S):
    idx = np.nonzero(ok)[0]
    fr = (om[idx] <= 128 - F).astype(float)
    c = np.concatenate([[0], np.cumsum(fr)])
    k = np.arange(1, len(idx) + 1)
    lo = np.maximum(k - N, 0)
    share = (c[k] - c[lo]) / np.maximum(k - lo, 1)
    full = np.zeros(len(ok))
    # forward fill: each reading takes the share as of the last ok echo at or before it
    pos = np.searchsorted(idx, np.arange(len(ok)), side='right') - 1
    valid = pos >= 0
    full[valid] = share[pos[valid]]
    return full >= S

def runs_of(d):
    return sorted(r for r in glob.glob(d + '/*-*-*') if os.path.exists(r + '/scoring_estimate.csv'))

def table(data, F, N, S):
    out = {}
    for g, items in data.items():
        h = fa = no = nn = 0
        for off, ok, om in items:
            f = flags(ok, om, F, N, S)
            h += np.sum(f & off); no += np.sum(off); fa += np.sum(f & ~off); nn += np.sum(~off)
        out[g] = (h / no if no else float('nan'), fa / nn if nn else float('nan'), no / (no + nn))
    return out

def main():
    if len(sys.argv) != 3 or sys.argv[1].startswith('-'):
        print(__doc__.strip())
        return 2
    sets = []
    for d in sys.argv[1:3]:
        data = {}
        for r in runs_of(d):
            data.setdefault(group(r), []).append(load(r))
        sets.append(data)
    tune, test = sets
    pooled = {'all': [x for v in tune.values() for x in v]}
    best = []
    for F in (1, 2, 3, 5, 8, 16):
        for N in (8, 16, 32, 64, 128):
            for S in (0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5):
                h, fa, _ = table(pooled, F, N, S)['all']
                best.append((h - fa, h, fa, F, N, S))
    best.sort(reverse=True)
    ok5 = sorted([b for b in best if b[2] <= 0.05], key=lambda b: -b[1])[:3]
    for tag, rows in (('best hit-false', best[:3]), ('best hit at false <= 0.05', ok5)):
        for _, h, fa, F, N, S in rows:
            print('%s: om <= 128-%d in a share >= %.2f of the last %d echoes within rc' % (tag, F, S, N))
            for name, data in (('tune', tune), ('test', test)):
                t = table(data, F, N, S)
                print('   %s: ' % name + '  '.join('%s %.2f/%.2f (off %.3f)' % (g, *t[g]) for g in sorted(t)))

if __name__ == '__main__':
    sys.exit(main())
