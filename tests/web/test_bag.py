#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Runs as ROS bags (python3-rosbag reads them back): host_sim --bag writes every message
its run's files hold (the odometry and true poses of trajectory.csv, every reading of
readings.csv with its servo angle as a transform, om.pgm and truth.pgm as trinary
OccupancyGrids), with the run's own time stamps; telemetry.py to-bag writes a log's
POSE, READING and map frames, its last /map equal to om.pgm; bad input gets a message."""
import csv
import math
import os
import subprocess
import sys

import webtest
from webtest import check, fail

sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
sys.path.insert(0, os.path.join(sys.argv[2], "tests", "sim"))
from slamtools import link as slamlink  # noqa: E402
from simtest import Sim  # noqa: E402

try:
    import numpy as np
    import rosbag
except ImportError as e:
    fail("the bag tests need python3-rosbag and python3-numpy (tools/install-deps.sh test): %s" % e)

sim = Sim()
TOOL = os.path.join(sim.src, "tools", "telemetry.py")
TYPES = {"/map": "nav_msgs/OccupancyGrid", "/odom": "nav_msgs/Odometry", "/tf": "tf2_msgs/TFMessage",
         "/tf_static": "tf2_msgs/TFMessage", "/sonar": "sensor_msgs/Range"}
TRUTH_TYPES = {"/truth/map": "nav_msgs/OccupancyGrid", "/truth/odom": "nav_msgs/Odometry"}
f32 = np.float32


def read_bag(path):
    bag = rosbag.Bag(path)
    info = bag.get_type_and_topic_info().topics
    msgs = {}
    for topic, msg, t in bag.read_messages():
        msgs.setdefault(topic, []).append((t, msg))
    latched = {c.topic for c in bag._get_connections() if c.header.get("latching") == b"1"}
    bag.close()
    return {t: v.msg_type for t, v in info.items()}, msgs, latched


def ticks(t):
    return t.secs * 100 + t.nsecs // 10000000 if t.nsecs % 10000000 == 0 else None


def yaw(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def same_angle(a, b):
    return abs(math.remainder(a - b, 2 * math.pi)) < 1e-9


def pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    head = data.split(b"\n", 3)
    w, h = map(int, head[1].split())
    return np.frombuffer(head[3], np.uint8).reshape(h, w)


def grid_matches(msg, image, yaml_path):
    """The OccupancyGrid is the image (trinary PGM values) cell for cell, with its YAML's
    resolution and origin."""
    keys = dict(line.split(": ", 1) for line in open(yaml_path).read().splitlines())
    origin = [float(v) for v in keys["origin"].strip("[]").split(",")]
    want = np.full(image.shape, -1, np.int8)
    want[image == slamlink.MAP_OCCUPIED] = 100
    want[image == slamlink.MAP_FREE] = 0
    data = np.array(msg.data, np.int8).reshape(msg.info.height, msg.info.width)
    return (msg.header.frame_id == "map" and msg.info.resolution == f32(float(keys["resolution"])) and
            msg.info.origin.position.x == origin[0] and msg.info.origin.position.y == origin[1] and
            (msg.info.width, msg.info.height) == image.shape[::-1] and
            np.array_equal(data, want[::-1]) and set(np.unique(image)) <= {0, 205, 254})


def check_transforms(tfs, want, what):
    """tfs: the /tf messages; want: {child: [(ticks, parent, x, y, yaw)...]} in order."""
    got = {}
    for t, m in tfs:
        for tr in m.transforms:
            got.setdefault(tr.child_frame_id, []).append(
                (ticks(t), ticks(tr.header.stamp), tr.header.frame_id, tr.transform.translation.x,
                 tr.transform.translation.y, yaw(tr.transform.rotation)))
    bad = 0
    for child, rows in want.items():
        have = got.get(child, [])
        if len(have) != len(rows):
            fail("%s: %d transforms to %s, expected %d" % (what, len(have), child, len(rows)))
        for (k, ks, parent, x, y, th), (wk, wparent, wx, wy, wth) in zip(have, rows):
            bad += not (k == ks == wk and parent == wparent and abs(x - wx) < 1e-9 and
                        abs(y - wy) < 1e-9 and same_angle(th, wth))
    check(bad == 0 and set(got) == set(want),
          "%s: every transform (%s) at its time, from its parent, where the run says"
          % (what, ", ".join("%d to %s" % (len(v), c) for c, v in sorted(want.items()))))


# ---- host_sim --bag: against the run's own files --------------------------------------------

run = sim.out("run")
bag = sim.out("run.bag")
p = sim.run("--duration", 30, "--seed", 5, "--room", sim.room("obstacles.room"), "--out", run,
            "--bag", bag)
types, msgs, latched = read_bag(bag)
check(types == dict(TYPES, **TRUTH_TYPES), "host_sim --bag: the topics and their types: %s" % types)
check(latched == {"/map", "/truth/map", "/tf_static"}, "the maps and /tf_static are latched")
with open(os.path.join(run, "trajectory.csv")) as f:
    traj = list(csv.DictReader(f))
with open(os.path.join(run, "readings.csv")) as f:
    readings = list(csv.DictReader(f))
cfg = dict(line.split(" = ") for line in open(os.path.join(run, "config.txt")).read().splitlines()
           if " = " in line)
T = [round(float(r["t_s"]) * 100) for r in traj]

for topic, cols, child in (("/odom", "odom", "base_link"), ("/truth/odom", "true", "truth_base_link")):
    got = msgs[topic]
    bad = sum(1 for (t, m), r, k in zip(got, traj, T) if not (
        ticks(t) == ticks(m.header.stamp) == k and m.header.frame_id == "odom" and
        m.child_frame_id == child and m.pose.pose.position.x == float(r[cols + "_x_m"]) and
        m.pose.pose.position.y == float(r[cols + "_y_m"]) and
        same_angle(yaw(m.pose.pose.orientation), float(r[cols + "_th_rad"]))))
    check(len(got) == len(traj) > 100 and bad == 0,
          "%s: one message per trajectory.csv row (%d), each its time and %s pose" % (topic, len(got), cols))

mount = (int(cfg["mount_x_um"]) * 1e-6, int(cfg["mount_y_um"]) * 1e-6, int(cfg["mount_yaw_mdeg"]) / 1000.0)
check_transforms(msgs["/tf"], {
    "base_link": [(k, "odom", float(r["odom_x_m"]), float(r["odom_y_m"]), float(r["odom_th_rad"]))
                  for r, k in zip(traj, T)],
    "sonar": [(round(float(r["t_s"]) * 100), "base_link", mount[0], mount[1],
               math.radians(90.0 - float(r["servo_deg"]) + mount[2])) for r in readings]}, "/tf")

sonar = msgs["/sonar"]
bad = 0
for (t, m), r in zip(sonar, readings):
    want = math.inf if r["status"] == "timeout" else f32(float(r["range_m"]))
    bad += not (ticks(t) == ticks(m.header.stamp) == round(float(r["t_s"]) * 100) and
                m.header.frame_id == "sonar" and m.radiation_type == 0 and m.range == want and
                m.field_of_view == f32(math.radians(15.0)) and m.max_range == f32(4.0) and
                m.min_range == f32(int(cfg["range_min_um"]) * 1e-6))
timeouts = sum(1 for r in readings if r["status"] == "timeout")
check(len(sonar) == len(readings) > 100 and bad == 0 and timeouts > 0,
      "/sonar: one Range per readings.csv row (%d, %d timeouts as +inf), its time, the 15 deg "
      "cone, 0.02..4 m" % (len(sonar), timeouts))

(t_map, om), = msgs["/map"]
(t_truth, truth), = msgs["/truth/map"]
check(ticks(t_map) == T[-1] and grid_matches(om, pgm(os.path.join(run, "om.pgm")), os.path.join(run, "om.yaml")),
      "/map: om.pgm cell for cell (100 occupied, 0 free, -1 unknown), om.yaml's resolution "
      "and origin, at the run's end")
check(ticks(t_truth) == T[0] and grid_matches(truth, pgm(os.path.join(run, "truth.pgm")),
                                             os.path.join(run, "truth.yaml")),
      "/truth/map: truth.pgm cell for cell, at the start")
(t_static, static), = msgs["/tf_static"]
tr = static.transforms[0]
check(ticks(t_static) == T[0] and tr.header.frame_id == "map" and tr.child_frame_id == "odom" and
      tr.transform.translation.x == 0 and tr.transform.rotation.w == 1,
      "/tf_static: map -> odom, the identity")

# ---- telemetry.py to-bag: against the log and om.pgm ------------------------------------------

out, log = webtest.settled_run(sim)
tbag = sim.out("log.bag")
p = subprocess.run(["/usr/bin/python3", TOOL, "to-bag", log, tbag], stdout=subprocess.PIPE,
                   stderr=subprocess.PIPE, text=True)
check(p.returncode == 0 and "wrote " + tbag in p.stdout, "to-bag: %s%s" % (p.stdout.strip(), p.stderr))
frames = [f for f in (slamlink.decode(t, pl) for t, pl in slamlink.Decoder().feed(open(log, "rb").read()))
          if f is not None]
hello = next(f for f in frames if f["type"] == "hello")
poses = [f for f in frames if f["type"] == "pose"]
reads = [f for f in frames if f["type"] == "reading"]
rows = [(i, f) for i, f in enumerate(frames) if f["type"] == "map_row" and f["map"] == 0]
passes = [i for i, f in rows if f["row"] == hello["b"] - 1 and f["first"] + len(f["cells"]) == hello["a"]]
last_row = max(i for i, f in enumerate(frames) if f["type"] == "map_row")
types, msgs, latched = read_bag(tbag)
check(types == TYPES, "to-bag: the topics and their types, no truth: %s" % types)
got = msgs["/odom"]
bad = sum(1 for (t, m), f in zip(got, poses) if not (
    ticks(t) == f["ticks"] and m.pose.pose.position.x == f["x_um"] * 1e-6 and
    m.pose.pose.position.y == f["y_um"] * 1e-6 and same_angle(yaw(m.pose.pose.orientation),
                                                              slamlink.wrap_rad(f["heading"]))))
check(len(got) == len(poses) > 100 and bad == 0, "/odom: one per POSE frame (%d), its ticks and pose" % len(got))
check_transforms(msgs["/tf"], {
    "base_link": [(f["ticks"], "odom", f["x_um"] * 1e-6, f["y_um"] * 1e-6, slamlink.wrap_rad(f["heading"]))
                  for f in poses],
    "sonar": [(f["ticks"], "base_link", hello["mount_x_um"] * 1e-6, hello["mount_y_um"] * 1e-6,
               math.radians(90.0 - f["servo_mdeg"] / 1000.0 + hello["mount_yaw_mdeg"] / 1000.0))
              for f in reads]}, "to-bag /tf")
bad = sum(1 for (t, m), f in zip(msgs["/sonar"], reads) if not (
    ticks(t) == f["ticks"] and m.range == (math.inf if f["outcome"] == 4 else f32(f["range_um"] * 1e-6)) and
    m.min_range == f32(hello["range_min_um"] * 1e-6)))
check(len(msgs["/sonar"]) == len(reads) and bad == 0, "/sonar: one per READING frame (%d)" % len(reads))
maps = msgs["/map"]
check(len(maps) == len(passes) + (last_row > passes[-1]) and len(passes) >= 2,
      "/map: one per full pass of OM (%d) and one at the end when rows came after it" % len(passes))
check(grid_matches(maps[-1][1], pgm(os.path.join(out, "om.pgm")), os.path.join(out, "om.yaml")),
      "to-bag: the last /map is the run's om.pgm cell for cell")

# ---- bad input ---------------------------------------------------------------------------------

noise = sim.out("noise.log")
with open(noise, "wb") as f:
    f.write(bytes((i * 7919 + (i >> 3)) % 256 for i in range(5000)))
for args, status, what in (([sim.out("missing.log"), tbag], 2, "No such file"),
                           ([noise, sim.out("n.bag")], 2, "holds no telemetry frame"),
                           ([log, sim.out("no/such/dir.bag")], 1, "cannot write")):
    p = subprocess.run(["/usr/bin/python3", TOOL, "to-bag"] + args, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    check(p.returncode == status and what in p.stderr and "Traceback" not in p.stderr,
          "to-bag %s: exit %d, %s" % (os.path.basename(args[0]), status, p.stderr.strip()))
p = sim.run("--duration", 1, "--out", sim.out("r2"), "--bag", sim.work, expect=2)
check("--bag" in p.stderr, "host_sim --bag into a folder: refused before the run: %s" % p.stderr.strip())
p = subprocess.run(["/usr/bin/python3", "-S", os.path.join(sim.src, "tools", "rosbag_out.py"), "--check"],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(p.returncode == 2 and "python3-rosbag" in p.stderr and "install-deps.sh" in p.stderr,
      "without the ROS packages the tool says which to install: %s" % p.stderr.strip())
sim.done()
