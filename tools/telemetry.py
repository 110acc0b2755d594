#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Talks to the robot over its telemetry link: prints, draws or serves to a browser what it
sends, turns a log into readings for host_sim --replay or a ROS bag, sends it commands.

usage:
  tools/telemetry.py dump SOURCE [--follow [--until-idle S]]  one line per frame
  tools/telemetry.py view SOURCE [--follow [--until-idle S]] [--png FILE [--every S]]
                                                   OM, TM and the path, drawn as they grow
  tools/telemetry.py to-readings LOG [--out DIR]   DIR/readings.csv and DIR/config.txt,
                                                   for host_sim --replay DIR/readings.csv
  tools/telemetry.py send PORT COMMAND [ARGS...] [--wait S] [--out DIR]
                                                   send one command, print the answer
  tools/telemetry.py frame COMMAND [ARGS...]       print a command's frame in hex
  tools/telemetry.py serve SOURCE [--port N] [--host ADDR] [--follow] [--record FILE]
                                                   the browser page and the robot's link
                                                   over a WebSocket (tools/web/README.md)
  tools/telemetry.py to-bag LOG OUT.bag [--fov DEG] [--max-range M]
                                                   a log as a ROS bag: /map, /odom, /tf,
                                                   /sonar (needs python3-rosbag)

SOURCE is a serial device (/dev/ttyUSB0, /dev/ttyAMA0, a pseudo-terminal /dev/pts/N;
needs python3-serial) or a file of raw bytes, such as `host_sim --telemetry FILE` writes.
--follow keeps reading a file that is still growing (host_sim --realtime) until Ctrl-C,
or, with --until-idle S, until the file has not grown for S seconds (the run ended).

view draws into a window; without a display, give --png FILE: the picture is written
at the end, and rewritten every --every seconds (default 5) while --follow reads on.

Commands: start, stop, mode MODE, get KEY, set KEY VALUE, save, map, calibrate.
MODE is one of: %(modes)s.
KEY is a field of slam_config_t (firmware/include/slam/config_fields.h); cal_left,
cal_right and cal_base take decimal factors such as 0.9901. `send PORT map --out DIR`
waits for both maps and writes DIR/om.pgm with its ROS YAML, and DIR/tm.pgm (where the
robot drove: a picture, no YAML, since no map loader should read it as obstacles).

Every field a frame gives that the tool sizes memory by is bounded: a HELLO's grid is
%(grid_min)d..%(grid_max)d cells a side (firmware/include/slam/grid.h), a map row lies within it; frames
beyond are counted as malformed. to-readings writes its rows as it reads them.

Exit status: 0 done; 1 the robot refused a command or did not answer; 2 bad arguments,
or a source with nothing valid in it.
"""
import argparse
import math
import os
import signal
import stat
import sys
import time

from slamtools import link as slamlink, pgm
from slamtools.errors import ToolError, main as tool_main
from slamtools.link import SYNC, Decoder, decode, reading_status  # noqa: F401  (the API)

BAM = slamlink.BAM


def open_port(path, baud):
    try:
        import serial
    except ImportError:
        raise ToolError("reading %s needs python3-serial (tools/install-deps.sh sim)" % path)
    try:
        return serial.Serial(path, baud, timeout=0.1)
    except (serial.SerialException, OSError) as e:
        raise ToolError("cannot open %s: %s" % (path, e))


class Source:
    """Frames from a device or a file; counts what could not be read as frames."""

    # Set by Ctrl-C or SIGTERM (stop()): a source that waits for more bytes ends. The
    # KeyboardInterrupt stop() raises can be lost, when it lands in code that swallows
    # exceptions (a finalizer inside matplotlib, say); this cannot.
    stopping = False
    # While a picture is being saved a Ctrl-C only sets stopping: interrupted inside
    # savefig(), matplotlib can be left unable to save the last picture.
    holding = False

    def __init__(self, path, baud=115200, follow=False, until_idle=None):
        try:
            mode = os.stat(path).st_mode
        except OSError as e:
            raise ToolError("%s: %s" % (path, e.strerror))
        if stat.S_ISDIR(mode):
            raise ToolError("%s is a directory: give a serial device or a telemetry log file" % path)
        self.path = path
        self.device = stat.S_ISCHR(mode)
        self.follow = follow
        self.until_idle = until_idle  # s without new bytes that end a --follow of a file
        self.dec = Decoder()
        self.frames = 0
        self.malformed = 0
        if self.device:
            port = open_port(path, baud)
            self.read = lambda: port.read(4096)
        else:
            try:
                f = open(path, "rb")
            except OSError as e:
                raise ToolError("%s: %s" % (path, e.strerror))
            self.read = lambda: f.read(65536)

    def __iter__(self):
        """Decoded frames; None now and then while waiting for more bytes."""
        last_data = time.monotonic()
        while True:
            try:
                data = self.read()
            except OSError as e:
                raise ToolError("reading %s: %s" % (self.path, e), 1)
            if data:
                last_data = time.monotonic()
            elif not self.device and self.until_idle is not None and \
                    time.monotonic() - last_data >= self.until_idle:
                return
            if not data:
                if (self.device or self.follow) and not Source.stopping:
                    time.sleep(0.05)
                    yield None
                    continue
                return
            for ftype, payload in self.dec.feed(data):
                fr = decode(ftype, payload)
                if fr is None:
                    self.malformed += 1
                    continue
                self.frames += 1
                yield fr

    @property
    def bad(self):
        return self.dec.bad + self.malformed

    def summary(self, prog):
        """A line on stderr: what was read; a ToolError when nothing valid was."""
        if self.frames == 0:
            raise ToolError("%s holds no telemetry frame (%d bytes outside frames, %d frames "
                        "with a bad CRC or length)" % (self.path, self.dec.skipped, self.bad))
        if self.bad:
            print("telemetry %s: %d frames read, %d bad frames skipped (bad CRC or length)"
                  % (prog, self.frames, self.bad), file=sys.stderr)
        if len(self.dec.buf) >= 2:
            print("telemetry %s: the last %d bytes are a frame cut short" % (prog, len(self.dec.buf)),
                  file=sys.stderr)


def cmd_dump(args):
    src = Source(args.source, args.baud, args.follow, args.until_idle)
    for fr in src:
        if fr is not None:
            print(slamlink.describe(fr), flush=args.follow)
    src.summary("dump")


class Maps:
    """OM, TM and the path as the frames tell them; rows that do not fit the grid the last
    HELLO announced are counted, not drawn."""

    def __init__(self, np):
        self.np = np
        self.geo = None
        self.maps = None
        self.path = []
        self.status = {}
        self.bad_rows = 0

    def take(self, fr):
        t = fr["type"]
        if t == "hello":
            if self.geo is None or (self.geo["a"], self.geo["b"]) != (fr["a"], fr["b"]):
                self.maps = [self.np.zeros((fr["b"], fr["a"]), self.np.uint8) for _ in range(2)]
            self.geo = fr
        elif t == "pose":
            self.path.append((fr["x_um"] * 1e-6, fr["y_um"] * 1e-6))
        elif t == "map_row":
            if (self.geo is None or fr["map"] > 1 or fr["row"] >= self.geo["b"]
                    or fr["first"] + len(fr["cells"]) > self.geo["a"]):
                self.bad_rows += 1
                return
            row = self.maps[fr["map"]][fr["row"]]
            row[fr["first"]:fr["first"] + len(fr["cells"])] = list(fr["cells"])
        elif t == "status":
            self.status = fr


def draw(fig, axes, m):
    """Both maps with the path; titles say what and when, axes are in metres."""
    if m.geo is None:
        for ax in axes:
            ax.set_title("waiting for a HELLO frame (the grid's geometry)")
        return
    g = m.geo
    cell = g["cell_um"] * 1e-6
    ox, oy = g["origin_x_um"] * 1e-6, g["origin_y_um"] * 1e-6
    ext = [ox, ox + g["a"] * cell, oy, oy + g["b"] * cell]
    t = m.status.get("ticks", 0) * slamlink.TICK_S
    titles = ("OM, obstacle map: black occupied, white free, grey unknown (%d hits)"
              % m.status.get("om_hits", 0), "TM, trajectory map: visits")
    if m.status.get("outside"):
        titles = (titles[0] + "\nTHE HOME DOES NOT FIT THE GRID: %d points fell outside it"
                  % m.status["outside"], titles[1])
    images = (slamlink.trinary(g["om_mode"], m.maps[0], m.maps[1]),
              slamlink.counts_image(m.maps[1], g["tm_max"]))
    for ax, img, title in zip(axes, images, titles):
        ax.clear()
        ax.imshow(img, origin="upper", extent=ext, cmap="gray", vmin=0, vmax=255,
                  interpolation="nearest")
        if m.path:
            xs, ys = zip(*m.path)
            ax.plot(xs, ys, "r-", lw=0.8, label="odometry path")
            ax.plot(xs[-1:], ys[-1:], "ro", ms=4)
            ax.set_xlim(min(xs) - 2, max(xs) + 2)
            ax.set_ylim(min(ys) - 2, max(ys) + 2)
            ax.legend(loc="lower right", fontsize=8)
        ax.set_title(title)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal")
    fig.suptitle("robot telemetry at t = %.1f s (cells of %.0f mm)" % (t, cell * 1e3))


INTERACTIVE = ("gtk3agg", "gtk4agg", "tkagg", "qtagg", "qt5agg", "wxagg", "macosx", "webagg",
               "gtk3cairo", "gtk4cairo", "qtcairo", "tkcairo", "wxcairo", "nbagg")


def cmd_view(args):
    try:
        import matplotlib
        if args.png:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        raise ToolError("%s (tools/install-deps.sh sim)" % e)
    if not args.png and matplotlib.get_backend().lower() not in INTERACTIVE:
        raise ToolError("no display to draw on (matplotlib backend '%s'%s). Draw into a "
                    "picture instead: tools/telemetry.py view %s --png view.png%s"
                    % (matplotlib.get_backend(), "" if os.environ.get("DISPLAY") else
                       ", DISPLAY is not set", args.source,
                       " --follow (rewritten every %g s)" % args.every if args.follow else ""))
    src = Source(args.source, args.baud, args.follow, args.until_idle)
    m = Maps(np)
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    last = time.time()

    def save():
        Source.holding = True
        try:
            draw(fig, axes, m)
            tmp = args.png + ".tmp.png"
            fig.savefig(tmp, dpi=80)
            os.replace(tmp, args.png)  # a viewer of the file never sees half a picture
        finally:
            Source.holding = False

    if not args.png:
        plt.ion()
        plt.show()
    try:
        for fr in src:
            if fr is not None:
                m.take(fr)
            now = time.time()
            if not args.png and now - last > 0.5:
                draw(fig, axes, m)
                plt.pause(0.001)
                last = now
            elif args.png and args.follow and now - last > args.every:
                save()
                last = now
    except KeyboardInterrupt:
        pass
    src.summary("view")
    if m.bad_rows:
        print("telemetry view: %d map rows outside the grid skipped" % m.bad_rows, file=sys.stderr)
    if args.png:
        save()
        print("telemetry view: wrote %s" % args.png)
    else:
        draw(fig, axes, m)
        plt.ioff()
        plt.show()


def cmd_to_readings(args):
    """READING frames as readings.csv rows, the HELLO's grid and sonar as config.txt. The
    rows go to the file as they are read: memory stays the same for a log of any length."""
    src = Source(args.log, args.baud, False)
    if src.device:
        raise ToolError("%s is a device: record a log first (cat %s > run.log, or "
                    "host_sim --telemetry FILE)" % (args.log, args.log))
    out = args.out or os.path.splitext(args.log)[0] + "-readings"
    hello = None
    changed = 0
    rows = 0
    drops = 0
    csv_path = os.path.join(out, "readings.csv")
    tmp = csv_path + ".tmp"
    created = not os.path.isdir(out)
    try:
        os.makedirs(out, exist_ok=True)
        f = open(tmp, "w")
    except OSError as e:
        raise ToolError("cannot write into %s: %s" % (out, e.strerror), 1)
    done = False
    try:
        with f:
            f.write("t_s,servo_deg,range_m,status,odom_x_m,odom_y_m,odom_th_rad\n")
            for fr in src:
                if fr["type"] == "hello" and "confidence_radius_um" in fr:
                    same = dict(fr, type=None) == dict(hello, type=None) if hello else True
                    changed += not same
                    hello = hello or fr
                elif fr["type"] == "reading":
                    status = reading_status(fr["outcome"])
                    rng = "" if status == "timeout" else "%.6f" % (fr["range_um"] * 1e-6)
                    f.write("%.2f,%.3f,%s,%s,%.6f,%.6f,%.10f\n" % (
                        fr["ticks"] * slamlink.TICK_S, fr["servo_mdeg"] / 1000.0, rng, status,
                        fr["x_um"] * 1e-6, fr["y_um"] * 1e-6, slamlink.wrap_rad(fr["heading"])))
                    rows += 1
                elif fr["type"] == "status":
                    drops = fr["drops"]
        src.summary("to-readings")
        if hello is None:
            raise ToolError("%s has no HELLO frame with the sonar's settings (the firmware "
                        "sends one every 5 s; a log from before telemetry version 2 lacks them)"
                        % args.log)
        if not rows:
            raise ToolError("%s has no READING frame" % args.log)
        # The grid's origin is start - (cell (0, 0)) - half a cell: with the start in cell
        # (0, 0), start = origin + half a cell, whatever the robot's own start cell was.
        half = hello["cell_um"] // 2
        cfg = [("cell_um", hello["cell_um"]), ("start_cell_a", 0), ("start_cell_b", 0),
               ("start_x_um", hello["origin_x_um"] + half),
               ("start_y_um", hello["origin_y_um"] + half),
               ("om_max", hello["om_max"]), ("tm_max", hello["tm_max"]),
               ("om_mode", hello["om_mode"])] + [
               (k, hello[k]) for k in ("om_hit", "om_miss") if k in hello] + [
               ("confidence_radius_um", hello["confidence_radius_um"]),
               ("range_min_um", hello["range_min_um"]), ("mount_x_um", hello["mount_x_um"]),
               ("mount_y_um", hello["mount_y_um"]), ("mount_yaw_mdeg", hello["mount_yaw_mdeg"])]
        write_text(os.path.join(out, "config.txt"),
                   "# the grid and the sonar as %s's HELLO frames tell them "
                   "(host_sim --replay reads it)\n" % os.path.basename(args.log)
                   + "".join("%s = %d\n" % kv for kv in cfg))
        os.replace(tmp, csv_path)
        done = True
    except OSError as e:
        raise ToolError("cannot write into %s: %s" % (out, e.strerror), 1)
    finally:
        if not done:  # a log that gives nothing leaves nothing behind
            if os.path.exists(tmp):
                os.unlink(tmp)
            if created:
                try:
                    os.rmdir(out)
                except OSError:
                    pass
    print("telemetry to-readings: %d readings into %s; the grid and sonar settings into %s"
          % (rows, csv_path, os.path.join(out, "config.txt")))
    print("  replay: host_sim --replay %s --out %s" % (csv_path, os.path.join(out, "replay")))
    if changed:
        print("telemetry to-readings: warning: the HELLO frames changed %d times (a SET of the sonar's "
              "settings?); config.txt holds the first" % changed, file=sys.stderr)
    if drops:
        print("telemetry to-readings: warning: the robot dropped %d telemetry events: readings are "
              "missing, and the replay will differ from the robot's map" % drops, file=sys.stderr)


def write_text(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def write_pgm(out, name, img, geo, yaml):
    """An image (first row the northern one) as the simulator writes it: PGM, and the ROS
    YAML of a trinary map when yaml is set (TM has none: it is not a map to load)."""
    pgm.write(os.path.join(out, name + ".pgm"), img)
    if yaml:
        write_text(os.path.join(out, name + ".yaml"),
                   pgm.yaml_text(name, geo["cell_um"], geo["origin_x_um"], geo["origin_y_um"]))


def cmd_send(args):
    data = slamlink.command(args.words)
    try:
        mode = os.stat(args.port).st_mode
    except OSError as e:
        raise ToolError("%s: %s" % (args.port, e.strerror))
    if not stat.S_ISCHR(mode):
        raise ToolError("%s is not a serial device or a pseudo-terminal" % args.port)
    port = open_port(args.port, args.baud)
    port.write(data)
    port.flush()
    ctype = data[2]
    dec = Decoder()
    want_map = args.words[0] == "map" and args.out
    answer = None
    geo = None
    rows = {}
    have = {}  # cells arrived per (map, row): completeness without going over them all
    deadline = time.time() + args.wait
    while time.time() < deadline:
        for ftype, payload in dec.feed(port.read(4096)):
            fr = decode(ftype, payload)
            if fr is None:
                continue
            if fr["type"] in ("ack", "error") and fr["command"] == ctype and answer is None:
                answer = fr
                print(slamlink.describe(fr))
            elif fr["type"] == "config" and ctype in (0x13, 0x14) and answer is None:
                answer = fr
                print(slamlink.describe(fr))
            elif want_map and answer and fr["type"] == "hello":
                if geo is not None and (geo["a"], geo["b"]) != (fr["a"], fr["b"]):
                    rows.clear()  # another grid: what came for the last one is not its map
                    have.clear()
                geo = fr
            elif (want_map and geo and fr["type"] == "map_row" and fr["map"] < 2
                  and fr["row"] < geo["b"] and fr["first"] + len(fr["cells"]) <= geo["a"]):
                key = (fr["map"], fr["row"], fr["first"])
                if key not in rows:
                    have[key[:2]] = have.get(key[:2], 0) + len(fr["cells"])
                rows[key] = fr["cells"]
        if answer is not None and (not want_map or answer["type"] == "error"):
            break
        if want_map and geo and map_complete(have, geo):
            break
    if answer is None:
        raise ToolError("%s did not answer within %g s" % (args.port, args.wait), 1)
    if answer["type"] == "error":
        raise ToolError("the robot refused it: %s" % slamlink.ERROR_TEXT.get(
            slamlink.ERRORS.get(answer["code"]), "code %d" % answer["code"]), 1)
    if want_map:
        if geo is None or not map_complete(have, geo):
            raise ToolError("the maps did not arrive whole within %g s (--wait)" % args.wait, 1)
        os.makedirs(args.out, exist_ok=True)
        import numpy as np
        grids = [np.zeros((geo["b"], geo["a"]), np.uint8) for _ in range(2)]
        for (m, row, first), cells in rows.items():
            if m in (0, 1) and row < geo["b"] and first + len(cells) <= geo["a"]:
                grids[m][row, first:first + len(cells)] = np.frombuffer(cells, np.uint8)
        write_pgm(args.out, "om", slamlink.trinary(geo["om_mode"], grids[0], grids[1]), geo, True)
        write_pgm(args.out, "tm", slamlink.counts_image(grids[1], geo["tm_max"]), geo, False)
        print("telemetry send: wrote %s/om.pgm (with its ROS .yaml) and %s/tm.pgm"
              % (args.out, args.out))


def map_complete(have, geo):
    """Every cell of both maps arrived: `have` counts the cells of each (map, row)."""
    return len(have) == 2 * geo["b"] and all(n >= geo["a"] for n in have.values())


def cmd_frame(args):
    print(slamlink.command(args.words).hex(" "))


def cmd_serve(args):
    from slamtools import bridge
    try:
        bridge.serve(args.source, args.host, args.port, args.baud, args.follow,
                     record=args.record)
    except KeyboardInterrupt:
        pass


def cmd_to_bag(args):
    from slamtools import rosbag
    n = rosbag.log_to_bag(args.log, args.out, args.fov, args.max_range)
    print("telemetry to-bag: wrote %s: %s" % (args.out, ", ".join(
        "%d on %s" % (c, t) for t, c in sorted(n.items()))))


def main(argv=None):
    doc = (__doc__ % {"modes": ", ".join(slamlink.MODES), "grid_min": slamlink.GRID_SIDE_MIN,
                      "grid_max": slamlink.GRID_SIDE_MAX}).strip().splitlines()
    ap = argparse.ArgumentParser(prog="tools/telemetry.py", description=doc[0] + " " + doc[1],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(doc[3:]))
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    p = sub.add_parser("dump", help="print one line per frame")
    p.add_argument("source")
    p.add_argument("--follow", action="store_true", help="keep reading a growing file")
    p.add_argument("--until-idle", type=float, metavar="S",
                   help="with --follow: end once the file has not grown for S seconds")
    p = sub.add_parser("view", help="draw OM, TM and the path")
    p.add_argument("source")
    p.add_argument("--follow", action="store_true", help="keep reading a growing file")
    p.add_argument("--until-idle", type=float, metavar="S",
                   help="with --follow: end once the file has not grown for S seconds")
    p.add_argument("--png", help="draw into this PNG file instead of a window")
    p.add_argument("--every", type=slamlink.arg_real(0.01, 1e6), default=5.0,
                   help="with --png and --follow: rewrite the picture this often, s (default 5)")
    p = sub.add_parser("to-readings", help="a log as readings.csv for host_sim --replay")
    p.add_argument("log")
    p.add_argument("--out", help="folder for readings.csv and config.txt (default: LOG "
                                 "without its extension, plus -readings)")
    p = sub.add_parser("send", help="send a command to the robot and print its answer")
    p.add_argument("port")
    p.add_argument("words", nargs="+", metavar="COMMAND")
    p.add_argument("--wait", type=slamlink.arg_real(0.0, 1e6), default=3.0,
                   help="seconds to wait for the answer")
    p.add_argument("--out", help="with `map`: write the maps into this folder")
    p = sub.add_parser("frame", help="print a command's frame in hex")
    p.add_argument("words", nargs="+", metavar="COMMAND")
    p = sub.add_parser("serve", help="the browser page and the robot's link over a WebSocket")
    p.add_argument("source", help="serial device, pseudo-terminal (or a link to one), or a "
                                  "telemetry file")
    p.add_argument("--port", type=slamlink.arg_int(0, 65535), default=8765, help="TCP port (default 8765; 0: any free)")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1, this machine only; "
                        "0.0.0.0: every network, e.g. a robot watched over Wi-Fi)")
    p.add_argument("--follow", action="store_true", help="a file: keep sending what is added")
    p.add_argument("--record", metavar="FILE",
                   help="a device: also append every byte it sends to FILE (a log for "
                        "to-bag or to-readings)")
    p = sub.add_parser("to-bag", help="a log as a ROS bag (/map, /odom, /tf, /sonar)")
    p.add_argument("log")
    p.add_argument("out", metavar="OUT.bag")
    p.add_argument("--fov", type=slamlink.arg_real(1.0, 179.0), default=15.0,
                   help="the sonar cone's full width, degrees (default 15, an HC-SR04's)")
    p.add_argument("--max-range", type=slamlink.arg_real(0.1, 100.0), default=4.0,
                   help="the sonar's longest range, m (default 4, an HC-SR04's)")
    for p in sub.choices.values():
        p.add_argument("--baud", type=slamlink.arg_int(1, 2**31 - 1), default=115200, help="serial speed (default 115200)")
    args = ap.parse_args(argv)
    if args.command == "view" and args.every <= 0:
        ap.error("--every must be positive")
    if getattr(args, "until_idle", None) is not None and \
            (not args.follow or not args.until_idle > 0):
        ap.error("--until-idle S needs --follow and a positive S")
    if args.command == "serve" and not 0 <= args.port <= 65535:
        ap.error("--port must be 0..65535")
    if args.command == "to-bag" and not (0 < args.fov < 180 and 0 < args.max_range <= 100):
        ap.error("--fov must be within 0..180 degrees and --max-range within 0..100 m")
    handlers = {"dump": cmd_dump, "view": cmd_view, "to-readings": cmd_to_readings,
                "send": cmd_send, "frame": cmd_frame, "serve": cmd_serve, "to-bag": cmd_to_bag}
    # SIGTERM (a service manager, kill) ends a --follow as Ctrl-C does: the picture is
    # drawn a last time; and Ctrl-C works even where the shell started us with it ignored.
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    try:
        handlers[args.command](args)
    except ToolError as e:
        e.prog = e.prog or "telemetry " + args.command
        raise
    except MemoryError:
        # The limits above keep every array a frame asks for small; this is the last word
        # when the machine has less memory than even that needs.
        print("telemetry %s: out of memory" % args.command, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return 0
    return 0


def stop(signum, frame):
    Source.stopping = True
    if not Source.holding:
        raise KeyboardInterrupt


def frames(path, baud=115200, follow=False):
    """Decoded frames of a file or device (None while waiting), for other tools and tests."""
    return iter(Source(path, baud, follow))


if __name__ == "__main__":
    tool_main(main)
