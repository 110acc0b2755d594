#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Draws the maps of a run into a PNG and says where it wrote it.

usage: tools/plot_run.py TARGET [--out PNG] [--quiet]

TARGET is one of:
  a host_sim output folder     truth, raw OM, post-processed OM, TM and both paths
                               (metrics.json, trajectory.csv and the maps)
  a host_sim --replay folder   the OM it rebuilt (om.pgm with om.yaml)
  a robot's storage folder     the newest good map record of its slots (slot0.bin,
                               slot1.bin: the Linux robot's storage_dir, host_sim
                               --storage) and the maps it wrote on exit (om.pgm,
                               om_post.pgm, tm.pgm)
  a file                       a dump of an MCU's storage flash, or one slot file: the
                               newest record in it whose CRCs check out

The picture goes to TARGET/figure.png (for a file: FILE.png beside it) unless --out
names another. Needs Debian's python3-matplotlib and python3-numpy. What it believes of a
file is bounded: files of at most 64 MiB, grids and images of 3..4096 cells a side
(firmware/include/slam/grid.h), record headers of at most 1 KiB.
Exit status: 0 drawn; 1 the picture could not be written; 2 nothing to draw in TARGET.
"""
import csv
import json
import os
import struct
import sys
import zlib

from slamtools import link as slamlink, pgm
from slamtools.commands import take_value
from slamtools.errors import ToolError, main as tool_main

MAGIC = 0x4D414C53  # "SLAM": mapstore.h
# What a tool believes of a header before it allocates by it: a grid of GRID_SIDE_MIN ..
# GRID_SIDE_MAX cells a side (grid.h), a header of at most a KiB, and files of at most
# pgm.FILE_MAX bytes: a record of the largest grid is 32 MiB; an MCU's flash is 1 MiB, a
# Linux robot's slot at most 16 MiB (storage_bytes), an image of the largest grid 16 MiB.
HEADER_MAX = 1024
HEADER = struct.Struct("<IHHHHIiiIIiiIBBBBII")
HEADER_NAMES = ("magic", "version", "header_bytes", "a", "b", "cell_um", "origin_x_um",
                "origin_y_um", "seq", "ticks", "pose_x_um", "pose_y_um", "pose_heading",
                "om_mode", "om_hit", "om_miss", "om_max", "data_crc", "header_crc")
MAP_NAMES = (("truth", "ground truth"), ("om", "OM: obstacle map"),
             ("om_post", "OM after post-processing"), ("om_ideal", "OM from the true poses"),
             ("tm", "TM: trajectory map"))


def records(data, where):
    """Every map record in a dump whose header and data CRCs check out, as
    (header dict, OM rows, TM rows), numpy arrays with row 0 at the bottom. A header whose
    grid or size no robot writes (GRID_SIDE_MIN .. GRID_SIDE_MAX cells a side, at most
    HEADER_MAX bytes) is not a record, whatever its CRC says."""
    import numpy as np
    out = []
    magic = struct.pack("<I", MAGIC)
    off = -1
    side = range(slamlink.GRID_SIDE_MIN, slamlink.GRID_SIDE_MAX + 1)
    while True:
        off = data.find(magic, off + 1)
        if off < 0 or off + HEADER.size > len(data):
            break
        h = dict(zip(HEADER_NAMES, HEADER.unpack_from(data, off)))
        cells = h["a"] * h["b"]
        start = off + h["header_bytes"]
        if (h["a"] not in side or h["b"] not in side or h["header_bytes"] > HEADER_MAX or
                h["header_bytes"] < HEADER.size or
                zlib.crc32(data[off:off + HEADER.size - 4]) != h["header_crc"] or
                start + 2 * cells > len(data) or
                zlib.crc32(data[start:start + 2 * cells]) != h["data_crc"]):
            continue
        om = np.frombuffer(data[start:start + cells], np.uint8).reshape(h["b"], h["a"])
        tm = np.frombuffer(data[start + cells:start + 2 * cells], np.uint8).reshape(h["b"], h["a"])
        h["where"] = "%s at byte %d" % (where, off)
        out.append((h, om, tm))
    return out


def label(ax, title):
    ax.set_title(title)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")


def figure_of_run(out, plt):
    """The full figure of a host_sim run (its metrics, trajectories and maps)."""
    try:
        with open(os.path.join(out, "metrics.json")) as f:
            m = json.load(f)
        sc = m["scenario"]
        cell = sc["cell_mm"] / 1000.0
        ox, oy = sc["grid"]["origin"]
        a, b = sc["grid"]["a"], sc["grid"]["b"]
        x0, y0, x1, y1 = sc["room_bounds"]
        maps = m["maps"]["odometry"]
        final_err = m["odometry"]["final_position_m"]
        path = {"odom": ([], []), "true": ([], [])}
        with open(os.path.join(out, "trajectory.csv")) as f:
            for row in csv.DictReader(f):
                for k in path:
                    path[k][0].append(float(row[k + "_x_m"]))
                    path[k][1].append(float(row[k + "_y_m"]))
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise ToolError("%s: not a complete host_sim output (%s)" % (out, e))
    extent = [ox, ox + a * cell, oy, oy + b * cell]
    panels = [("truth", "ground truth"),
              ("om", "raw OM (F1 %.2f)" % maps["raw"]["f1"]),
              ("om_post", "post-processed OM (F1 %.2f)" % maps["insert"]["f1"]),
              ("tm", "trajectory map TM")]
    fig, axes = plt.subplots(1, 5, figsize=(22, 5))
    for ax, (name, title) in zip(axes, panels):
        ax.imshow(pgm.read(os.path.join(out, name + ".pgm")), cmap="gray", vmin=0, vmax=255,
                  extent=extent, interpolation="nearest")
        label(ax, title)
    ax = axes[4]
    ax.imshow(pgm.read(os.path.join(out, "truth.pgm")), cmap="gray", vmin=0, vmax=255,
              extent=extent, interpolation="nearest", alpha=0.5)
    ax.plot(*path["true"], color="tab:green", lw=1.0, label="true path")
    ax.plot(*path["odom"], color="tab:red", lw=1.0, label="odometry")
    ax.plot(path["true"][0][:1], path["true"][1][:1], "ko", ms=5, label="start")
    ax.legend(loc="lower right", fontsize=8)
    label(ax, "paths: final odometry error %.2f m" % final_err)
    margin = 0.3
    for ax in axes:
        ax.set_xlim(x0 - margin, x1 + margin)
        ax.set_ylim(y0 - margin, y1 + margin)
    fig.suptitle("%s  -  %.0f s, seed %d, %d mm cells, %s exploration%s" % (
        os.path.basename(sc["room"]), sc["duration_s"], sc["seed"], sc["cell_mm"],
        sc["explore"], ", ideal" if sc["ideal"] else ""))
    return fig


def pgm_panels(folder):
    """The maps of a folder that have their YAML: (title, image, extent)."""
    panels = []
    for name, title in MAP_NAMES:
        image = os.path.join(folder, name + ".pgm")
        yaml = os.path.join(folder, name + ".yaml")
        if os.path.isfile(image) and os.path.isfile(yaml):
            img = pgm.read(image)
            geo = pgm.read_yaml(yaml)
            res, (ox, oy) = geo["resolution"], geo["origin"]
            h, w = img.shape
            panels.append((title + " (%s.pgm)" % name, img,
                           [ox, ox + w * res, oy, oy + h * res], None))
    return panels


def record_panels(recs, quiet):
    """OM and TM of the newest record, drawn as the simulator draws them."""
    import numpy as np
    h, om, tm = max(recs, key=lambda r: r[0]["seq"])
    if not quiet:
        print("plot_run: the newest good map record is number %d (%s), saved at t = %.2f s"
              % (h["seq"], h["where"], h["ticks"] / 100.0))
    cell = h["cell_um"] * 1e-6
    ox, oy = h["origin_x_um"] * 1e-6, h["origin_y_um"] * 1e-6
    ext = [ox, ox + h["a"] * cell, oy, oy + h["b"] * cell]
    pose = (h["pose_x_um"] * 1e-6, h["pose_y_um"] * 1e-6)
    when = "saved at t = %.1f s (record %d, %s)" % (h["ticks"] / 100.0, h["seq"], h["where"])
    return [("OM " + when, slamlink.trinary(h["om_mode"], om, tm), ext, pose),
            ("TM " + when, slamlink.counts_image(tm, tm.max()), ext, pose)]


def figure_of_maps(panels, title, plt):
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 6), squeeze=False)
    for ax, (name, img, ext, pose) in zip(axes[0], panels):
        ax.imshow(img, cmap="gray", vmin=0, vmax=255, extent=ext, interpolation="nearest")
        if pose is not None:
            ax.plot([pose[0]], [pose[1]], "ro", ms=5, label="robot at the save")
            ax.legend(loc="lower right", fontsize=8)
        # Zoom onto what was seen: the cells that are not unknown-white, with a margin.
        seen = (img < 250).nonzero()
        if len(seen[0]):
            h, w = img.shape
            cx = (ext[1] - ext[0]) / w
            cy = (ext[3] - ext[2]) / h
            ax.set_xlim(ext[0] + (seen[1].min() - 10) * cx, ext[0] + (seen[1].max() + 10) * cx)
            ax.set_ylim(ext[3] - (seen[0].max() + 10) * cy, ext[3] - (seen[0].min() - 10) * cy)
        label(ax, name)
    fig.suptitle(title)
    return fig


def main(argv):
    args = [a for a in argv[1:] if a not in ("--quiet",)]
    quiet = "--quiet" in argv[1:]
    out_png = take_value(args, "--out", "a file name")
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args and args[0] in ("-h", "--help") else 2
    target = args[0]
    if not os.path.exists(target):
        raise ToolError("%s: no such file or folder" % target)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ToolError("%s (install: tools/install-deps.sh sim)" % e)

    if os.path.isdir(target):
        png = out_png or os.path.join(target, "figure.png")
        if os.path.isfile(os.path.join(target, "metrics.json")):
            fig = figure_of_run(target, plt)
        else:
            panels = pgm_panels(target)
            recs = []
            for name in sorted(os.listdir(target)):
                if name.startswith("slot") and name.endswith(".bin"):
                    recs += records(pgm.read_file(os.path.join(target, name)), name)
            if recs:
                panels += record_panels(recs, quiet)
            if not panels:
                raise ToolError("%s holds nothing to draw: no metrics.json (a host_sim run), no "
                            "om.pgm with om.yaml (a replay, a robot's maps), no slot*.bin "
                            "with a good map record" % target)
            fig = figure_of_maps(panels, os.path.abspath(target), plt)
    else:
        png = out_png or os.path.splitext(target)[0] + ".png"
        recs = records(pgm.read_file(target), os.path.basename(target))
        if not recs:
            raise ToolError("%s holds no map record whose CRCs check out (a dump of the storage "
                        "flash or a slot file is expected)" % target)
        fig = figure_of_maps(record_panels(recs, quiet), os.path.abspath(target), plt)
    fig.tight_layout()
    try:
        fig.savefig(png, dpi=90, metadata={"Software": None})
    except OSError as e:
        raise ToolError("cannot write %s: %s" % (png, e.strerror), 1)
    if not quiet:
        print("plot_run: wrote %s" % png)
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv)
