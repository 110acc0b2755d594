# SPDX-License-Identifier: MIT
"""A generated room's model and its furniture, for slamtools/roomgen.py.

A Scene is a room or a flat in whole millimetres: outer walls (zero-width rectangles),
inner walls and furniture (axis-parallel boxes), legs and bins (circles), the doors, and
the *parts* of its floor (rooms, hall) that must all be reachable. A Region is the part
being furnished, with the faces of its walls and its convex corners. Furniture is placed
by one rule that keeps passages open: a piece touches a wall or another piece, or keeps
GAP away from it (tables and screens always keep GAP), and nothing stands before a door;
place_start() then checks the whole on the 5 cm raster of roomfile.py.
Every number comes from one Draw, the seed's stream.
"""
import random

from . import roomfile
from .roomfile import CELL, START_CLEAR

GAP = 600          # mm: furniture touches a wall or another piece, or keeps this far away
DOOR_KEEP = 800    # mm in front of a door, on both sides, kept free of furniture
ATTEMPTS = 30      # draws of the furniture before a room is left empty

# Pieces against a wall: (label, length along the wall mm, depth mm, on legs).
WALL_PIECES = (
    ("sofa", (1600, 2400), (800, 1000), False, 0.18),
    ("cabinet", (600, 1200), (400, 600), False, 0.24),
    ("shelf", (800, 2000), (250, 400), False, 0.18),
    ("bed", (900, 1800), (1900, 2100), False, 0.12),
    ("wardrobe", (1000, 2000), (550, 650), False, 0.12),
    ("desk", (1000, 1600), (600, 800), True, 0.16),
)
HALL_PIECES = (("cabinet", (600, 1200), (300, 450), False, 0.6),
               ("shelf", (800, 1600), (250, 350), False, 0.4))


class Draw:
    """The seed's one stream of numbers."""

    def __init__(self, seed):
        self._r = random.Random(seed)

    def u(self):
        return self._r.random()

    def mm(self, lo, hi, step=10):
        """A multiple of `step` above lo, uniform in [lo, hi]."""
        assert hi >= lo, (lo, hi)
        n = (hi - lo) // step
        return lo + step * min(int(self.u() * (n + 1)), n)

    def count(self, lo, hi):
        return lo + min(int(self.u() * (hi - lo + 1)), hi - lo)

    def chance(self, p):
        return self.u() < p

    def pick(self, seq):
        return seq[min(int(self.u() * len(seq)), len(seq) - 1)]

    def weighted(self, rows):
        """A row of `rows` by its last field, a weight."""
        x = self.u() * sum(r[-1] for r in rows)
        for r in rows:
            x -= r[-1]
            if x < 0:
                return r
        return rows[-1]


# Rectangles are (x0, y0, x1, y1) in mm with x0 <= x1, y0 <= y1; a wall is one of zero width.
def overlap(a, b):
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def gap2(a, b):
    """The squared distance between two rectangles (0 when they touch or overlap)."""
    dx = max(b[0] - a[2], a[0] - b[2], 0)
    dy = max(b[1] - a[3], a[1] - b[3], 0)
    return dx * dx + dy * dy


def within(a, b):
    return b[0] <= a[0] and b[1] <= a[1] and a[2] <= b[2] and a[3] <= b[3]


class Face:
    """A straight piece of wall furniture can stand against: horizontal (`h`, y = c) or
    vertical (`v`, x = c), from lo to hi, the room on the side `inward` (+1 or -1)."""

    def __init__(self, axis, c, lo, hi, inward):
        self.axis, self.c, self.lo, self.hi, self.inward = axis, c, lo, hi, inward

    def rect(self, t, length, depth):
        """The footprint of a piece `length` long from t along the face, `depth` deep."""
        a, b = (self.c, self.c + depth) if self.inward > 0 else (self.c - depth, self.c)
        return (t, a, t + length, b) if self.axis == "h" else (a, t, b, t + length)


class Region:
    """A room (or the hall) being furnished: its faces, its convex corners, its floor."""

    def __init__(self, name, rects, faces, area_m2, hall=False):
        self.name, self.rects, self.faces, self.hall = name, rects, faces, hall
        self.area_m2 = area_m2
        self.corners = convex_corners(faces)

    def holds(self, r):
        """Whether rectangle r lies on this region's floor (one of its rectangles, or two
        that share an edge, as the arms of an L)."""
        if any(within(r, q) for q in self.rects):
            return True
        inside = [q for q in self.rects if overlap(r, q)]
        area = sum((min(r[2], q[2]) - max(r[0], q[0])) * (min(r[3], q[3]) - max(r[1], q[1]))
                   for q in inside)
        return area == (r[2] - r[0]) * (r[3] - r[1])


def convex_corners(faces):
    """Corners where a horizontal and a vertical face meet with the room between them:
    (x, y, sx, sy), (sx, sy) pointing into the room."""
    out = []
    for h in faces:
        if h.axis != "h":
            continue
        for v in faces:
            if v.axis != "v" or v.c not in (h.lo, h.hi) or h.c not in (v.lo, v.hi):
                continue
            along_h = 1 if v.c == h.lo else -1
            along_v = 1 if h.c == v.lo else -1
            if along_h == v.inward and along_v == h.inward:
                out.append((v.c, h.c, v.inward, h.inward))
    return out


class Scene:
    """One room or flat: the geometry, and what the header says about it."""

    def __init__(self, kind, seed, w, h):
        self.kind, self.seed, self.w, self.h = kind, seed, w, h
        self.shape = "flat"
        self.notch = None          # the rectangle an L-shape leaves out
        self.walls = []            # outer walls: zero-width rectangles
        self.inner = []            # inner walls: boxes
        self.doors = []            # openings: rectangles through an inner wall
        self.keep = []             # rectangles before doors, kept free
        self.parts = []            # (name, rectangle): every one must be reachable
        self.items = []            # (label, family, footprint, boxes, circles)
        self.start = None          # (x, y, heading in degrees)

    def inside(self, x, y):
        if not (0 < x < self.w and 0 < y < self.h):
            return False
        n = self.notch
        return n is None or not (n[0] <= x <= n[2] and n[1] <= y <= n[3])

    def area_m2(self):
        a = self.w * self.h
        if self.notch:
            a -= (self.notch[2] - self.notch[0]) * (self.notch[3] - self.notch[1])
        return a / 1e6

    def obstacles(self):
        """Every rectangle and circle the robot and the sonar meet."""
        rects = self.walls + self.inner + [b for it in self.items for b in it[3]]
        circles = [c for it in self.items for c in it[4]]
        return rects, circles

    def fits(self, fp, family, region):
        """Whether a footprint may stand here: on the region's floor, off every other
        thing, clear of the doors, and touching each thing near it or GAP away from it."""
        if not region.holds(fp) or any(overlap(fp, k) for k in self.keep):
            return False
        solid = family in ("wall", "bin")
        for other in self.walls + self.inner + [it[2] for it in self.items]:
            if overlap(fp, other):
                return False
            g = gap2(fp, other)
            if (g > 0 or not solid) and g < GAP * GAP:
                return False
        return True


def place_start(d, scene, prefer):
    """Draws the start in the part `prefer` (or any, when it has no room) where it has
    START_CLEAR around it, and checks that every part is reachable from it; False when
    that fails."""
    rects, circles = scene.obstacles()
    field, nx, ny = roomfile.clearance(rects, circles, scene.w, scene.h)
    roomy = START_CLEAR * START_CLEAR
    for _, rect in [p for p in scene.parts if p[0] == prefer] + scene.parts:
        spots = [k for k in roomfile.cells_in(rect, nx, ny) if field[k] >= roomy]
        if spots:
            break
    else:
        return False
    k = d.pick(spots)
    x, y = CELL // 2 + CELL * (k % nx), CELL // 2 + CELL * (k // nx)
    if roomfile.reach_problem(field, nx, ny, scene.parts, (x, y)):
        return False
    scene.start = (x, y, d.count(0, 359))
    return True


# --- furniture ---------------------------------------------------------------------

def legs(rect, r, inset):
    x0, y0, x1, y1 = rect
    a = r + inset
    return [(x0 + a, y0 + a, r), (x1 - a, y0 + a, r), (x0 + a, y1 - a, r), (x1 - a, y1 - a, r)]


def along(d, face, length):
    """Where along a face a piece starts: in a corner, or GAP or more from its ends."""
    room = face.hi - face.lo - length
    if room < 0:
        return None
    if room < 2 * GAP or d.chance(0.35):
        return face.lo if d.chance(0.5) else face.hi - length
    return face.lo + GAP + d.mm(0, room - 2 * GAP)


def wall_piece(d, scene, region, pieces):
    label, lengths, depths, on_legs, _ = d.weighted(pieces)
    for _ in range(20):
        face = d.weighted([(f, f.hi - f.lo) for f in region.faces])[0]
        length, depth = d.mm(*lengths), d.mm(*depths)
        t = along(d, face, length)
        if t is None:
            continue
        fp = face.rect(t, length, depth)
        if scene.fits(fp, "wall", region):
            if on_legs:
                scene.items.append((label, "wall", fp, [], legs(fp, d.mm(6, 15, 1), 20)))
            else:
                scene.items.append((label, "wall", fp, [fp], []))
            return True
    return False


def table(d, scene, region):
    """A table on legs standing free, with chairs on legs around some."""
    w, dep = d.mm(800, 1800), d.mm(600, 1000)
    chairs = d.count(1, 4) if dep >= 800 and d.chance(0.5) else 0
    cs = d.mm(400, 450)
    for _ in range(20):
        q = d.pick(region.rects)
        x, y = d.mm(q[0], q[2]), d.mm(q[1], q[3])
        top = (x, y, x + w, y + dep) if d.chance(0.5) else (x, y, x + dep, y + w)
        along_x = top[2] - top[0] >= top[3] - top[1]
        seats = []
        for k in range(chairs):
            side = -1 if k % 2 == 0 else 1
            long0, long1 = (top[0], top[2]) if along_x else (top[1], top[3])
            quarter = 1 + 2 * (k // 2) if chairs > 2 else 2  # of the table's length
            mid = long0 + (long1 - long0) * quarter // 4
            edge = top[(1 if along_x else 0) + (0 if side < 0 else 2)]
            a, b = (edge - 50 - cs, edge - 50) if side < 0 else (edge + 50, edge + 50 + cs)
            seats.append((mid - cs // 2, a, mid + cs // 2, b) if along_x else
                         (a, mid - cs // 2, b, mid + cs // 2))
        fp = (min(r[0] for r in [top] + seats), min(r[1] for r in [top] + seats),
              max(r[2] for r in [top] + seats), max(r[3] for r in [top] + seats))
        if scene.fits(fp, "table", region):
            circles = legs(top, d.mm(6, 15, 1), 30)
            for s in seats:
                circles += legs(s, d.mm(8, 12, 1), 20)
            scene.items.append(("table" + (" with %d chairs" % chairs if chairs else ""),
                                "table", fp, [], circles))
            return True
    return False


def bin_(d, scene, region):
    """A round bin or pot in a corner or against a wall beside a piece of furniture."""
    r = d.mm(100, 250)
    label = "pot" if d.chance(0.4) else "bin"
    beside = [it for it in scene.items if it[1] == "wall" and region.holds(it[2])]
    for _ in range(20):
        if region.corners and (not beside or d.chance(0.5)):
            x, y, sx, sy = d.pick(region.corners)
            cx, cy, where = x + sx * r, y + sy * r, "in a corner"
        elif beside:
            fp = d.pick(beside)[2]
            face = d.pick([f for f in region.faces if touches(fp, f)] or [None])
            if face is None:
                continue
            lo, hi = (fp[0], fp[2]) if face.axis == "h" else (fp[1], fp[3])
            t = lo - r if d.chance(0.5) else hi + r
            off = face.c + face.inward * r
            cx, cy = (t, off) if face.axis == "h" else (off, t)
            where = "beside furniture"
        else:
            return False
        if scene.fits((cx - r, cy - r, cx + r, cy + r), "bin", region):
            scene.items.append(("%s %s" % (label, where), "bin",
                                (cx - r, cy - r, cx + r, cy + r), [], [(cx, cy, r)]))
            return True
    return False


def touches(fp, face):
    if face.axis == "h":
        return (fp[1] == face.c or fp[3] == face.c) and face.lo <= fp[0] and fp[2] <= face.hi
    return (fp[0] == face.c or fp[2] == face.c) and face.lo <= fp[1] and fp[3] <= face.hi


def screen(d, scene, region):
    """A free-standing screen: a thin box."""
    t, length = d.mm(20, 50, 1), d.mm(800, 1600)
    for _ in range(20):
        q = d.pick(region.rects)
        x, y = d.mm(q[0], q[2]), d.mm(q[1], q[3])
        fp = (x, y, x + length, y + t) if d.chance(0.5) else (x, y, x + t, y + length)
        if scene.fits(fp, "screen", region):
            scene.items.append(("screen", "screen", fp, [fp], []))
            return True
    return False


def furnish(d, scene, region, share):
    """Furniture for one region, `share` (0..1) of the usual amount."""
    perimeter = sum(f.hi - f.lo for f in region.faces) / 1000
    a = region.area_m2
    if region.hall:
        plan = [(wall_piece, HALL_PIECES, d.count(0, 2)), (bin_, None, d.count(0, 2))]
    else:
        plan = [(wall_piece, WALL_PIECES, d.count(max(1, int(perimeter / 5)),
                                                  max(2, int(perimeter / 2.5)))),
                (table, None, d.count(int(a / 25), 1 + int(a / 15))),
                (bin_, None, d.count(1, 2 + int(a / 15))),
                (screen, None, d.count(0, 1 + int(a / 25)) if scene.kind == "room" else 0)]
    for fn, arg, n in plan:
        for _ in range(int(n * share + 0.5)):
            if arg is None:
                fn(d, scene, region)
            else:
                fn(d, scene, region, arg)


def furnish_all(d, scene, regions, prefer):
    """Furniture for every region, drawn again until the scene passes its check."""
    for attempt in range(ATTEMPTS + 1):
        scene.items = []
        share = 1.0 if attempt < 10 else 0.5 if attempt < 20 else 0.0
        for region in regions:
            furnish(d, scene, region, share)
        if place_start(d, scene, prefer):
            return scene
    raise RuntimeError("%s %d: no start reaches every part" % (scene.kind, scene.seed))
