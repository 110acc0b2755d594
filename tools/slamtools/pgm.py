# SPDX-License-Identifier: MIT
"""The one reader and writer of the maps the project exports: binary 8-bit PGM (P5,
maxval 255, '#' comments in the header) with a ROS map_server YAML beside it.

Every size is bounded before memory is taken for it: a file of at most FILE_MAX bytes,
images of 1..SIDE_MAX pixels a side (the largest grid of firmware/include/slam/grid.h).
Anything else is a ToolError (exit 2) that names the file and what is wrong with it.
Images are numpy uint8 arrays, first row the image's top (north), as the files hold them.
"""
import os
import stat

from . import link
from .errors import ToolError

# A map record of the largest grid is 32 MiB, an image of it 16 MiB.
FILE_MAX = 64 << 20
SIDE_MAX = link.GRID_SIDE_MAX


def read_file(path, limit=FILE_MAX):
    """A whole regular file of at most limit bytes, never reading more than a byte beyond
    (a FIFO would wait and a device never end, so neither is read)."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise ToolError("%s: not a regular file" % path)
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as e:
        raise ToolError("%s: cannot read: %s" % (path, e.strerror)) from None
    if len(data) > limit:
        raise ToolError("%s: larger than %d bytes: no map of a robot's grid is" % (path, limit))
    return data


def parse(data, where):
    """The image in a PGM file's bytes; where names the file in a message."""
    import numpy as np
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maxval
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            end = data.find(b"\n", pos)
            if end < 0:
                break
            pos = end + 1
            continue
        end = pos
        while end < len(data) and not data[end:end + 1].isspace():
            end += 1
        if end == pos:
            break
        fields.append(data[pos:end])
        pos = end
    if len(fields) < 4 or fields[0] != b"P5" or not all(f.isdigit() for f in fields[1:]) \
            or fields[3] != b"255" or pos >= len(data):
        raise ToolError("%s: not a binary 8-bit PGM (P5, maxval 255)" % where)
    w, h = int(fields[1]), int(fields[2])
    if not (1 <= w <= SIDE_MAX and 1 <= h <= SIDE_MAX):
        raise ToolError("%s: %d x %d pixels: a map is 1..%d a side" % (where, w, h, SIDE_MAX))
    body = data[pos + 1:pos + 1 + w * h]  # one whitespace byte ends the header
    if len(body) != w * h:
        raise ToolError("%s: %d bytes of pixels, %d x %d needs %d" % (where, len(body), w, h, w * h))
    return np.frombuffer(body, dtype=np.uint8).reshape(h, w)


def read(path):
    """The image of a PGM file."""
    return parse(read_file(path), path)


def encode(img):
    """A 2-D uint8 array as the bytes of a PGM file, as the simulator writes them."""
    h, w = img.shape
    return b"P5\n%d %d\n255\n" % (w, h) + img.tobytes()


def write(path, img):
    """A PGM file of a 2-D uint8 array (first row the top)."""
    with open(path, "wb") as f:
        f.write(encode(img))


def yaml_text(name, cell_um, origin_x_um, origin_y_um):
    """The map_server YAML of NAME.pgm, a trinary map, as the C programs write it."""
    return link.MAP_YAML % (name, link.um_text(cell_um), link.um_text(origin_x_um),
                            link.um_text(origin_y_um))


def read_yaml(path):
    """The keys of a map_server YAML the tools use (the simple form the project writes):
    resolution (m a cell), origin [x, y] (m), occupied_thresh, free_thresh, negate."""
    keys = {}
    try:
        for line in read_file(path, 1 << 20).decode("utf-8").splitlines():
            k, _, v = line.partition(":")
            keys[k.strip()] = v.strip()
        out = {"resolution": link.parse_real(keys["resolution"], 1e-6, 1e4),
               "origin": [link.parse_real(v.strip(), -1e7, 1e7)
                          for v in keys["origin"].strip("[]").split(",")[:2]],
               "occupied_thresh": link.parse_real(keys.get("occupied_thresh", "0.65"), 0, 1),
               "free_thresh": link.parse_real(keys.get("free_thresh", "0.196"), 0, 1),
               "negate": link.parse_int(keys.get("negate", "0"), 0, 1)}
    except (KeyError, ValueError, UnicodeDecodeError):
        raise ToolError("%s: not a map_server YAML with a resolution and an origin" % path) from None
    if len(out["origin"]) != 2:
        raise ToolError("%s: the origin needs x and y" % path)
    return out
