# SPDX-License-Identifier: MIT
"""The robot's link in Python: telemetry frames in, command frames out, as
firmware/include/slam/telemetry.h describes them (tools/telemetry.py is the program)."""
import math
import struct

SYNC = b"\xa5\x5a"
HELLO, POSE, READING, MAP_ROW, STATUS, ACK, ERROR, CONFIG = range(1, 9)
FRAME_NAMES = {HELLO: "hello", POSE: "pose", READING: "reading", MAP_ROW: "map_row",
               STATUS: "status", ACK: "ack", ERROR: "error", CONFIG: "config"}

# Commands: name -> (type, payload length).
COMMANDS = {"start": (0x10, 0), "stop": (0x11, 0), "mode": (0x12, 1), "get": (0x13, 1),
            "set": (0x14, 5), "save": (0x15, 0), "map": (0x16, 0), "calibrate": (0x17, 0)}
COMMAND_NAMES = {t: n for n, (t, _) in COMMANDS.items()}
ERRORS = {1: "crc", 2: "length", 3: "command", 4: "key", 5: "range", 6: "fixed",
          7: "unsupported"}
ERROR_TEXT = {
    "crc": "the frame was damaged on the way (bad CRC)",
    "length": "the frame's length is not the command's, or it stopped half-way",
    "command": "the robot knows no such command",
    "key": "the robot knows no such configuration key",
    "range": "the value is out of range (the configuration would be invalid)",
    "fixed": "this key takes effect only when the robot starts",
    "unsupported": "this robot cannot do that (no map storage)",
}
MODES = ("off", "random", "tm", "square")
OUTCOMES = ("hit", "far", "near", "outside", "timeout")
FLAG_STOPPED, FLAG_PENDING = 0x01, 0x02

# What an OM cell holds (firmware/include/slam/grid.h) and how every exported map shows
# it (hal_common/mapexport.h): one meaning for the C programs and these tools.
OM_COUNT, OM_EVIDENCE = 0, 1
EVIDENCE_ZERO = 128
MAP_OCCUPIED, MAP_FREE, MAP_UNKNOWN = 0, 254, 205
MAP_YAML = ("image: %s.pgm\nmode: trinary\nresolution: %s\norigin: [%s, %s, 0.0]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n")


def um_text(um):
    """Whole micrometres as metres with six decimals, as the C programs print them."""
    return "%s%d.%06d" % ("-" if um < 0 else "", abs(um) // 1000000, abs(um) % 1000000)


def trinary(mode, om, tm=None):
    """The exported image of OM (numpy arrays, row 0 at the bottom, as the grid stores
    them): MAP_OCCUPIED, MAP_FREE or MAP_UNKNOWN a cell, first row the grid's last."""
    import numpy as np
    om = np.asarray(om)
    out = np.full(om.shape, MAP_UNKNOWN, np.uint8)
    if mode == OM_EVIDENCE:
        out[om < EVIDENCE_ZERO] = MAP_FREE
        out[om > EVIDENCE_ZERO] = MAP_OCCUPIED
    else:
        if tm is not None:
            out[np.asarray(tm) != 0] = MAP_FREE
        out[om != 0] = MAP_OCCUPIED
    return out[::-1]


def counts_image(cells, top):
    """A count map as a grey image (255 for none, 0 for top and more), first row last."""
    import numpy as np
    top = max(int(top), 1)
    v = np.minimum(np.asarray(cells, np.uint32), top)
    return (255 - (v * 255 + top // 2) // top).astype(np.uint8)[::-1]

# The configuration keys GET and SET address: (id, name, type, live), as
# TELEM_CONFIG_KEYS in telemetry.h (a test compares the two).
KEYS = [
    (1, "wheel_diameter_left_um", "U32", 1), (2, "wheel_diameter_right_um", "U32", 1),
    (3, "wheel_base_um", "U32", 1), (4, "encoder_counts_per_rev", "U32", 1),
    (5, "cal_left", "I32", 1), (6, "cal_right", "I32", 1), (7, "cal_base", "I32", 1),
    (8, "start_x_um", "I32", 0), (9, "start_y_um", "I32", 0),
    (10, "start_heading_mdeg", "I32", 0), (11, "cell_um", "U32", 0),
    (12, "start_cell_a", "U16", 0), (13, "start_cell_b", "U16", 0), (14, "om_max", "U8", 0),
    (15, "tm_max", "U8", 0), (16, "om_mode", "U8", 0), (17, "om_hit", "U8", 0),
    (18, "om_miss", "U8", 0), (19, "confidence_radius_um", "U32", 1),
    (20, "range_min_um", "U32", 1), (21, "sound_speed_mm_per_s", "U32", 1),
    (22, "mount_x_um", "I32", 1), (23, "mount_y_um", "I32", 1),
    (24, "mount_yaw_mdeg", "I32", 1), (25, "sweep_first_mdeg", "I32", 0),
    (26, "sweep_last_mdeg", "I32", 0), (27, "sweep_stops", "U8", 0),
    (28, "settle_ticks", "U8", 0), (29, "echo_timeout_ticks", "U8", 0),
    (30, "servo_pulse_0deg_us", "U16", 0), (31, "servo_pulse_180deg_us", "U16", 0),
    (32, "post_threshold", "U8", 1), (33, "post_template_k", "U8", 1),
    (34, "post_insert", "U8", 1), (35, "top_speed_mm_s", "U16", 1),
    (36, "accel_mm_s2", "U16", 1), (37, "motion_kp_q8", "U16", 1),
    (38, "motion_ki_q8", "U16", 1), (39, "explore_mode", "U8", 1),
    (40, "cruise_mm_s", "U16", 1), (41, "turn_mm_s", "U16", 1), (42, "avoid_um", "U32", 1),
    (43, "clearance_um", "U32", 1), (44, "square_side_um", "U32", 1),
    (45, "square_laps", "U8", 1), (46, "explore_seed", "U32", 1),
    (47, "save_period_s", "U16", 1), (48, "localize", "U8", 0),
    (49, "ping_interval_ticks", "U8", 0), (50, "follow_um", "U32", 1),
    (51, "umbmark_runs", "U8", 1), (52, "umbmark_pause_s", "U16", 1),
]
KEY_IDS = {name: k for k, name, _, _ in KEYS}
KEY_BY_ID = {k: (name, typ, live) for k, name, typ, live in KEYS}
Q30_KEYS = ("cal_left", "cal_right", "cal_base")  # decimal factors, sent as raw Q1.30
TYPE_RANGE = {"U8": (0, 255), "U16": (0, 65535), "U32": (0, 2**32 - 1),
              "I32": (-2**31, 2**31 - 1)}

BAM = 2.0 * math.pi / 4294967296.0  # radians per binary angle unit
TICK_S = 0.01


def _crc_table():
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
        table.append(crc)
    return table


CRC_TABLE = _crc_table()


def crc16(data):
    """CRC-16/CCITT-FALSE, as the firmware computes it."""
    crc = 0xFFFF
    for b in data:
        crc = ((crc << 8) & 0xFFFF) ^ CRC_TABLE[((crc >> 8) ^ b) & 0xFF]
    return crc


def frame(ftype, payload=b""):
    """One frame: sync, type, length, payload, CRC (low byte first)."""
    body = bytes([ftype, len(payload)]) + bytes(payload)
    crc = crc16(body)
    return SYNC + body + bytes([crc & 0xFF, crc >> 8])


class Decoder:
    """Feeds bytes, yields (type, payload) of every frame whose CRC checks out; frames
    whose CRC fails are counted in `bad`, bytes outside any frame in `skipped`."""

    def __init__(self):
        self.buf = bytearray()
        self.bad = 0
        self.skipped = 0

    def feed(self, data):
        self.buf += data
        out = []
        while True:
            i = self.buf.find(SYNC)
            if i < 0:
                keep = 1 if self.buf[-1:] == SYNC[:1] else 0
                self.skipped += len(self.buf) - keep
                del self.buf[:len(self.buf) - keep]
                break
            self.skipped += i
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
                self.skipped += 1
                del self.buf[:1]
                continue
            out.append((body[0], body[2:]))
            del self.buf[:6 + n]
        return out


_STATUS_NAMES = ("ticks", "pings", "echoes", "timeouts", "om_hits", "overruns", "saves",
                 "drops", "commands", "refused")


def decode(ftype, p):
    """A frame as a dict; None when its length is not its type's (a malformed frame)."""
    n = len(p)
    if ftype == HELLO and n in (19, 39, 42):
        v, a, b, cell, ox, oy, om_max, tm_max = struct.unpack("<BHHIiiBB", p[:19])
        d = dict(type="hello", version=v, a=a, b=b, cell_um=cell, origin_x_um=ox,
                 origin_y_um=oy, om_max=om_max, tm_max=tm_max, om_mode=OM_COUNT)
        if n >= 39:
            rc, rmin, mx, my, myaw = struct.unpack("<IIiii", p[19:39])
            d.update(confidence_radius_um=rc, range_min_um=rmin, mount_x_um=mx, mount_y_um=my,
                     mount_yaw_mdeg=myaw)
        if n == 42:
            d.update(om_mode=p[39], om_hit=p[40], om_miss=p[41])
        return d
    if ftype == POSE and n == 16:
        t, x, y, h = struct.unpack("<IiiI", p)
        return dict(type="pose", ticks=t, x_um=x, y_um=y, heading=h)
    if ftype == READING and n == 26:
        t, stop, outcome, servo, rng, x, y, h = struct.unpack("<IBBiIiiI", p)
        return dict(type="reading", ticks=t, stop=stop, outcome=outcome, servo_mdeg=servo,
                    range_um=rng, x_um=x, y_um=y, heading=h)
    if ftype == MAP_ROW and n >= 5:
        which, row, first = struct.unpack("<BHH", p[:5])
        return dict(type="map_row", map=which, row=row, first=first, cells=bytes(p[5:]))
    if ftype == STATUS and n in (32, 42):
        d = dict(zip(_STATUS_NAMES, struct.unpack("<%dI" % (n // 4), p[:n // 4 * 4])))
        d["type"] = "status"
        if n == 42:
            d["explore_mode"], d["flags"] = p[40], p[41]
        return d
    if ftype == ACK and n == 1:
        return dict(type="ack", command=p[0])
    if ftype == ERROR and n == 3:
        return dict(type="error", command=p[0], code=p[1], key=p[2])
    if ftype == CONFIG and n == 5:
        key, raw = struct.unpack("<BI", p)
        return dict(type="config", key=key, raw=raw)
    if ftype in FRAME_NAMES:
        return None
    return dict(type="unknown", code=ftype, length=n)


def reading_status(outcome):
    """The status column of readings.csv for a READING frame's outcome."""
    return {0: "ok", 3: "ok", 1: "far", 2: "near"}.get(outcome, "timeout")


def wrap_rad(bam):
    """A binary angle in radians, in [-pi, pi]."""
    return math.remainder(bam * BAM, 2.0 * math.pi)


def key_value(key, raw):
    """A configuration value as text, from the raw 32 bits of a CONFIG frame."""
    name, typ, _ = KEY_BY_ID.get(key, ("key%d" % key, "U32", 1))
    v = raw - (1 << 32) if typ == "I32" and raw >= 1 << 31 else raw
    if name in Q30_KEYS:
        return name, "%.9f" % (v / float(1 << 30))
    if name == "explore_mode" and v < len(MODES):
        return name, "%d (%s)" % (v, MODES[v])
    return name, str(v)


def describe(fr):
    """One line for a frame, the same form for every type: name key=value..., units in
    the keys, headings in degrees."""
    t = fr["type"]
    if t == "hello":
        head = "hello version=%d a=%d b=%d cell_m=%.3f origin_x_m=%.6f origin_y_m=%.6f " \
               "om_max=%d tm_max=%d" % (fr["version"], fr["a"], fr["b"], fr["cell_um"] * 1e-6,
                                        fr["origin_x_um"] * 1e-6, fr["origin_y_um"] * 1e-6,
                                        fr["om_max"], fr["tm_max"])
        if "confidence_radius_um" in fr:
            head += " rc_m=%.3f range_min_m=%.3f mount_x_m=%.3f mount_y_m=%.3f " \
                    "mount_yaw_deg=%.3f" % (fr["confidence_radius_um"] * 1e-6,
                                            fr["range_min_um"] * 1e-6, fr["mount_x_um"] * 1e-6,
                                            fr["mount_y_um"] * 1e-6, fr["mount_yaw_mdeg"] / 1000.0)
        return head
    if t == "pose":
        return "pose t_s=%.2f x_m=%.6f y_m=%.6f heading_deg=%.3f" % (
            fr["ticks"] * TICK_S, fr["x_um"] * 1e-6, fr["y_um"] * 1e-6,
            math.degrees(wrap_rad(fr["heading"])))
    if t == "reading":
        out = OUTCOMES[fr["outcome"]] if fr["outcome"] < len(OUTCOMES) else str(fr["outcome"])
        rng = "-" if out == "timeout" else "%.6f" % (fr["range_um"] * 1e-6)
        return "reading t_s=%.2f stop=%d servo_deg=%.3f range_m=%s outcome=%s x_m=%.6f " \
               "y_m=%.6f heading_deg=%.3f" % (fr["ticks"] * TICK_S, fr["stop"],
                                              fr["servo_mdeg"] / 1000.0, rng, out,
                                              fr["x_um"] * 1e-6, fr["y_um"] * 1e-6,
                                              math.degrees(wrap_rad(fr["heading"])))
    if t == "map_row":
        return "map_row map=%s row=%d first=%d cells=%d" % (
            "OM" if fr["map"] == 0 else "TM" if fr["map"] == 1 else fr["map"], fr["row"],
            fr["first"], len(fr["cells"]))
    if t == "status":
        line = "status t_s=%.2f " % (fr["ticks"] * TICK_S) + " ".join(
            "%s=%d" % (k, fr[k]) for k in _STATUS_NAMES[1:] if k in fr)
        if "flags" in fr:
            mode = MODES[fr["explore_mode"]] if fr["explore_mode"] < len(MODES) else fr["explore_mode"]
            line += " mode=%s stopped=%d pending=%d" % (mode, bool(fr["flags"] & FLAG_STOPPED),
                                                        bool(fr["flags"] & FLAG_PENDING))
        return line
    if t == "ack":
        return "ack command=%s" % COMMAND_NAMES.get(fr["command"], fr["command"])
    if t == "error":
        line = "error command=%s code=%s" % (COMMAND_NAMES.get(fr["command"], "0x%02x" % fr["command"]),
                                             ERRORS.get(fr["code"], fr["code"]))
        if fr["key"]:
            line += " key=%s" % KEY_BY_ID.get(fr["key"], (fr["key"],))[0]
        return line
    if t == "config":
        return "config key=%s value=%s" % key_value(fr["key"], fr["raw"])
    return "unknown type=%d length=%d" % (fr["code"], fr["length"])


class CommandError(ValueError):
    """A command line that cannot be encoded; the message says why."""


def command(words):
    """The frame of a command given as words: start, stop, mode MODE, get KEY,
    set KEY VALUE, save, map, calibrate."""
    if not words or words[0] not in COMMANDS:
        raise CommandError("expected a command: %s" % ", ".join(COMMANDS))
    name = words[0]
    ctype, _ = COMMANDS[name]
    want = {"mode": 2, "get": 2, "set": 3}.get(name, 1)
    if len(words) != want:
        usage = {"mode": "mode off|random|tm|square", "get": "get KEY", "set": "set KEY VALUE"}
        raise CommandError("usage: %s" % usage.get(name, name))
    if name == "mode":
        if words[1] not in MODES:
            raise CommandError("mode: '%s' is not one of %s" % (words[1], ", ".join(MODES)))
        return frame(ctype, bytes([MODES.index(words[1])]))
    if name in ("get", "set"):
        key = KEY_IDS.get(words[1])
        if key is None:
            raise CommandError("unknown key '%s'; the keys: %s" % (words[1], " ".join(KEY_IDS)))
        if name == "get":
            return frame(ctype, bytes([key]))
        typ = KEY_BY_ID[key][1]
        try:
            if words[1] in Q30_KEYS:
                v = round(float(words[2]) * (1 << 30))
            else:
                v = int(words[2], 0)
        except ValueError:
            raise CommandError("set %s: '%s' is not a %s" % (
                words[1], words[2], "decimal factor" if words[1] in Q30_KEYS else "whole number"))
        lo, hi = TYPE_RANGE[typ]
        if not lo <= v <= hi:
            raise CommandError("set %s: %d does not fit its field (%d .. %d)" % (words[1], v, lo, hi))
        return frame(ctype, struct.pack("<BI", key, v & 0xFFFFFFFF))
    return frame(ctype)
