# SPDX-License-Identifier: MIT
"""A trinary map scored against a run's truth by the rule of host_sim's metrics (DESIGN §5):
a mapped (black) cell is right within one cell (Chebyshev) of a truth cell; recall is the
share of observable truth cells with a mapped cell within one. tools/mapscore.py is the
command line, tools/compare.py scores OctoMap's maps with it."""
import os

import numpy as np

from . import pgm
from .errors import ToolError


def near(mask):
    """Cells within Chebyshev distance 1 of a set cell (the grid's edge clips)."""
    p = np.pad(mask, 1)
    h, w = mask.shape
    out = np.zeros_like(mask)
    for dy in range(3):
        for dx in range(3):
            out |= p[dy:dy + h, dx:dx + w]
    return out


def score(occupied, truth, observable):
    """Precision, recall and F1 of boolean maps of one shape, with the counts behind them."""
    mapped = int(occupied.sum())
    true_pos = int((occupied & near(truth)).sum())
    counted = truth & observable
    n_obs = int(counted.sum())
    matched = int((counted & near(occupied)).sum())
    p = true_pos / mapped if mapped else 0.0
    r = matched / n_obs if n_obs else 0.0
    f1 = 2.0 * p * r / (p + r) if p + r > 0.0 else 0.0
    return {"precision": p, "recall": r, "f1": f1, "mapped": mapped, "true_positive": true_pos,
            "observable": n_obs, "matched": matched}


def load_truth(run_dir):
    """The run's (truth, observable) boolean masks."""
    masks = []
    for name in ("scoring_truth.pgm", "scoring_observable.pgm"):
        path = os.path.join(run_dir, name)
        if not os.path.exists(path):
            raise ToolError("%s: missing (run host_sim with --scoring)" % path)
        masks.append(pgm.read(path) == 0)
    if masks[0].shape != masks[1].shape:
        raise ToolError("%s: the two masks differ in size" % run_dir)
    return masks[0], masks[1]


def score_file(map_path, truth, observable):
    """The score of a trinary PGM (occupied = 0) against a run's masks."""
    img = pgm.read(map_path)
    if img.shape != truth.shape:
        raise ToolError("%s: %d x %d, the run's grid is %d x %d" % (
            map_path, img.shape[1], img.shape[0], truth.shape[1], truth.shape[0]))
    return score(img == 0, truth, observable)
