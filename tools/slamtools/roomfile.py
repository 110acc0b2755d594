# SPDX-License-Identifier: MIT
"""A .room file in Python: read it, its extent, whether every part is reachable, what a
touch met, a drawing.

tools/roomgen.py checks what it draws with reach_problem() before writing a file,
tools/corpus_report.py takes a room's extent for the grid and what its touches met, and
the tests check the files themselves. Only what the generated rooms use is checked
(axis-parallel walls, boxes, circles); any .room file reads and draws.
"""
import math
from collections import deque

CELL = 50          # mm: the raster of the reachability check
PASS = 275         # mm: half the narrowest passage kept clear (0.55 m)
START_CLEAR = 400  # mm: clearance around the start

KEYWORDS = {"wall": 4, "box": 4, "circle": 3, "start": 3}


class Room:
    """A parsed .room file, in metres; `parts` and `doors` from roomgen's header lines."""

    def __init__(self):
        self.walls, self.boxes, self.circles, self.polys = [], [], [], []
        self.start = None
        self.parts, self.doors = [], []
        self.header = []


def parse(text, name="room"):
    """A Room from a .room file's text; ValueError names the line of a statement it cannot
    read (host_sim's loader is the judge of a file: this reads the ones it accepts)."""
    room = Room()
    for n, line in enumerate(text.splitlines(), 1):
        body, _, comment = line.partition("#")
        words = body.split()
        if not words:
            fields = comment.split()
            if fields and fields[0] == "part" and len(fields) == 6:
                room.parts.append((fields[1], tuple(float(v) for v in fields[2:])))
            elif fields and fields[0] == "door" and len(fields) == 5:
                room.doors.append(tuple(float(v) for v in fields[1:]))
            elif not room.walls and not room.boxes:
                room.header.append(comment.strip())
            continue
        key, vals = words[0], words[1:]
        try:
            nums = [float(v) for v in vals]
        except ValueError:
            raise ValueError("%s:%d: not a number in '%s'" % (name, n, line.strip()))
        if key == "poly" and len(nums) >= 6 and len(nums) % 2 == 0:
            room.polys.append(nums)
        elif key == "start" and len(nums) == 3:
            room.start = tuple(nums)
        elif KEYWORDS.get(key) == len(nums):
            {"wall": room.walls, "box": room.boxes, "circle": room.circles}[key].append(
                tuple(nums))
        else:
            raise ValueError("%s:%d: cannot read '%s'" % (name, n, line.strip()))
    if room.start is None:
        raise ValueError("%s: no start" % name)
    return room


def extent(room):
    """The bounding box of everything in a room, (x0, y0, x1, y1) in metres."""
    xs, ys = [], []
    for x0, y0, x1, y1 in room.walls:
        xs += [x0, x1]
        ys += [y0, y1]
    for x, y, w, h in room.boxes:
        xs += [x, x + w]
        ys += [y, y + h]
    for cx, cy, r in room.circles:
        xs += [cx - r, cx + r]
        ys += [cy - r, cy + r]
    for p in room.polys:
        xs += p[0::2]
        ys += p[1::2]
    return min(xs), min(ys), max(xs), max(ys)


def to_mm(v):
    return int(round(v * 1000))


# --- reachability ------------------------------------------------------------------
# Rectangles are (x0, y0, x1, y1) in whole mm (a wall is one of zero width), circles
# (cx, cy, r); the raster's cell (i, j) has its centre at (25 + 50 i, 25 + 50 j) mm.

def clearance(rects, circles, w, h, cap=START_CLEAR):
    """Squared distance (mm², at most cap²) from each cell's centre to the nearest
    obstacle, over 0..w × 0..h mm. Returns (field, nx, ny), field[j * nx + i]."""
    nx, ny = -(-w // CELL), -(-h // CELL)
    cap2 = cap * cap
    f = [cap2] * (nx * ny)
    half = CELL // 2
    for x0, y0, x1, y1 in rects:
        i0, i1 = max(0, -((x0 - cap - half) // -CELL)), min(nx - 1, (x1 + cap - half) // CELL)
        j0, j1 = max(0, -((y0 - cap - half) // -CELL)), min(ny - 1, (y1 + cap - half) // CELL)
        dx2 = [max(x0 - c, c - x1, 0) ** 2
               for c in range(half + CELL * i0, half + 1 + CELL * i1, CELL)]
        for j in range(j0, j1 + 1):
            dy = max(y0 - half - CELL * j, half + CELL * j - y1, 0)
            a, b = j * nx + i0, j * nx + i1 + 1
            f[a:b] = map(min, f[a:b], [d + dy * dy for d in dx2])
    for cx, cy, r in circles:
        i0 = max(0, -((cx - r - cap - half) // -CELL))
        i1 = min(nx - 1, (cx + r + cap - half) // CELL)
        j0 = max(0, -((cy - r - cap - half) // -CELL))
        j1 = min(ny - 1, (cy + r + cap - half) // CELL)
        for j in range(j0, j1 + 1):
            dy2 = (half + CELL * j - cy) ** 2
            for i in range(i0, i1 + 1):
                d = max(math.sqrt((half + CELL * i - cx) ** 2 + dy2) - r, 0.0)
                if d * d < f[j * nx + i]:
                    f[j * nx + i] = d * d
    return f, nx, ny


def cell_of(x, y, nx):
    return (y // CELL) * nx + x // CELL


def cells_in(rect, nx, ny):
    """The cells whose centres lie in a rectangle (mm)."""
    half = CELL // 2
    i0, i1 = max(0, -((rect[0] - half) // -CELL)), min(nx - 1, (rect[2] - half) // CELL)
    j0, j1 = max(0, -((rect[1] - half) // -CELL)), min(ny - 1, (rect[3] - half) // CELL)
    return [j * nx + i for j in range(j0, j1 + 1) for i in range(i0, i1 + 1)]


def reach(field, nx, first):
    """The cells a disc of radius PASS reaches from cell `first`, side to side."""
    ok = PASS * PASS
    seen = {first} if field[first] >= ok else set()
    todo = deque(seen)
    while todo:
        k = todo.popleft()
        i = k % nx
        for n in (k - nx, k + nx, k - 1 if i > 0 else -1, k + 1 if i < nx - 1 else -1):
            if 0 <= n < len(field) and n not in seen and field[n] >= ok:
                seen.add(n)
                todo.append(n)
    return seen


def reach_problem(field, nx, ny, parts, start):
    """None when, from the start (x, y mm), every cell of every part (name, rectangle mm)
    where a disc of radius PASS fits is reachable, and each part has one; else what fails."""
    seen = reach(field, nx, cell_of(start[0], start[1], nx))
    ok = PASS * PASS
    for name, rect in parts:
        fits = [k for k in cells_in(rect, nx, ny) if field[k] >= ok]
        if not fits:
            return "%s: nowhere with %d mm clear" % (name, PASS)
        cut = [k for k in fits if k not in seen]
        if cut:
            k = cut[0]
            return "%s: %d places with %d mm clear cut off from the start, as (%d, %d) mm" % (
                name, len(cut), PASS, CELL // 2 + CELL * (k % nx), CELL // 2 + CELL * (k // nx))
    return None


def geometry_mm(room):
    """A generated room's obstacles as whole-mm rectangles and circles, and its size."""
    rects = [tuple(to_mm(v) for v in r) for r in room.walls]
    for x0, y0, x1, y1 in rects:
        if x0 != x1 and y0 != y1:
            raise ValueError("a wall that is not axis-parallel: %s" % (rects,))
    rects = [(min(r[0], r[2]), min(r[1], r[3]), max(r[0], r[2]), max(r[1], r[3])) for r in rects]
    rects += [(to_mm(x), to_mm(y), to_mm(x + w), to_mm(y + h)) for x, y, w, h in room.boxes]
    circles = [tuple(to_mm(v) for v in c) for c in room.circles]
    _, _, x1, y1 = extent(room)
    return rects, circles, to_mm(x1), to_mm(y1)


def check(room):
    """What is wrong with a generated room by the generator's own rules: the start's
    clearance (exact, against every obstacle) and every part reachable. [] when nothing."""
    rects, circles, w, h = geometry_mm(room)
    sx, sy = to_mm(room.start[0]), to_mm(room.start[1])
    near = min([math.sqrt(max(x0 - sx, sx - x1, 0) ** 2 + max(y0 - sy, sy - y1, 0) ** 2)
                for x0, y0, x1, y1 in rects] +
               [math.sqrt((cx - sx) ** 2 + (cy - sy) ** 2) - r for cx, cy, r in circles])
    problems = [] if near >= START_CLEAR else ["the start has %.0f mm clear" % near]
    field, nx, ny = clearance(rects, circles, w, h)
    parts = [(n, (to_mm(x), to_mm(y), to_mm(x + pw), to_mm(y + ph))) for n, (x, y, pw, ph)
             in room.parts]
    p = reach_problem(field, nx, ny, parts, (sx, sy)) if parts else "no parts listed"
    return problems + ([p] if p else [])


# --- what a touch met ---------------------------------------------------------------

THIN = 0.05  # m: a circle thinner than this is a leg; else a round thing (a bin, a pot)
TOUCH_KINDS = ("corner", "face", "wall end", "leg", "round")
SAME = 0.001  # m: ends this close meet


def edges(room):
    """Every straight side in a room: walls, the boxes' four sides, the polygons' edges,
    each (x0, y0, x1, y1) in metres."""
    out = list(room.walls)
    for x, y, w, h in room.boxes:
        out += [(x, y, x + w, y), (x + w, y, x + w, y + h), (x + w, y + h, x, y + h),
                (x, y + h, x, y)]
    for p in room.polys:
        pts = list(zip(p[0::2], p[1::2]))
        out += [a + b for a, b in zip(pts, pts[1:] + pts[:1])]
    return out


def touched(room, x, y):
    """What the body whose centre is at (x, y) met: the kind (TOUCH_KINDS) of the obstacle
    nearest that centre. A side's end nearest it is a corner where another side ends too
    (met point first, it is convex on the robot's side: a box's, an L-shaped room's inner
    corner), else a wall's free end; a side's inside is a face."""
    sides = edges(room)
    ends = [e[:2] for e in sides] + [e[2:] for e in sides]
    best, kind = math.inf, None
    for x0, y0, x1, y1 in sides:
        vx, vy = x1 - x0, y1 - y0
        n2 = vx * vx + vy * vy
        t = 0.0 if n2 == 0 else max(0.0, min(1.0, ((x - x0) * vx + (y - y0) * vy) / n2))
        px, py = x0 + t * vx, y0 + t * vy
        d = math.hypot(x - px, y - py)
        if d < best:
            best = d
            if 0.0 < t < 1.0:
                kind = "face"
            else:
                met = sum(1 for ex, ey in ends if math.hypot(ex - px, ey - py) <= SAME)
                kind = "corner" if met > 1 else "wall end"
    for cx, cy, r in room.circles:
        d = math.hypot(x - cx, y - cy) - r
        if d < best:
            best, kind = d, "leg" if r < THIN else "round"
    return kind


def touch_side(bearing_deg):
    """Where on the body a touch was, from its bearing (degrees, left positive): front
    within 30° of straight ahead, behind beyond 135°, else left or right."""
    b = abs(bearing_deg)
    return "front" if b <= 30 else "behind" if b > 135 else "left" if bearing_deg > 0 else "right"


# --- drawing -----------------------------------------------------------------------

def draw(room, ax, title=None):
    """A room on a matplotlib axis: walls black, inner walls grey, furniture brown, legs
    and bins as circles, doors dashed, the start an arrow."""
    from matplotlib.patches import Circle, Rectangle
    for x0, y0, x1, y1 in room.walls:
        ax.plot([x0, x1], [y0, y1], color="black", lw=1.5)
    for p in room.polys:
        ax.fill(p[0::2], p[1::2], fill=False, color="black", lw=1.0)
    for x, y, w, h in room.boxes:
        inner = min(w, h) == 0.1 and max(w, h) > 0.1
        ax.add_patch(Rectangle((x, y), w, h, color="0.35" if inner else "tab:brown",
                               alpha=1.0 if inner else 0.7, lw=0))
    for cx, cy, r in room.circles:
        thin = r < THIN
        ax.add_patch(Circle((cx, cy), max(r, 0.03) if thin else r,
                            color="black" if thin else "tab:green", alpha=0.9 if thin else 0.6,
                            lw=0))
    for x, y, w, h in room.doors:
        if w > h:
            ax.plot([x, x + w], [y + h / 2, y + h / 2], color="tab:blue", lw=1, ls="--")
        else:
            ax.plot([x + w / 2, x + w / 2], [y, y + h], color="tab:blue", lw=1, ls="--")
    sx, sy, th = room.start
    tip = (sx + 0.5 * math.cos(math.radians(th)), sy + 0.5 * math.sin(math.radians(th)))
    ax.annotate("", xy=tip, xytext=(sx, sy),
                arrowprops=dict(arrowstyle="->", color="tab:red", lw=1.5))
    ax.plot([sx], [sy], "o", color="tab:red", ms=4)
    ax.set_aspect("equal")
    x0, y0, x1, y1 = extent(room)
    ax.set_xlim(x0 - 0.2, x1 + 0.2)
    ax.set_ylim(y0 - 0.2, y1 + 0.2)
    ax.tick_params(labelsize=7)
    if title:
        ax.set_title(title, fontsize=9)
