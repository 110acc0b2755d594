# SPDX-License-Identifier: MIT
"""Household rooms and flats drawn from a seed: the model of tools/roomgen.py (its --help
says what a room and a flat are, and why every number is drawn the way it is)."""
import json
import math
import os
import textwrap

from . import roomfile
from .furnish import DOOR_KEEP, Draw, Face, Region, Scene, furnish_all
from .roomfile import START_CLEAR

WALL_T = 100       # mm: inner walls
DOOR_MIN, DOOR_MAX = 700, 900    # mm: door openings
ROOM_BANDS = ((9, 12, 0.12), (12, 25, 0.33), (25, 40, 0.30), (40, 60, 0.25))  # m², weight


# --- layouts -----------------------------------------------------------------------

def faces_of(rect, doors):
    """The four inner faces of a rectangular room, less its door openings."""
    x0, y0, x1, y1 = rect
    sides = (("h", y0, x0, x1, 1), ("h", y1, x0, x1, -1),
             ("v", x0, y0, y1, 1), ("v", x1, y0, y1, -1))
    out = []
    for axis, c, lo, hi, inward in sides:
        cuts = sorted((dr[0], dr[2]) if axis == "h" else (dr[1], dr[3]) for dr in doors
                      if (axis == "h" and c in (dr[1], dr[3]) and dr[0] < hi and lo < dr[2]) or
                      (axis == "v" and c in (dr[0], dr[2]) and dr[1] < hi and lo < dr[3]))
        for a, b in cuts:
            if a > lo:
                out.append(Face(axis, c, lo, a, inward))
            lo = b
        if hi > lo:
            out.append(Face(axis, c, lo, hi, inward))
    return out


def wall_with_doors(scene, axis, c, lo, hi, doors):
    """An inner wall from lo to hi at c (its low side), and the given doors (start, width)
    through it: its boxes, the openings and the floor kept free before them."""
    for a, w in sorted(doors):
        if a > lo:
            scene.inner.append((lo, c, a, c + WALL_T) if axis == "h" else (c, lo, c + WALL_T, a))
        opening = (a, c, a + w, c + WALL_T) if axis == "h" else (c, a, c + WALL_T, a + w)
        scene.doors.append(opening)
        scene.keep.append((a, c - DOOR_KEEP, a + w, c + WALL_T + DOOR_KEEP) if axis == "h" else
                          (c - DOOR_KEEP, a, c + WALL_T + DOOR_KEEP, a + w))
        lo = a + w
    if hi > lo:
        scene.inner.append((lo, c, hi, c + WALL_T) if axis == "h" else (c, lo, c + WALL_T, hi))


def door_in(d, lo, hi, margin=150):
    """A door (start, width) somewhere between lo and hi, `margin` from each end."""
    w = d.mm(DOOR_MIN, DOOR_MAX)
    return (d.mm(lo + margin, hi - margin - w), w)


def room_outline(d):
    """Shape, bounding box (mm) and the notch an L-shape leaves out of it."""
    lo, hi, _ = d.weighted(ROOM_BANDS)
    target = lo + (hi - lo) * d.u()
    ell = target >= 12 and d.chance(0.4)
    fx, fy = (0.35 + 0.2 * d.u(), 0.35 + 0.2 * d.u()) if ell else (0.0, 0.0)
    box = target / (1 - fx * fy)
    aspect = 1 + (max(1.0, min(1.8, box / 9, 81 / box)) - 1) * d.u()
    w = min(9.0, max(3.0, math.sqrt(box * aspect)))
    h = min(9.0, max(3.0, box / w))
    w, h = (h, w) if d.chance(0.5) else (w, h)
    w, h = int(w * 100 + 0.5) * 10, int(h * 100 + 0.5) * 10
    if not ell:
        return "rectangle", w, h, None
    nw, nh = int(fx * w / 10 + 0.5) * 10, int(fy * h / 10 + 0.5) * 10
    right, top = d.chance(0.5), d.chance(0.5)
    return ("L-shape", w, h, (w - nw if right else 0, h - nh if top else 0,
                              w if right else nw, h if top else nh))


def outline_walls(w, h, notch):
    """The outline's walls (zero-width rectangles): the box, less the notch's corner."""
    pts = [(0, 0), (w, 0), (w, h), (0, h)]
    if notch:
        x0, y0, x1, y1 = notch
        k = pts.index((0 if x0 == 0 else w, 0 if y0 == 0 else h))
        corner, inner = pts[k], (x1 if x0 == 0 else x0, y1 if y0 == 0 else y0)

        def on_edge(p):  # where the edge from p to the corner meets the notch
            return (inner[0], corner[1]) if p[1] == corner[1] else (corner[0], inner[1])
        pts[k:k + 1] = [on_edge(pts[k - 1]), inner, on_edge(pts[(k + 1) % 4])]
    return [(min(a[0], b[0]), min(a[1], b[1]), max(a[0], b[0]), max(a[1], b[1]))
            for a, b in zip(pts, pts[1:] + pts[:1])]


def wall_faces(scene):
    """The faces of the outline (cut where an inner wall meets it) and of the inner walls'
    long sides."""
    out = []
    for x0, y0, x1, y1 in scene.walls:
        if y0 == y1:
            out.append(Face("h", y0, x0, x1, 1 if scene.inside((x0 + x1) / 2, y0 + 1) else -1))
        else:
            out.append(Face("v", x0, y0, y1, 1 if scene.inside(x0 + 1, (y0 + y1) / 2) else -1))
    for x0, y0, x1, y1 in scene.inner:
        if x1 - x0 > WALL_T:
            out += [Face("h", y0, x0, x1, -1), Face("h", y1, x0, x1, 1)]
        if y1 - y0 > WALL_T:
            out += [Face("v", x0, y0, y1, -1), Face("v", x1, y0, y1, 1)]
    cut = []
    for f in out:
        spans = [(b[0], b[2]) if f.axis == "h" else (b[1], b[3]) for b in scene.inner
                 if (b[1] if f.inward > 0 else b[3]) == f.c and f.axis == "h"
                 or (b[0] if f.inward > 0 else b[2]) == f.c and f.axis == "v"]
        lo = f.lo
        for a, b in sorted(spans):
            if a > lo and a < f.hi:
                cut.append(Face(f.axis, f.c, lo, a, f.inward))
            lo = max(lo, b)
        if f.hi > lo:
            cut.append(Face(f.axis, f.c, lo, f.hi, f.inward))
    return cut


def split(rects, axis, c):
    """Rectangles cut by an inner wall from c to c + WALL_T across them (axis: the wall's)."""
    out = []
    for r in rects:
        lo, hi = (r[0], r[2]) if axis == "v" else (r[1], r[3])
        if not lo < c < hi:
            out.append(r)
        elif axis == "v":
            out += [(r[0], r[1], c, r[3]), (c + WALL_T, r[1], r[2], r[3])]
        else:
            out += [(r[0], r[1], r[2], c), (r[0], c + WALL_T, r[2], r[3])]
    return out


def partition(d, scene, rects):
    """Sometimes a wall across the room's longer side, with a door, 1.5 m or more from
    the walls parallel to it; returns the floor's rectangles."""
    w, h, notch = scene.w, scene.h, scene.notch
    if max(w, h) < 5000 or not d.chance(0.35):
        return rects
    axis = "v" if w >= h else "h"
    size = w if axis == "v" else h
    edges = ([notch[0], notch[2]] if axis == "v" else [notch[1], notch[3]]) if notch else []
    for _ in range(10):
        c = d.mm(1500, size - 1500 - WALL_T)
        if any(0 < e < size and e - 1500 - WALL_T < c < e + 1500 for e in edges):
            continue
        span = [r for r in rects if (r[0] < c < r[2] if axis == "v" else r[1] < c < r[3])]
        lo = min(r[1] if axis == "v" else r[0] for r in span)
        hi = max(r[3] if axis == "v" else r[2] for r in span)
        wall_with_doors(scene, axis, c, lo, hi, [door_in(d, lo, hi, 200)])
        return split(rects, axis, c)
    return rects


def make_room(seed):
    """The room of a seed (a Scene, checked, with its start)."""
    d = Draw(seed)
    shape, w, h, notch = room_outline(d)
    sc = Scene("room", seed, w, h)
    sc.shape, sc.notch = shape, notch
    sc.walls = outline_walls(w, h, notch)
    rects = [(0, 0, w, h)]
    if notch:  # the two arms: the one as wide as the box, and the rest
        x0, y0, x1, y1 = notch
        rects = [(0, y1, w, h) if y0 == 0 else (0, 0, w, y0),
                 (x1, y0, w, y1) if x0 == 0 else (0, y0, x0, y1)]
    rects = partition(d, sc, rects)
    sc.parts = [("part%d" % (k + 1), r) for k, r in enumerate(rects)]
    region = Region("room", rects, wall_faces(sc), sc.area_m2())
    return furnish_all(d, sc, [region], None)


def strip(d, x_end):
    """Rooms side by side from 0 to x_end, each 2.4 m wide or more: their (x0, x1)."""
    k = d.count(-(-(x_end + WALL_T) // (5000 + WALL_T)), (x_end + WALL_T) // (2400 + WALL_T))
    spare = x_end - (k - 1) * WALL_T - k * 2400
    cuts = sorted(d.mm(0, spare) for _ in range(k - 1)) + [spare]
    out, x, prev = [], 0, 0
    for c in cuts:
        width = 2400 + c - prev
        out.append((x, x + width))
        x, prev = x + width + WALL_T, c
    return out


def make_flat(seed):
    """The flat of a seed: a hall across it (along x, or along y when transposed), rooms
    on both sides, sometimes one at its end."""
    d = Draw(seed)
    hw = d.mm(1100, 1600, 50)
    w = d.mm(7000, 12000, 100)
    h = d.mm(5000 + 2 * WALL_T + hw + 100, 12000, 100)
    hy = d.mm(2500, h - 2 * WALL_T - hw - 2500, 100)
    hall = (hy + WALL_T, hy + WALL_T + hw)
    top = hall[1] + WALL_T
    xe = w - WALL_T - d.mm(3000, min(4500, w * 45 // 100)) if w >= 8000 and d.chance(0.5) else w
    sc = Scene("flat", seed, w, h)
    sc.walls = outline_walls(w, h, None)
    below, above = strip(d, xe), strip(d, xe)
    wall_with_doors(sc, "h", hy, 0, xe, [door_in(d, a, b) for a, b in below])
    wall_with_doors(sc, "h", hall[1], 0, xe, [door_in(d, a, b) for a, b in above])
    for rooms, lo, hi in ((below, 0, hy), (above, top, h)):
        for _, b in rooms[:-1]:
            wall_with_doors(sc, "v", b, lo, hi, [door_in(d, lo, hi)] if d.chance(0.3) else [])
    if xe < w:
        doors = [door_in(d, hall[0], hall[1], 100)]
        doors += [door_in(d, 0, hy)] if d.chance(0.3) else []
        doors += [door_in(d, top, h)] if d.chance(0.3) else []
        wall_with_doors(sc, "v", xe, 0, h, doors)
    rects = [("hall", (0, hall[0], xe, hall[1]))]
    rects += [("room", (a, 0, b, hy)) for a, b in below]
    rects += [("room", (a, top, b, h)) for a, b in above]
    rects += [("room", (xe + WALL_T, 0, w, h))] if xe < w else []
    names = ["hall"] + ["room%d" % k for k in range(1, len(rects))]
    sc.parts = [(n, r) for n, (_, r) in zip(names, rects)]
    regions = [Region(n, [r], faces_of(r, sc.doors), (r[2] - r[0]) * (r[3] - r[1]) / 1e6,
                      n == "hall")
               for n, r in sc.parts]
    flip = d.chance(0.5)
    prefer = "hall" if d.chance(0.6) else d.pick(names[1:])
    furnish_all(d, sc, regions, prefer)
    return transpose(sc) if flip else sc


def transpose(sc):
    """The same flat mirrored across x = y (a hall along y instead of x)."""
    def t(r):
        return (r[1], r[0], r[3], r[2])
    out = Scene(sc.kind, sc.seed, sc.h, sc.w)
    out.shape = sc.shape
    out.walls, out.inner, out.doors = [t(r) for r in sc.walls], [t(r) for r in sc.inner], \
        [t(r) for r in sc.doors]
    out.parts = [(n, t(r)) for n, r in sc.parts]
    out.items = [(lab, fam, t(fp), [t(b) for b in boxes], [(c[1], c[0], c[2]) for c in circ])
                 for lab, fam, fp, boxes, circ in sc.items]
    x, y, th = sc.start
    out.start = (y, x, (90 - th) % 360)
    return out


# --- the file ----------------------------------------------------------------------

def m(v):
    """Millimetres as metres, three decimals."""
    assert v >= 0
    return "%d.%03d" % (v // 1000, v % 1000)


def counted(labels):
    seen = {}
    for lab in labels:
        seen[lab] = seen.get(lab, 0) + 1
    return ", ".join(lab if n == 1 else "%d %s" % (n, plural(lab))
                     for lab, n in sorted(seen.items()))


def plural(word):
    head, _, tail = word.partition(" ")
    head = {"shelf": "shelves"}.get(head, head + "s")
    return head + (" " + tail if tail else "")


def summary(sc):
    """What a scene holds, in words (its file's header)."""
    if sc.kind == "room":
        what = ["%s %s m x %s m%s, floor area %.2f m²" % (
            "an L-shaped room in a box of" if sc.notch else "a rectangular room,",
            m(sc.w), m(sc.h), "", sc.area_m2())]
        what.append("a partition wall with a %s m door" % m(door_width(sc.doors[0]))
                    if sc.doors else "no partition wall")
    else:
        what = ["a flat of %s m x %s m, floor area %.2f m², a hall and %d rooms" % (
            m(sc.w), m(sc.h), sc.area_m2(), len(sc.parts) - 1),
            "inner walls %s m thick with %d doors of %s m" % (
                m(WALL_T), len(sc.doors), ", ".join(m(door_width(r)) for r in sc.doors))]
    fam = {f: [it for it in sc.items if it[1] == f] for f in ("wall", "table", "bin", "screen")}
    what.append("against the walls: %s" % (counted(it[0] for it in fam["wall"]) or "nothing"))
    what.append("tables on legs: %s" % (counted(it[0] for it in fam["table"]) or "none"))
    what.append("bins and pots: %s" % (counted(it[0] for it in fam["bin"]) or "none"))
    if sc.kind == "room":
        what.append("screens: %d" % len(fam["screen"]))
    what.append("%d legs in all" % sum(len(it[4]) for it in sc.items if it[4] and it[1] != "bin"))
    return "; ".join(what) + "."


def door_width(r):
    return max(r[2] - r[0], r[3] - r[1])


def room_text(sc):
    """The .room file of a scene."""
    head = "%s %d of tools/roomgen.py (kind %s, seed %d): %s" % (
        sc.kind.capitalize(), sc.seed, sc.kind, sc.seed, summary(sc))
    head += (" The start has %.1f m clear; every place with %.3f m clear (a %.2f m passage) is "
             "reachable from it. '# part NAME x y w h': the floor's rectangles (rooms, hall); "
             "'# door x y w h': the openings through inner walls." % (
                 START_CLEAR / 1000, roomfile.PASS / 1000, 2 * roomfile.PASS / 1000))
    lines = ["# SPDX-License-Identifier: MIT"]
    lines += ["# " + t for t in textwrap.wrap(head, 88, break_long_words=False,
                                              break_on_hyphens=False)]
    lines += ["# part %s %s %s %s %s" % (n, m(r[0]), m(r[1]), m(r[2] - r[0]), m(r[3] - r[1]))
              for n, r in sc.parts]
    lines += ["# door %s %s %s %s" % (m(r[0]), m(r[1]), m(r[2] - r[0]), m(r[3] - r[1]))
              for r in sc.doors]
    lines += ["wall %s %s %s %s" % tuple(m(v) for v in r) for r in sc.walls]
    lines += ["box %s %s %s %s    # inner wall" % (m(r[0]), m(r[1]), m(r[2] - r[0]), m(r[3] - r[1]))
              for r in sc.inner]
    for label, _, _, boxes, circles in sc.items:
        lines += ["box %s %s %s %s    # %s" % (m(r[0]), m(r[1]), m(r[2] - r[0]), m(r[3] - r[1]),
                                               label) for r in boxes]
        lines += ["circle %s %s %s    # %s" % (m(c[0]), m(c[1]), m(c[2]), label) for c in circles]
    lines.append("start %s %s %d" % (m(sc.start[0]), m(sc.start[1]), sc.start[2]))
    return "\n".join(lines) + "\n"


def make(kind, seed):
    return make_room(seed) if kind == "room" else make_flat(seed)


def index_entry(sc, name):
    return {"file": name, "kind": sc.kind, "seed": sc.seed, "shape": sc.shape,
            "area_m2": round(sc.area_m2(), 4), "size_m": [sc.w / 1000, sc.h / 1000],
            "parts": len(sc.parts), "doors": len(sc.doors)}


def write_corpus(out, rooms, flats, first):
    """room_<seed>.room, flat_<seed>.room and index.json in `out`; returns the index."""
    os.makedirs(out, exist_ok=True)
    entries = []
    for kind, n in (("room", rooms), ("flat", flats)):
        for seed in range(first, first + n):
            sc = make(kind, seed)
            name = "%s_%d.room" % (kind, seed)
            with open(os.path.join(out, name), "w") as f:
                f.write(room_text(sc))
            entries.append(index_entry(sc, name))
    index = {"generator": "tools/roomgen.py", "first_seed": first, "rooms": rooms,
             "flats": flats, "files": entries}
    with open(os.path.join(out, "index.json"), "w") as f:
        json.dump(index, f, indent=1)
        f.write("\n")
    return index
