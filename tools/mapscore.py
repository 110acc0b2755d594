#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Scores a trinary map against a run's truth, by the rule of host_sim's metrics (DESIGN §5).

    tools/mapscore.py MAP.pgm RUN_DIR

RUN_DIR is a `host_sim --scoring` run: scoring_truth.pgm (the room's boundary cells) and
scoring_observable.pgm (the cells within rc of a sonar position), black where set, in
the orientation of om.pgm. A map's occupied cells are its black (0) pixels, whichever
program wrote it. A mapped cell is a true positive when a truth cell lies within one cell
(Chebyshev); recall is the share of observable truth cells with a mapped cell within one.
"""
import os
import sys

import numpy as np

EXIT_USAGE = 2


class ScoreError(Exception):
    """A file that is not what the scorer needs; the message names it."""


def read_pgm(path):
    """A binary (P5) 8-bit PGM as a 2-D uint8 array, first row first."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ScoreError("%s: cannot read: %s" % (path, e.strerror)) from None
    fields = []
    pos = 0
    while len(fields) < 4:  # magic, width, height, maxval; '#' comments between
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.find(b"\n", pos) + 1 or len(data)
            continue
        end = pos
        while end < len(data) and not data[end:end + 1].isspace():
            end += 1
        if end == pos:
            raise ScoreError("%s: not a PGM (the header ends early)" % path)
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P5" or not all(f.isdigit() for f in fields[1:]) or fields[3] != b"255":
        raise ScoreError("%s: not an 8-bit binary PGM (P5, maxval 255)" % path)
    w, h = int(fields[1]), int(fields[2])
    body = data[pos + 1:pos + 1 + w * h]
    if len(body) != w * h:
        raise ScoreError("%s: %d bytes of pixels, %d x %d needs %d" % (path, len(body), w, h, w * h))
    return np.frombuffer(body, dtype=np.uint8).reshape(h, w)


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
            raise ScoreError("%s: missing (run host_sim with --scoring)" % path)
        masks.append(read_pgm(path) == 0)
    if masks[0].shape != masks[1].shape:
        raise ScoreError("%s: the two masks differ in size" % run_dir)
    return masks[0], masks[1]


def score_file(map_path, truth, observable):
    """The score of a trinary PGM (occupied = 0) against a run's masks."""
    img = read_pgm(map_path)
    if img.shape != truth.shape:
        raise ScoreError("%s: %d x %d, the run's grid is %d x %d" % (
            map_path, img.shape[1], img.shape[0], truth.shape[1], truth.shape[0]))
    return score(img == 0, truth, observable)


def main(argv):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(argv) != 3:
        print("usage: tools/mapscore.py MAP.pgm RUN_DIR (--help says more)", file=sys.stderr)
        return EXIT_USAGE
    try:
        truth, observable = load_truth(argv[2])
        s = score_file(argv[1], truth, observable)
    except ScoreError as e:
        print("mapscore: %s" % e, file=sys.stderr)
        return EXIT_USAGE
    print("precision %.4f recall %.4f f1 %.4f (mapped %d, true positive %d, observable %d, "
          "matched %d)" % (s["precision"], s["recall"], s["f1"], s["mapped"],
                           s["true_positive"], s["observable"], s["matched"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
