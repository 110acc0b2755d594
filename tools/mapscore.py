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
import sys

from slamtools import mapscore
from slamtools.errors import ToolError, main as tool_main


def main(argv):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(argv) != 3:
        raise ToolError("usage: tools/mapscore.py MAP.pgm RUN_DIR (--help says more)")
    truth, observable = mapscore.load_truth(argv[2])
    s = mapscore.score_file(argv[1], truth, observable)
    print("precision %.4f recall %.4f f1 %.4f (mapped %d, true positive %d, observable %d, "
          "matched %d)" % (s["precision"], s["recall"], s["f1"], s["mapped"],
                           s["true_positive"], s["observable"], s["matched"]))
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv)
