#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/roomgen.py: a seed gives the same bytes every time (whatever Python's hash seed),
another seed another room; the rooms of seeds 1-200 and the flats of seeds 1-30, read back
from the files `corpus` writes, lie in their ranges (sizes, areas, door widths, legs, bins,
screens), have their start 0.4 m clear and reach every room and hall through 0.55 m
passages (roomfile.check on the written file), and host_sim accepts a sample of them."""
import json
import os
import subprocess
import sys

from simtest import Sim, check, fail

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import roomfile  # noqa: E402

ROOMGEN = os.path.join(sim.src, "tools", "roomgen.py")
ROOMS, FLATS = 200, 30
EPS = 1e-9


def roomgen(*args, hash_seed="0"):
    env = dict(os.environ, PYTHONHASHSEED=hash_seed)
    return subprocess.run(["/usr/bin/python3", ROOMGEN] + [str(a) for a in args],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)


# The same seed, the same bytes: twice, under two hash seeds, to stdout and to --out.
for kind, seed in (("room", 7), ("flat", 3)):
    a, b = roomgen(kind, seed), roomgen(kind, seed, hash_seed="12345")
    out = sim.out("%s_%d.room" % (kind, seed))
    c = roomgen(kind, seed, "--out", out)
    with open(out, "rb") as f:
        written = f.read()
    check(a.returncode == 0 and a.stdout and a.stdout == b.stdout == written,
          "%s %d: the same bytes every time (%d bytes)" % (kind, seed, len(a.stdout)))
    other = roomgen(kind, seed + 1).stdout
    body = [x for x in a.stdout.splitlines() if not x.startswith(b"#")]
    check(body != [x for x in other.splitlines() if not x.startswith(b"#")],
          "%s %d and %d differ" % (kind, seed, seed + 1))
png = sim.out("room.png")
p = roomgen("flat", 2, "--out", sim.out("flat_2.room"), "--png", png)
with open(png, "rb") as f:
    check(p.returncode == 0 and f.read(8) == b"\x89PNG\r\n\x1a\n", "--png draws a flat")
for bad in (["room", "-1"], ["room", "x"], ["flat"], ["corpus", "--rooms", "2"], ["bogus"]):
    p = roomgen(*bad)
    check(p.returncode == 2 and b"error" in p.stderr, "roomgen %s: exit 2 with a message"
          % " ".join(bad))

# The corpus, as the report writes it.
corpus = sim.out("corpus")
p = roomgen("corpus", "--rooms", ROOMS, "--flats", FLATS, "--out", corpus)
check(p.returncode == 0, "roomgen corpus --rooms %d --flats %d%s" % (
    ROOMS, FLATS, "" if p.returncode == 0 else ": " + p.stderr.decode().strip()))
with open(os.path.join(corpus, "index.json")) as f:
    index = json.load(f)
entries = index["files"]
check(sorted(e["file"] for e in entries) == sorted(
    ["room_%d.room" % s for s in range(1, ROOMS + 1)] +
    ["flat_%d.room" % s for s in range(1, FLATS + 1)]), "index.json lists every file written")

bodies = set()
bands = {}
problems = []
for e in entries:
    path = os.path.join(corpus, e["file"])
    with open(path) as f:
        text = f.read()
    room = roomfile.parse(text, path)
    bodies.add("\n".join(x for x in text.splitlines() if not x.startswith("#")))
    x0, y0, x1, y1 = roomfile.extent(room)
    w, h = x1 - x0, y1 - y0
    name = e["file"]
    if (x0, y0) != (0, 0) or abs(w - e["size_m"][0]) > EPS or abs(h - e["size_m"][1]) > EPS:
        problems.append("%s: extent %s is not its size %s" % (name, (x0, y0, x1, y1), e["size_m"]))
    if e["kind"] == "room":
        if not (3 - EPS <= min(w, h) and max(w, h) <= 9 + EPS):
            problems.append("%s: %.3f x %.3f m, not 3-9 m a side" % (name, w, h))
        if not 8.9 <= e["area_m2"] <= 60.1:
            problems.append("%s: %.2f m² is not 9-60" % (name, e["area_m2"]))
        band = next(b for b, top in (("<12", 12), ("12-25", 25), ("25-40", 40), (">40", 99))
                    if e["area_m2"] < top)
        bands[band] = bands.get(band, 0) + 1
    else:
        rooms = [n for n, _ in room.parts if n != "hall"]
        if max(w, h) > 12 + EPS or len(rooms) < 2 or "hall" not in [n for n, _ in room.parts]:
            problems.append("%s: %.3f x %.3f m, a hall and %d rooms" % (name, w, h, len(rooms)))
        if len(room.doors) < len(rooms):
            problems.append("%s: %d doors for %d rooms" % (name, len(room.doors), len(rooms)))
    for dx, dy, dw, dh in room.doors:
        if abs(min(dw, dh) - 0.1) > EPS or not 0.7 - EPS <= max(dw, dh) <= 0.9 + EPS:
            problems.append("%s: a door of %.3f x %.3f m" % (name, dw, dh))
        o = [roomfile.to_mm(v) for v in (dx, dy, dx + dw, dy + dh)]
        for box in room.boxes:
            b = [roomfile.to_mm(v) for v in (box[0], box[1], box[0] + box[2], box[1] + box[3])]
            if b[0] < o[2] and o[0] < b[2] and b[1] < o[3] and o[1] < b[3]:
                problems.append("%s: a box in the door at %.3f %.3f" % (name, dx, dy))
        for cx, cy, r in room.circles:
            if o[0] - r * 1000 < roomfile.to_mm(cx) < o[2] + r * 1000 and \
                    o[1] - r * 1000 < roomfile.to_mm(cy) < o[3] + r * 1000:
                problems.append("%s: a circle in the door at %.3f %.3f" % (name, dx, dy))
    for cx, cy, r in room.circles:
        if not (0.006 - EPS <= r <= 0.015 + EPS or 0.1 - EPS <= r <= 0.25 + EPS):
            problems.append("%s: a circle of radius %.3f m (a leg 12-30 mm thick, a bin or pot "
                            "0.1-0.25 m)" % (name, r))
    for bx, by, bw, bh in room.boxes:
        thin, long_ = min(bw, bh), max(bw, bh)
        screen = 0.02 - EPS <= thin <= 0.05 + EPS and 0.8 - EPS <= long_ <= 1.6 + EPS
        if thin < 0.1 - EPS and not screen:
            problems.append("%s: a box of %.3f x %.3f m (a screen is 20-50 mm x 0.8-1.6 m)"
                            % (name, bw, bh))
    problems += ["%s: %s" % (name, p) for p in roomfile.check(room)]
if problems:
    fail("%d problems:\n  %s" % (len(problems), "\n  ".join(problems[:20])))
check(True, "%d rooms and %d flats: sizes, areas, doors, legs, bins, screens in range; the start "
      "0.4 m clear, every room and hall reachable through 0.55 m" % (ROOMS, FLATS))
check(len(bodies) == len(entries), "no two seeds give the same geometry")
check(len(bands) == 4 and min(bands.values()) >= 10,
      "every area band has rooms: %s" % sorted(bands.items()))

# host_sim takes them: its start checks (in the room, the body clear, rays meet walls).
sample = ["room_%d.room" % s for s in range(1, ROOMS + 1, 10)] + \
         ["flat_%d.room" % s for s in range(1, FLATS + 1, 5)]
for name in sample:
    sim.run("--room", os.path.join(corpus, name), "--duration", 1, "--out", sim.out("run"))
check(True, "host_sim runs %d of them (every 10th room, every 5th flat)" % len(sample))
sim.done()
