#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Exploration in the simulator: the default (walls) mode touches nothing and maps the walls.

1. Over every shipped room and ten seeds, ten minutes each, at the default level (the
   typical sonar, issue 28): no collision, the body never nearer than 5 mm to anything
   (measured: 9 mm at the closest, in clutter), and the wall coverage (metrics.json) at
   least 0.9 on average, 0.8 in every room but narrow (measured 0.930, clutter's 0.835 the
   lowest). The narrow room's coverage is 0.57 or 1.0 by whether a run passes its
   opening, a coin's throw: over 40 runs from shifted starts (tools/corpus_report.py
   --seeds 40 --first-seed 5000 --shift-start 0.1) 17 passed before the way to frontiers
   out of sight and 18 with it (mean 0.762 and 0.765), while seeds 1-10 went from 8 to 3.
   Part 4 holds it to being passed at all.
2. The same runs: the raw F1 of the map built from the robot's own pose at least 0.88 on
   average (0.911 measured).
3. In the default room (seeds 1-5) the walls mode covers more of the walls than the paper's
   random mode, and maps them with a higher raw F1.
4. The narrow room's east half lies beyond a 0.36 m opening: some seed passes it.
5. A chair (four legs 0.36 m apart) that the robot drives into, seeds 1-6: it backs out
   (an escape) and no run goes 45 s without 0.2 m of progress (measured: 28 s at most;
   before escapes, seeds 3, 4 and 6 turned about among the legs for 260-510 s). The same
   chair round the start: no way in to back out along, so it squeezes out (34 s at most;
   without the squeeze, seeds 2 and 4 stayed the whole 600 s).

Until a wall's free end was round (hal/host/README.md, Rooms), part 1 ran at the
optimistic sonar: at the typical one 8 of these 60 runs met the end of clutter's screen,
which then presented nothing to the sonar.
"""
import os

from simtest import Sim, check, check_path, mean

sim = Sim()
ROOMS = sorted(f for f in os.listdir(os.path.join(sim.src, "host_sim", "rooms")) if f.endswith(".room"))


def run(room, seed, *args):
    d = sim.out("%s-%d-%s" % (room, seed, "-".join(str(a) for a in args)))
    sim.run("--room", sim.room(room), "--seed", seed, "--duration", 600, "--out", d, *args)
    return sim.metrics(d)


per_room = {}
for room in ROOMS:
    # Ten seeds: in the multi-room flat a run finds the doors or not (wall coverage 0.43,
    # 0.70 or 0.9+), and in clutter it reaches the north strip or not, so five seeds
    # judge luck more than the exploration.
    ms = [run(room, s) for s in range(1, 11)]
    per_room[room] = ms
    coll = sum(m["robot"]["collisions"] for m in ms)
    closest = min(m["exploration"]["min_clearance_m"] for m in ms)
    cover = mean(m["exploration"]["wall_coverage"] for m in ms)
    print("%s: collisions %d, closest %.3f m, wall coverage %.3f" % (room, coll, closest, cover))
    check_path(coll == 0 and closest > 0.005, "%s: no collision, closest %.3f m" % (room, closest))
    if room != "narrow.room":
        check(cover >= 0.8, "%s: wall coverage %.3f >= 0.8" % (room, cover))
overall = mean(m["exploration"]["wall_coverage"] for ms in per_room.values() for m in ms)
check(overall >= 0.9, "mean wall coverage over the shipped rooms %.3f >= 0.9" % overall)

runs = [m for ms in per_room.values() for m in ms]
own = mean(m["maps"]["odometry"]["raw"]["f1"] for m in runs)
print("own-pose F1 %.3f" % own)
check(own >= 0.88, "own-pose raw F1 %.3f >= 0.88" % own)

walls = per_room["default.room"][:5]
rand = [run("default.room", s, "--explore", "random") for s in range(1, 6)]
wc = (mean(m["exploration"]["wall_coverage"] for m in walls), mean(m["exploration"]["wall_coverage"] for m in rand))
f1 = (mean(m["maps"]["odometry"]["raw"]["f1"] for m in walls), mean(m["maps"]["odometry"]["raw"]["f1"] for m in rand))
check(wc[0] > wc[1], "default room: walls covers more wall than random (%.3f > %.3f)" % wc)
check(f1[0] > f1[1], "default room: and maps it with a higher raw F1 (%.3f > %.3f)" % f1)

passed = sum(m["robot"]["openings_passed"] for m in per_room["narrow.room"])
east = max(m["exploration"]["wall_coverage"] for m in per_room["narrow.room"])
check(passed >= 1 and east > 0.8, "narrow room: an opening passed (%d), coverage up to %.3f" % (passed, east))

CHAIR = """# a 4 m x 3 m room, a chair's four legs
wall 0 0 4 0
wall 4 0 4 3
wall 4 3 0 3
wall 0 3 0 0
circle 1.82 1.32 0.012
circle 2.18 1.32 0.012
circle 1.82 1.68 0.012
circle 2.18 1.68 0.012
start 1.4 1.5 0
"""
chair = sim.out("chair.room")
with open(chair, "w") as f:
    f.write(CHAIR)
for start, where in ((("1.4", "1.5", "0"), "driven into"), (("2.0", "1.5", "20"), "round the start")):
    for seed in range(1, 7):
        d = sim.out("chair-%s-%d" % (start[0], seed))
        sim.run("--room", chair, "--start", *start, "--seed", seed, "--duration", 600, "--out", d)
        m = sim.metrics(d)
        stuck = m["exploration"]["longest_without_progress_s"]
        print("chair %s, seed %d: %d escapes, longest without progress %.1f s"
              % (where, seed, m["robot"]["escapes"], stuck))
        check_path(stuck < 45.0, "chair %s, seed %d: longest without progress %.1f s < 45 s"
                   % (where, seed, stuck))
sim.done()
