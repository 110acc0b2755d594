#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Reads the robot's telemetry (firmware/include/slam/telemetry.h) from a serial port, a
pseudo-terminal or a file, and prints it or draws the maps live.

usage:
  tools/telemetry.py dump SOURCE [--baud N]            one line per frame
  tools/telemetry.py view SOURCE [--baud N] [--follow] [--png FILE]
                                                       OM, TM and the path, updated live

SOURCE is a serial device (/dev/ttyUSB0, /dev/ttyAMA0, /dev/pts/N: needs python3-serial)
or a file of raw bytes, such as host_sim --telemetry FILE writes; --follow keeps reading
a file that is still growing (host_sim --realtime). --png draws the last state into FILE
instead of opening a window.
"""
import argparse
import math
import os
import stat
import struct
import sys
import time

SYNC = b"\xa5\x5a"
HELLO, POSE, READING, MAP_ROW, STATUS = 1, 2, 3, 4, 5
OUTCOMES = ("hit", "far", "near", "outside", "timeout")
BAM = 2.0 * math.pi / 4294967296.0


def crc16(data):
    """CRC-16/CCITT-FALSE, as the firmware computes it."""
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


class Decoder:
    """Feeds bytes, yields (type, payload) of every frame whose CRC checks out."""

    def __init__(self):
        self.buf = bytearray()
        self.bad = 0

    def feed(self, data):
        self.buf += data
        out = []
        while True:
            i = self.buf.find(SYNC)
            if i < 0:
                del self.buf[:max(0, len(self.buf) - 1)]
                break
            del self.buf[:i]
            if len(self.buf) < 6:
                break
            n = self.buf[3]
            if len(self.buf) < 6 + n:
                break
            body = bytes(self.buf[2:4 + n])
            crc = self.buf[4 + n] | self.buf[5 + n] << 8
            if crc != crc16(body):
                self.bad += 1
                del self.buf[:1]
                continue
            out.append((body[0], body[2:]))
            del self.buf[:6 + n]
        return out


def decode(ftype, p):
    """A frame as a dict."""
    if ftype == HELLO:
        v, a, b, cell, ox, oy, om_max, tm_max = struct.unpack("<BHHIiiBB", p)
        return dict(type="hello", version=v, a=a, b=b, cell_um=cell, origin_x_um=ox,
                    origin_y_um=oy, om_max=om_max, tm_max=tm_max)
    if ftype == POSE:
        t, x, y, h = struct.unpack("<IiiI", p)
        return dict(type="pose", ticks=t, x_um=x, y_um=y, heading=h)
    if ftype == READING:
        t, stop, outcome, servo, rng, x, y, h = struct.unpack("<IBBiIiiI", p)
        return dict(type="reading", ticks=t, stop=stop, outcome=outcome, servo_mdeg=servo,
                    range_um=rng, x_um=x, y_um=y, heading=h)
    if ftype == MAP_ROW:
        which, row, first = struct.unpack("<BHH", p[:5])
        return dict(type="map_row", map=which, row=row, first=first, cells=bytes(p[5:]))
    if ftype == STATUS:
        names = ("ticks", "pings", "echoes", "timeouts", "om_hits", "overruns", "saves", "drops")
        return dict(zip(names, struct.unpack("<8I", p)), type="status")
    return dict(type="unknown", code=ftype, length=len(p))


def frames(path, baud, follow):
    """Yields decoded frames from a device or a file."""
    dec = Decoder()
    mode = os.stat(path).st_mode
    if stat.S_ISCHR(mode):
        try:
            import serial
        except ImportError:
            sys.exit("telemetry: reading a serial device needs python3-serial")
        port = serial.Serial(path, baud, timeout=0.2)
        read = lambda: port.read(4096)
    else:
        f = open(path, "rb")
        read = lambda: f.read(65536)
    while True:
        data = read()
        if not data:
            if stat.S_ISCHR(mode) or follow:
                time.sleep(0.05)
                yield None
                continue
            return
        for ftype, payload in dec.feed(data):
            yield decode(ftype, payload)


def dump(args):
    for fr in frames(args.source, args.baud, args.follow):
        if fr is None:
            continue
        if fr["type"] == "map_row":
            print("map_row map=%s row=%d first=%d cells=%d" % (
                "OM" if fr["map"] == 0 else "TM", fr["row"], fr["first"], len(fr["cells"])))
        elif fr["type"] == "reading":
            print("reading t=%.2f stop=%d servo=%.1f range=%.3f %s pose=(%.3f, %.3f, %.1f)" % (
                fr["ticks"] / 100.0, fr["stop"], fr["servo_mdeg"] / 1000.0, fr["range_um"] * 1e-6,
                OUTCOMES[fr["outcome"]] if fr["outcome"] < len(OUTCOMES) else fr["outcome"],
                fr["x_um"] * 1e-6, fr["y_um"] * 1e-6, math.degrees(fr["heading"] * BAM)))
        else:
            print(" ".join("%s=%s" % (k, v) for k, v in fr.items()))


def view(args):
    try:
        import matplotlib
        if args.png:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        sys.exit("telemetry: %s (tools/install-deps.sh sim)" % e)
    geo = None
    maps = None
    path = []
    hits = []
    status = {}
    fig, (ax_om, ax_tm) = plt.subplots(1, 2, figsize=(12, 6))
    last_draw = 0.0

    def draw():
        if geo is None:
            return
        cell = geo["cell_um"] * 1e-6
        ox, oy = geo["origin_x_um"] * 1e-6, geo["origin_y_um"] * 1e-6
        ext = [ox, ox + geo["a"] * cell, oy, oy + geo["b"] * cell]
        for ax, m, vmax, title in ((ax_om, maps[0], geo["om_max"], "OM"),
                                   (ax_tm, maps[1], geo["tm_max"], "TM")):
            ax.clear()
            ax.imshow(m, origin="lower", extent=ext, cmap="gray_r", vmin=0, vmax=vmax,
                      interpolation="nearest")
            if path:
                xs, ys = zip(*path)
                ax.plot(xs, ys, "r-", lw=0.8)
            ax.set_title("%s   t = %.1f s, %d OM hits" % (title, status.get("ticks", 0) / 100.0,
                                                          status.get("om_hits", 0)))
            if path:
                xs, ys = zip(*path)
                ax.set_xlim(min(xs) - 2, max(xs) + 2)
                ax.set_ylim(min(ys) - 2, max(ys) + 2)
            ax.set_aspect("equal")

    if not args.png:
        plt.ion()
        plt.show()
    for fr in frames(args.source, args.baud, args.follow):
        if fr is not None:
            t = fr["type"]
            if t == "hello":
                if geo is None or (geo["a"], geo["b"]) != (fr["a"], fr["b"]):
                    maps = [np.zeros((fr["b"], fr["a"]), np.uint8) for _ in range(2)]
                geo = fr
            elif t == "pose":
                path.append((fr["x_um"] * 1e-6, fr["y_um"] * 1e-6))
            elif t == "map_row" and maps is not None and fr["map"] < 2:
                row = maps[fr["map"]][fr["row"]]
                row[fr["first"]:fr["first"] + len(fr["cells"])] = list(fr["cells"])
            elif t == "status":
                status = fr
        if not args.png and time.time() - last_draw > 0.5:
            draw()
            plt.pause(0.001)
            last_draw = time.time()
    draw()
    if args.png:
        fig.savefig(args.png, dpi=80)
    else:
        plt.ioff()
        plt.show()


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.strip().splitlines()[2:]))
    ap.add_argument("command", choices=("dump", "view"))
    ap.add_argument("source")
    ap.add_argument("--baud", type=int, default=115200)
    ap.add_argument("--follow", action="store_true")
    ap.add_argument("--png")
    args = ap.parse_args()
    if not os.path.exists(args.source):
        sys.exit("telemetry: %s does not exist" % args.source)
    try:
        (dump if args.command == "dump" else view)(args)
    except KeyboardInterrupt:
        pass
    except BrokenPipeError:
        pass


if __name__ == "__main__":
    main()
