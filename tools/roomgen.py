#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Household rooms and multi-room flats for the simulator, each drawn from a seed.

usage: tools/roomgen.py room SEED [--out FILE] [--png FILE]
       tools/roomgen.py flat SEED [--out FILE] [--png FILE]
       tools/roomgen.py corpus --rooms N --flats M [--first-seed S] --out DIR
       tools/roomgen.py figure [--out PNG]

A *room* is a rectangle or an L-shape, 3-9 m a side, 9 to 60 m² (its target area is
drawn from four bands, 9-12, 12-25, 25-40 and 40-60 m², so every band of the corpus
report gets members), sometimes split by a partition wall with a door. A *flat* is up to
12 m × 12 m: a hall across it, rooms on both sides of it (and sometimes a room at its end),
inner walls 0.1 m thick, a door 0.7-0.9 m wide from every room to the hall and some between
rooms. Both are furnished: boxes against the walls (sofas, cabinets, shelves, beds,
wardrobes), tables and desks on four legs 12-30 mm thick (with chairs on legs around some
tables), round bins and pots (radius 0.1-0.25 m) in corners and beside furniture, and in
rooms free-standing screens (20-50 mm thick, 0.8-1.6 m long).

Before a file is written its geometry is checked on a 5 cm raster: every place where a
disc of 0.275 m radius fits (a passage of 0.55 m) is reachable from the start through such
places, every room and hall holds one of them, and the start has 0.4 m clear around it.
A draw that fails is drawn again from the same stream (so still the seed's room), with
less furniture after ten failures and none after twenty.

Determinism: every number comes from random.Random(seed).random() and arithmetic on it
(+ - * / and the square root, which IEEE 754 rounds alike everywhere; no randint, choice or
uniform, whose algorithms Python may change); coordinates are whole millimetres, written as
metres with three decimals: the same seed gives the same bytes in every Python 3.
Exit status: 0 done, 1 a file could not be written, 2 bad arguments.
"""
import argparse
import os
import sys

from slamtools import roomfile
from slamtools.errors import ToolError, main as tool_main
from slamtools.roomgen import make, room_text, write_corpus


# The rooms the figure shows: a rectangle, L-shapes, a partition, small and large.
FIGURE = (("room", 1), ("room", 3), ("room", 15), ("room", 22), ("room", 2), ("flat", 1))


def figure(path, scenes=FIGURE):
    """Generated rooms and a flat side by side in one PNG."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ToolError("%s (tools/install-deps.sh sim)" % e, 1)
    cols = 3
    rows = -(-len(scenes) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.6 * rows), squeeze=False)
    for ax, (kind, seed) in zip(axes.flat, scenes):
        sc = make(kind, seed)
        room = roomfile.parse(room_text(sc))
        what = "%d rooms and a hall" % (len(sc.parts) - 1) if kind == "flat" else \
            sc.shape + (", a partition" if sc.doors else "")
        roomfile.draw(room, ax, "%s %d: %s, %.1f m²" % (kind, seed, what, sc.area_m2()))
    for ax in list(axes.flat)[len(scenes):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=60, metadata={"Software": None})


def draw_one(sc, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ToolError("%s (tools/install-deps.sh sim)" % e, 1)
    fig, ax = plt.subplots(figsize=(7, 7))
    roomfile.draw(roomfile.parse(room_text(sc)), ax, "%s %d, %.1f m²" % (sc.kind, sc.seed,
                                                                        sc.area_m2()))
    fig.tight_layout()
    fig.savefig(path, dpi=80, metadata={"Software": None})


def seed_arg(text):
    try:
        v = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError("'%s' is not a whole number" % text)
    if v < 0:
        raise argparse.ArgumentTypeError("%d: a seed is 0 or more" % v)
    return v


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/roomgen.py", usage=argparse.SUPPRESS,
                                 description=__doc__.strip(),
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", metavar="{room,flat,corpus,figure}")
    sub.required = True
    for kind, what in (("room", "one room"), ("flat", "one flat")):
        p = sub.add_parser(kind, help="%s, to stdout or --out" % what)
        p.add_argument("seed", type=seed_arg, metavar="SEED")
        p.add_argument("--out", metavar="FILE", help="write the .room file here (default: stdout)")
        p.add_argument("--png", metavar="FILE", help="also draw it into this PNG (matplotlib)")
    p = sub.add_parser("corpus", help="N rooms and M flats from seed S on, and index.json")
    p.add_argument("--rooms", type=seed_arg, required=True, metavar="N")
    p.add_argument("--flats", type=seed_arg, required=True, metavar="M")
    p.add_argument("--first-seed", type=seed_arg, default=1, metavar="S")
    p.add_argument("--out", required=True, metavar="DIR")
    p = sub.add_parser("figure", help="a few rooms and a flat in one PNG")
    p.add_argument("--out", default=os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "host_sim", "figures", "corpus.png"), metavar="PNG",
        help="(default host_sim/figures/corpus.png)")
    args = ap.parse_args(argv)
    try:
        if args.what == "corpus":
            index = write_corpus(args.out, args.rooms, args.flats, args.first_seed)
            print("roomgen: %d rooms and %d flats in %s" % (args.rooms, args.flats, args.out),
                  file=sys.stderr)
            return 0 if index else 1
        if args.what == "figure":
            figure(args.out)
            return 0
        sc = make(args.what, args.seed)
        text = room_text(sc)
        if args.out:
            with open(args.out, "w") as f:
                f.write(text)
        else:
            sys.stdout.write(text)
        if args.png:
            draw_one(sc, args.png)
    except OSError as e:
        raise ToolError("%s: %s" % (e.filename or args.out, e.strerror), 1)
    return 0


if __name__ == "__main__":
    tool_main(main)
