#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A run as a ROS 1 bag, for RViz, Foxglove or any ROS tool: from a host_sim output folder
(host_sim --bag runs this), or from a telemetry log (tools/telemetry.py to-bag).

usage:
  tools/rosbag_out.py RUN_DIR OUT.bag [--fov DEG] [--max-range M] [--quiet]
  tools/rosbag_out.py --check        exit 0 when bags can be written here, else say why

Topics, every stamp the run's own time (simulated seconds from the start; a robot's log:
its ticks since it started):
  /map         nav_msgs/OccupancyGrid  OM, trinary: 100 occupied, 0 free, -1 unknown, with
                                       the resolution and origin of om.yaml (frame map);
                                       a run's at its end, a log's at each full pass of OM
  /odom        nav_msgs/Odometry       the robot's own pose, odom -> base_link (no twist:
                                       the logs carry none)
  /tf          tf2_msgs/TFMessage      odom -> base_link with each pose; base_link -> sonar
                                       with each reading (the servo's angle, Eq. 3)
  /tf_static   tf2_msgs/TFMessage      map -> odom, the identity: the robot maps in its
                                       odometry's frame
  /sonar       sensor_msgs/Range       every reading (frame sonar), ULTRASOUND, the cone's
                                       full width and the sonar's range; a timeout is +inf
  /truth/odom  nav_msgs/Odometry       host_sim only: the true pose (odom -> truth_base_link)
  /truth/map   nav_msgs/OccupancyGrid  host_sim only: truth.pgm

Needs Debian's python3-rosbag and the message packages python3-nav-msgs,
python3-sensor-msgs, python3-geometry-msgs, python3-tf2-msgs (tools/install-deps.sh ros).
Exit status: 0 done; 1 the bag could not be written; 2 bad arguments or input, or the
packages are missing.
"""
import argparse
import sys

from slamtools import link as slamlink
from slamtools.errors import main as tool_main
from slamtools.rosbag import ros, run_to_bag


def main(argv=None):
    doc = __doc__.strip().splitlines()
    ap = argparse.ArgumentParser(prog="tools/rosbag_out.py", description=doc[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(doc[2:]))
    ap.add_argument("run", nargs="?", metavar="RUN_DIR", help="a host_sim output folder")
    ap.add_argument("out", nargs="?", metavar="OUT.bag")
    ap.add_argument("--fov", type=slamlink.arg_real(1.0, 179.0), default=15.0,
                    help="the sonar cone's full width, degrees (default 15, an HC-SR04's)")
    ap.add_argument("--max-range", type=slamlink.arg_real(0.1, 100.0), default=4.0,
                    help="the sonar's longest range, m (default 4, an HC-SR04's)")
    ap.add_argument("--check", action="store_true", help="only say whether bags can be written")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    if args.check:
        ros()
        return 0
    if args.run is None or args.out is None:
        ap.error("give RUN_DIR and OUT.bag")
    counts = run_to_bag(args.run, args.out, args.fov, args.max_range)
    if not args.quiet:
        print("  ROS bag         %s (%s)" % (args.out, ", ".join(
            "%d %s" % (n, t) for t, n in sorted(counts.items()))))
    return 0


if __name__ == "__main__":
    tool_main(main)
