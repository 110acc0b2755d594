# SPDX-License-Identifier: MIT
"""A run as a ROS 1 bag (tools/rosbag_out.py's --help lists the topics): from a host_sim
output folder, or from a telemetry log (tools/telemetry.py to-bag). ROS's modules are
imported only when a bag is written: the rest of the tools never need them."""
import csv
import math
import os
import stat

from . import link as slamlink, pgm
from .errors import ToolError

ULTRASOUND = 0


def ros():
    """The ROS modules, or ToolError naming the packages to install."""
    try:
        import rosbag
        import rospy
        from geometry_msgs.msg import TransformStamped
        from nav_msgs.msg import OccupancyGrid, Odometry
        from sensor_msgs.msg import Range
        from tf2_msgs.msg import TFMessage
    except ImportError as e:
        raise ToolError("writing a ROS bag needs python3-rosbag, python3-nav-msgs, "
                       "python3-sensor-msgs, python3-geometry-msgs and python3-tf2-msgs "
                       "(tools/install-deps.sh ros): %s" % e)
    return dict(rosbag=rosbag, Time=rospy.Time, TransformStamped=TransformStamped,
                OccupancyGrid=OccupancyGrid, Odometry=Odometry, Range=Range, TFMessage=TFMessage)


def stamp(R, ticks):
    """A time of whole 10 ms ticks, exactly."""
    return R["Time"](ticks // 100, ticks % 100 * 10000000)


def yaw_quaternion(q, yaw):
    q.x = q.y = 0.0
    q.z = math.sin(yaw / 2.0)
    q.w = math.cos(yaw / 2.0)


class Writer:
    """Messages gathered with their stamps, written in time order (a bag's readers play it
    in that order); counts by topic."""

    def __init__(self, R):
        self.R = R
        self.items = []
        self.counts = {}

    def add(self, topic, ticks, msg, latched=False):
        self.items.append((ticks, len(self.items), topic, msg, latched))
        self.counts[topic] = self.counts.get(topic, 0) + 1

    def odom(self, topic, ticks, x, y, th, child):
        m = self.R["Odometry"]()
        m.header.stamp = stamp(self.R, ticks)
        m.header.frame_id = "odom"
        m.child_frame_id = child
        m.pose.pose.position.x = x
        m.pose.pose.position.y = y
        yaw_quaternion(m.pose.pose.orientation, th)
        self.add(topic, ticks, m)

    def transform(self, ticks, parent, child, x, y, yaw):
        t = self.R["TransformStamped"]()
        t.header.stamp = stamp(self.R, ticks)
        t.header.frame_id = parent
        t.child_frame_id = child
        t.transform.translation.x = x
        t.transform.translation.y = y
        yaw_quaternion(t.transform.rotation, yaw)
        return t

    def tf(self, ticks, parent, child, x, y, yaw, static=False):
        self.add("/tf_static" if static else "/tf", ticks,
                 self.R["TFMessage"](transforms=[self.transform(ticks, parent, child, x, y, yaw)]),
                 latched=static)

    def reading(self, ticks, servo_deg, range_m, sonar):
        """base_link -> sonar at the servo's angle, and the Range (None: a timeout)."""
        yaw = math.radians(90.0 - servo_deg + sonar["mount_yaw_deg"])
        self.tf(ticks, "base_link", "sonar", sonar["mount_x"], sonar["mount_y"], yaw)
        m = self.R["Range"]()
        m.header.stamp = stamp(self.R, ticks)
        m.header.frame_id = "sonar"
        m.radiation_type = ULTRASOUND
        m.field_of_view = math.radians(sonar["fov_deg"])
        m.min_range = sonar["min_range"]
        m.max_range = sonar["max_range"]
        m.range = math.inf if range_m is None else range_m  # REP 117: +inf, nothing seen
        self.add("/sonar", ticks, m)

    def grid(self, topic, ticks, image, resolution, origin_x, origin_y, thresholds=None):
        """A map image (PGM values, first row the northern one) as an OccupancyGrid, by
        map_server's trinary rule: occupied above occupied_thresh, free below free_thresh,
        else unknown."""
        import numpy as np
        occ_t, free_t, negate = thresholds or (0.65, 0.196, 0)
        img = np.asarray(image, dtype=np.float64)[::-1]  # row 0 at the origin, as ROS has it
        p = img / 255.0 if negate else (255.0 - img) / 255.0
        data = np.full(img.shape, -1, np.int8)
        data[p > occ_t] = 100
        data[p < free_t] = 0
        m = self.R["OccupancyGrid"]()
        m.header.stamp = stamp(self.R, ticks)
        m.header.frame_id = "map"
        m.info.map_load_time = m.header.stamp
        m.info.resolution = resolution
        m.info.width = img.shape[1]
        m.info.height = img.shape[0]
        m.info.origin.position.x = origin_x
        m.info.origin.position.y = origin_y
        m.info.origin.orientation.w = 1.0
        m.data = data.ravel().tolist()
        self.add(topic, ticks, m, latched=True)

    def write(self, path):
        tmp = path + ".tmp"
        try:
            bag = self.R["rosbag"].Bag(tmp, "w")
            try:
                for ticks, _, topic, msg, latched in sorted(self.items, key=lambda i: i[:2]):
                    # A map and the static transform are latched, as map_server publishes
                    # them: a player hands them to every subscriber that comes later.
                    header = {"topic": topic, "type": msg._type, "md5sum": msg._md5sum,
                              "message_definition": msg._full_text, "callerid": "/sonarslam",
                              "latching": "1"} if latched else None
                    bag.write(topic, msg, t=stamp(self.R, ticks), connection_header=header)
            finally:
                bag.close()
            os.replace(tmp, path)
        except (OSError, ValueError, self.R["rosbag"].ROSBagException) as e:
            try:
                os.unlink(tmp)
            except OSError:
                pass
            raise ToolError("cannot write %s: %s" % (path, e), 1)
        return dict(self.counts)


# ---- a host_sim run ----------------------------------------------------------------------------

def read_config(path):
    cfg = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0]
            if "=" in line:
                k, v = line.split("=", 1)
                cfg[k.strip()] = v.strip()
    return cfg


def ticks_of(t_s):
    return int(round(float(t_s) * 100))


def run_to_bag(run, out, fov_deg=15.0, max_range=4.0):
    """A host_sim output folder as a bag; the counts of messages by topic."""
    R = ros()
    files = ("trajectory.csv", "readings.csv", "om.pgm", "om.yaml", "truth.pgm", "truth.yaml",
             "config.txt")
    for name in files:
        if not os.path.isfile(os.path.join(run, name)):
            raise ToolError("%s has no %s: give a host_sim output folder" % (run, name))
    try:
        cfg = read_config(os.path.join(run, "config.txt"))
        sonar = dict(mount_x=int(cfg["mount_x_um"]) * 1e-6, mount_y=int(cfg["mount_y_um"]) * 1e-6,
                     mount_yaw_deg=int(cfg["mount_yaw_mdeg"]) / 1000.0, fov_deg=fov_deg,
                     min_range=int(cfg["range_min_um"]) * 1e-6, max_range=max_range)
    except (KeyError, ValueError) as e:
        raise ToolError("%s/config.txt: %s is missing or not a number" % (run, e))
    w = Writer(R)
    with open(os.path.join(run, "trajectory.csv")) as f:
        traj = list(csv.DictReader(f))
    if not traj:
        raise ToolError("%s/trajectory.csv has no rows" % run)
    first, last = ticks_of(traj[0]["t_s"]), ticks_of(traj[-1]["t_s"])
    w.tf(first, "map", "odom", 0.0, 0.0, 0.0, static=True)
    for row in traj:
        k = ticks_of(row["t_s"])
        x, y, th = float(row["odom_x_m"]), float(row["odom_y_m"]), float(row["odom_th_rad"])
        w.odom("/odom", k, x, y, th, "base_link")
        w.tf(k, "odom", "base_link", x, y, th)
        w.odom("/truth/odom", k, float(row["true_x_m"]), float(row["true_y_m"]),
               float(row["true_th_rad"]), "truth_base_link")
    with open(os.path.join(run, "readings.csv")) as f:
        for row in csv.DictReader(f):
            rng = None if row["status"] == "timeout" else float(row["range_m"])
            w.reading(ticks_of(row["t_s"]), float(row["servo_deg"]), rng, sonar)
    for topic, name, k in (("/map", "om", last), ("/truth/map", "truth", first)):
        y = pgm.read_yaml(os.path.join(run, name + ".yaml"))
        w.grid(topic, k, pgm.read(os.path.join(run, name + ".pgm")), y["resolution"],
               y["origin"][0], y["origin"][1],
               (y["occupied_thresh"], y["free_thresh"], y["negate"]))
    return w.write(out)


# ---- a telemetry log --------------------------------------------------------------------------

def log_to_bag(log, out, fov_deg=15.0, max_range=4.0):
    """A telemetry log (host_sim --telemetry, or a capture of the robot) as a bag: /odom
    and /tf from POSE, /sonar from READING, /map at each full pass of OM and at the end."""
    import numpy as np
    try:
        if stat.S_ISCHR(os.stat(log).st_mode):
            raise ToolError("%s is a device: record a log first (cat %s > run.log)" % (log, log))
        f = open(log, "rb")
    except OSError as e:
        raise ToolError("%s: %s" % (log, e.strerror))
    R = ros()
    w = Writer(R)
    dec = slamlink.Decoder()
    geo = None
    om = tm = None
    ticks = 0
    started = False
    changed = False  # map rows since the last /map
    frames = 0

    def publish():
        cell = geo["cell_um"] * 1e-6
        w.grid("/map", ticks, slamlink.trinary(geo["om_mode"], om, tm), cell,
               geo["origin_x_um"] * 1e-6, geo["origin_y_um"] * 1e-6)

    with f:
        while True:
            data = f.read(1 << 16)
            if not data:
                break
            for ftype, payload in dec.feed(data):
                fr = slamlink.decode(ftype, payload)
                if fr is None:
                    continue
                frames += 1
                t = fr["type"]
                ticks = fr.get("ticks", ticks)
                if t == "hello":
                    if geo is None or (geo["a"], geo["b"]) != (fr["a"], fr["b"]):
                        om = np.full((fr["b"], fr["a"]), slamlink.EVIDENCE_ZERO
                                     if fr["om_mode"] == slamlink.OM_EVIDENCE else 0, np.uint8)
                        tm = np.zeros((fr["b"], fr["a"]), np.uint8)
                    geo = fr
                    if not started:
                        w.tf(ticks, "map", "odom", 0.0, 0.0, 0.0, static=True)
                        started = True
                elif t == "pose":
                    x, y, th = fr["x_um"] * 1e-6, fr["y_um"] * 1e-6, slamlink.wrap_rad(fr["heading"])
                    w.odom("/odom", ticks, x, y, th, "base_link")
                    w.tf(ticks, "odom", "base_link", x, y, th)
                elif t == "reading" and geo is not None and "mount_x_um" in geo:
                    sonar = dict(mount_x=geo["mount_x_um"] * 1e-6, mount_y=geo["mount_y_um"] * 1e-6,
                                 mount_yaw_deg=geo["mount_yaw_mdeg"] / 1000.0, fov_deg=fov_deg,
                                 min_range=geo["range_min_um"] * 1e-6, max_range=max_range)
                    rng = None if fr["outcome"] == 4 else fr["range_um"] * 1e-6
                    w.reading(ticks, fr["servo_mdeg"] / 1000.0, rng, sonar)
                elif t == "map_row" and geo is not None:
                    n = len(fr["cells"])
                    if fr["map"] > 1 or fr["row"] >= geo["b"] or fr["first"] + n > geo["a"]:
                        continue
                    grid = om if fr["map"] == 0 else tm
                    grid[fr["row"], fr["first"]:fr["first"] + n] = np.frombuffer(fr["cells"], np.uint8)
                    changed = True
                    if fr["map"] == 0 and fr["row"] == geo["b"] - 1 and fr["first"] + n == geo["a"]:
                        publish()  # a whole pass of OM
                        changed = False
    if frames == 0:
        raise ToolError("%s holds no telemetry frame" % log)
    if geo is None:
        raise ToolError("%s has no HELLO frame (the grid's geometry): the firmware sends one "
                       "every 5 s" % log)
    if changed:
        publish()
    return w.write(out)
