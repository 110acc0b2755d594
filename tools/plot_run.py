#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Draws the figure of a host_sim run: truth, raw OM, post-processed OM, TM, trajectories.

usage: tools/plot_run.py OUT_DIR        writes OUT_DIR/figure.png

Reads the run's PGM maps, trajectory.csv and metrics.json (Debian's python3-matplotlib
and python3-numpy).
"""
import csv
import json
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:
    sys.exit("plot_run: %s (install: tools/install-deps.sh sim)" % e)


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields = []
    pos = 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P5":
        raise ValueError("%s: not a binary PGM" % path)
    w, h, maxval = int(fields[1]), int(fields[2]), int(fields[3])
    img = np.frombuffer(data[pos + 1:pos + 1 + w * h], dtype=np.uint8).reshape(h, w)
    return img, maxval


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 else 2)
    out = sys.argv[1]
    with open(os.path.join(out, "metrics.json")) as f:
        m = json.load(f)
    sc = m["scenario"]
    cell = sc["cell_mm"] / 1000.0
    ox, oy = sc["grid"]["origin"]
    a, b = sc["grid"]["a"], sc["grid"]["b"]
    extent = [ox, ox + a * cell, oy, oy + b * cell]
    x0, y0, x1, y1 = sc["room_bounds"]
    margin = 0.3

    ox_, oy_, tx, ty = [], [], [], []
    with open(os.path.join(out, "trajectory.csv")) as f:
        for row in csv.DictReader(f):
            ox_.append(float(row["odom_x"]))
            oy_.append(float(row["odom_y"]))
            tx.append(float(row["true_x"]))
            ty.append(float(row["true_y"]))

    maps = m["maps"]["odometry"]
    panels = [
        ("truth", "ground truth", None),
        ("om", "raw OM  (F1 %.2f)" % maps["raw"]["f1"], None),
        ("om_post", "post-processed OM  (F1 %.2f)" % maps["insert"]["f1"], None),
        ("tm", "trajectory map TM", None),
    ]
    fig, axes = plt.subplots(1, 5, figsize=(22, 5))
    for ax, (name, title, _) in zip(axes, panels):
        img, _ = read_pgm(os.path.join(out, name + ".pgm"))
        ax.imshow(img, cmap="gray", vmin=0, vmax=255, extent=extent, interpolation="nearest")
        ax.set_title(title)
    ax = axes[4]
    img, _ = read_pgm(os.path.join(out, "truth.pgm"))
    ax.imshow(img, cmap="gray", vmin=0, vmax=255, extent=extent, interpolation="nearest",
              alpha=0.5)
    ax.plot(tx, ty, color="tab:green", lw=1.0, label="true path")
    ax.plot(ox_, oy_, color="tab:red", lw=1.0, label="odometry")
    ax.plot(tx[:1], ty[:1], "ko", ms=5, label="start")
    od = m["odometry"]
    ax.set_title("paths: final odometry error %.2f m" % od["final_position_m"])
    ax.legend(loc="lower right", fontsize=8)
    for ax in axes:
        ax.set_xlim(x0 - margin, x1 + margin)
        ax.set_ylim(y0 - margin, y1 + margin)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    fig.suptitle("%s  -  %.0f s, seed %d, %d mm cells, %s exploration%s" % (
        os.path.basename(sc["room"]), sc["duration_s"], sc["seed"], sc["cell_mm"],
        sc["explore"], ", ideal" if sc["ideal"] else ""))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figure.png"), dpi=90, metadata={"Software": None})


if __name__ == "__main__":
    main()
