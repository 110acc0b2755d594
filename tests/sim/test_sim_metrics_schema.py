#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""metrics.json is documented field by field in host_sim/metrics.schema.json, and every
run's file follows it exactly (simtest checks each run of every simulator test; this test
checks the schema itself, that the validator refuses what it must, and runs that reach
the corners of the file: a crop of a ROS map, --ideal, coverage marks reached, and
post_sweep, written only with --sweep)."""
import copy
import json
import os

import schema
from simtest import Sim, check

sim = Sim()
with open(os.path.join(sim.src, "host_sim", "metrics.schema.json")) as f:
    sch = json.load(f)

gaps = schema.undocumented(sch)
check(not gaps, "every field of the schema is described, required, and no object takes "
      "unlisted fields%s" % ("" if not gaps else ": " + "; ".join(gaps)))

run = sim.out("run")
sim.run("--duration", 30, "--seed", 3, "--sweep", "--out", run)  # validated by sim.run
m = sim.metrics(run)
check(schema.validate(m, sch) == [], "a run's metrics.json validates")
check("post_sweep" in m, "--sweep writes post_sweep")
plain = sim.out("plain")
sim.run("--duration", 30, "--seed", 3, "--out", plain)
mp = sim.metrics(plain)
check(set(m) - set(mp) == {"post_sweep"} and
      all(mp[k] == m[k] for k in mp),
      "without --sweep metrics.json loses post_sweep and nothing else (%s)"
      % sorted(set(m) ^ set(mp)))


def refused(change, what):
    doc = copy.deepcopy(m)
    change(doc)
    errs = schema.validate(doc, sch)
    check(errs != [], "the validator refuses %s (%s)" % (what, errs[0] if errs else "accepted"))


refused(lambda d: d.update(surprise=1), "an unknown top-level field")
refused(lambda d: d["robot"].update(new_counter=3), "an unknown field in an object")
refused(lambda d: d["maps"]["odometry"]["raw"].pop("f1"), "a missing field")
refused(lambda d: d["robot"].__setitem__("pings", 1.5), "a float where a count belongs")
refused(lambda d: d["robot"].__setitem__("pings", True), "a boolean where a count belongs")
refused(lambda d: d["scenario"].__setitem__("explore", "spiral"), "an unknown exploration mode")
refused(lambda d: d["maps"]["odometry"]["raw"].__setitem__("precision", 1.5), "a fraction above 1")
refused(lambda d: d["scenario"].__setitem__("start", [1, 2]), "a start pose of two numbers")
refused(lambda d: d["post_sweep"]["f1"][0].__setitem__(0, "x"), "a string in a table")

try:
    schema.validate(m, {"type": "object", "patternProperties": {}})
    check(False, "a schema keyword the validator does not know is refused")
except schema.SchemaError:
    check(True, "a schema keyword the validator does not know is refused")

# The corners: --ideal with a square path, a crop of a ROS map, marks of coverage reached.
sim.run("--duration", 20, "--ideal", "--explore", "square", "--out", sim.out("ideal"))
pgm = sim.out("map.pgm")
with open(pgm, "wb") as f:
    f.write(b"P5\n60 60\n255\n" + bytes([0 if x in (0, 59) or y in (0, 59) else 254
                                         for y in range(60) for x in range(60)]))
with open(sim.out("map.yaml"), "w") as f:
    f.write("image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
crop = sim.out("crop")
sim.run("--room", sim.out("map.yaml"), "--crop", 0.5, 0.5, 1.5, 1.5, "--start", 1.2, 1.2, 0,
        "--cell", 100, "--duration", 240, "--explore", "tm", "--out", crop)
mc = sim.metrics(crop)
check(mc["scenario"]["crop"] is not None and mc["exploration"]["time_to_50_s"] is not None,
      "a cropped map that reaches 50 %% coverage validates (crop %s, 50 %% at %s s)"
      % (mc["scenario"]["crop"], mc["exploration"]["time_to_50_s"]))

# A touch: the square, an odometry experiment that heeds nothing, 4 m a side in the 5 m x
# 4 m room, reaches the east wall head-on, 12 s in, its pose still right.
check((m["robot"]["collisions"] == 0) == (m["exploration"]["first_touch"] is None),
      "a run has a first touch exactly when it touches (%d touches)" % m["robot"]["collisions"])
touch = sim.out("touch")
sim.run("--duration", 60, "--explore", "square", "--set", "square_side_um=4000000",
        "--out", touch)
ft = sim.metrics(touch)["exploration"]["first_touch"]
check(ft is not None and sim.metrics(touch)["robot"]["collisions"] >= 1,
      "a run that touches says when and where: %s" % ft)
if ft is not None:
    check(5.0 < ft["t_s"] < 30.0 and abs(ft["bearing_deg"]) <= 10.0 and ft["x_m"] > 4.7
          and ft["position_error_m"] < 0.05,
          "the square's first touch: %.1f s, the wall %+.0f deg from the heading, at x %.2f m, "
          "the pose %.3f m off" % (ft["t_s"], ft["bearing_deg"], ft["x_m"],
                                   ft["position_error_m"]))
    refused(lambda d: d["exploration"].__setitem__("first_touch", {"t_s": 1.0}),
            "a first touch without its pose")
sim.done()
