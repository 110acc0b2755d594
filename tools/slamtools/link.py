# SPDX-License-Identifier: MIT
"""The robot's link in Python: telemetry frames in, command frames out, as
firmware/include/slam/telemetry.h describes them (tools/telemetry.py is the program),
the one rule for numbers, and the configuration and mode tables read from the firmware."""
import ast
import binascii
import collections
import math
import os
import re
import struct

from .errors import FAILED, ToolError

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
OUTCOMES = ("hit", "far", "near", "outside", "timeout")
FLAG_STOPPED, FLAG_PENDING, FLAG_EXPLORED = 0x01, 0x02, 0x04

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


# ---- numbers in text ----------------------------------------------------------------------
# The one rule for numbers written as text, the same as the C readers' (hal/common/include/
# hal_common/number.h, where it is explained; tests/data/numbers.txt holds both to one table
# of cases): decimal only, the whole text, no blanks around it, no hexadecimal, no inf or nan,
# no digit separators. Python's own int() and float() take " 5", "1_000", "inf", and
# int(x, 0) "0x10": every tool reads numbers through these two instead.

_WHOLE = re.compile(r"[+-]?[0-9]+")
_REAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


class NumberError(ToolError, ValueError):
    """Text that is not a number by the rule, or a number out of range; the message says
    which, with the text shown escaped."""


def shown(text, limit=40):
    """Text for a message: at most `limit` characters, anything unprintable escaped."""
    out = "".join(c if c.isprintable() else "\\x%02x" % ord(c) if ord(c) < 256 else
                  "\\u%04x" % ord(c) for c in str(text)[:limit])
    return out + ("..." if len(str(text)) > limit else "")


def _range_check(v, text, lo, hi, what):
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise NumberError("%s: '%s' is out of range %s..%s" % (
            what, shown(text), "" if lo is None else lo, "" if hi is None else hi))
    return v


def parse_int(text, lo=None, hi=None, what="value"):
    """A whole decimal number within [lo, hi] (None: no limit); NumberError otherwise."""
    if not isinstance(text, str) or _WHOLE.fullmatch(text) is None:
        raise NumberError("%s: '%s' is not a whole decimal number" % (what, shown(text)))
    return _range_check(int(text), text, lo, hi, what)


def parse_real(text, lo=None, hi=None, what="value"):
    """A decimal number within [lo, hi] (None: any finite one) as a float; NumberError
    otherwise. One too large for a double is out of range; one too small reads as 0."""
    if not isinstance(text, str) or _REAL.fullmatch(text) is None:
        raise NumberError("%s: '%s' is not a decimal number" % (what, shown(text)))
    v = float(text)
    if not math.isfinite(v):
        raise NumberError("%s: '%s' is out of range (beyond a double)" % (what, shown(text)))
    return _range_check(v, text, lo, hi, what)


def arg_real(lo, hi):
    """parse_real() as an argparse type: a decimal number in [lo, hi]."""
    return _arg(parse_real, lo, hi)


def arg_int(lo, hi):
    """parse_int() as an argparse type: a whole decimal number in [lo, hi]."""
    return _arg(parse_int, lo, hi)


def _arg(parse, lo, hi):
    import argparse

    def typed(text):
        try:
            return parse(text, lo, hi, what="value")
        except NumberError as e:
            raise argparse.ArgumentTypeError(str(e).partition(": ")[2])
    return typed


# ---- the firmware's tables ------------------------------------------------------------
# The configuration fields and the exploration modes are read from the firmware's own
# tables (firmware/include/slam/config_fields.h, explore_modes.h) when this module is
# imported: the tools hold no copy of them. tests/test_config_tables.py holds this reading
# to what the compiled C does.

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HEADER_DIR = os.path.join(SOURCE_DIR, "firmware", "include", "slam")


class TableError(ToolError, RuntimeError):
    """A firmware table could not be read; the message names the file and what is wrong.
    The tree is broken, not the user's input: a failure (exit 1)."""

    def __init__(self, message):
        super().__init__(message, FAILED)


# One row of config_fields.h. type: U8, U16, U32, I32 or Q30 (an I32 holding a Q1.30
# factor, a decimal in text); default, lo, hi: integers (raw Q1.30 for Q30); rule: the
# name of the rule that compares the field with others (NONE: none); live: 1 when SET may
# change it while the robot runs; words: the valid range in words, as messages give it.
Field = collections.namedtuple("Field", "name type default lo hi rule id live words")

_C_TOKENS = re.compile(r'"(?:\\.|[^"\\\n])*"|/\*.*?\*/|//[^\n]*', re.S)
_CASTS = re.compile(r"\(\s*(?:const\s+)?"
                    r"(?:u?int(?:8|16|32|64)_t|q\d+_\d+_t|unsigned|int|size_t)\s*\)")
_SUFFIX = re.compile(r"\b(0[xX][0-9a-fA-F]+|\d+)[uUlL]+\b")
_C_LIMITS = {"UINT8_MAX": 255, "UINT16_MAX": 65535, "UINT32_MAX": 2**32 - 1,
             "INT32_MAX": 2**31 - 1, "INT32_MIN": -2**31}


def _header(name):
    """A header's text without comments (string literals kept)."""
    path = os.path.join(HEADER_DIR, name)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise TableError("cannot read %s (%s): the tools take the configuration fields and "
                         "the mode names from the firmware's headers, so they must run from "
                         "the source tree" % (path, e.strerror or e)) from None
    return _C_TOKENS.sub(lambda m: m.group(0) if m.group(0)[0] == '"' else " ", text)


def _rows(text, macro, where):
    """The argument lists of the X(...) rows of `#define MACRO(X)`, as lists of strings."""
    m = re.search(r"#\s*define\s+%s\(X\)((?:[^\n]*\\\n)*[^\n]*)" % macro, text)
    if m is None:
        raise TableError("%s: no #define %s(X)" % (where, macro))
    body = m.group(1).replace("\\\n", " ")
    rows, i = [], 0
    while True:
        i = body.find("X(", i)
        if i < 0:
            return rows
        if i > 0 and (body[i - 1].isalnum() or body[i - 1] == "_"):
            i += 2
            continue
        args, depth, cur, j = [], 0, "", i + 2
        while j < len(body):
            c = body[j]
            if c == '"':
                k = j + 1
                while body[k] != '"':
                    k += 2 if body[k] == "\\" else 1
                cur += body[j:k + 1]
                j = k + 1
                continue
            if c == "(":
                depth += 1
            elif c == ")" and depth == 0:
                break
            elif c == ")":
                depth -= 1
            elif c == "," and depth == 0:
                args.append(cur.strip())
                cur = ""
                j += 1
                continue
            cur += c
            j += 1
        else:
            raise TableError("%s: a row of %s is not closed: %s" % (where, macro, body[i:i + 60]))
        args.append(cur.strip())
        rows.append(args)
        i = j + 1


def _symbols(texts):
    """The object-like #defines and plain enum constants of the headers: name -> C text."""
    sym = {}
    for text in texts:
        defines = re.findall(r"^[ \t]*#[ \t]*define[ \t]+(\w+)[ \t]+([^\n\\]+)$", text, re.M)
        for name, value in defines:
            sym.setdefault(name, value.strip())
        for body in re.findall(r"\benum\b[^{;]*\{([^}]*)\}", text):
            if "(" in body:
                continue  # generated from a table: those constants come from the table
            prev = None
            for item in filter(None, (x.strip() for x in body.split(","))):
                name, _, value = item.partition("=")
                name = name.strip()
                value = value.strip() or ("0" if prev is None else "(%s) + 1" % prev)
                sym.setdefault(name, value)
                prev = name
    return sym


class _Eval:
    """Integer C expressions over a table of symbols, as the C compiler computes them."""

    def __init__(self, symbols, values):
        self.symbols = symbols
        self.values = dict(_C_LIMITS, **values)
        self.busy = set()

    def __call__(self, text, where):
        expr = _SUFFIX.sub(r"\1", _CASTS.sub(" ", text)).strip()
        try:
            return self.node(ast.parse(expr, mode="eval").body, where)
        except SyntaxError:
            raise TableError("%s: '%s' is not an expression the tools can evaluate"
                             % (where, text)) from None

    def node(self, n, where):
        if isinstance(n, ast.Constant) and type(n.value) is int:
            return n.value
        if isinstance(n, ast.Name):
            return self.name(n.id, where)
        if isinstance(n, ast.UnaryOp) and isinstance(n.op, (ast.USub, ast.UAdd)):
            v = self.node(n.operand, where)
            return -v if isinstance(n.op, ast.USub) else v
        if isinstance(n, ast.BinOp):
            a, b = self.node(n.left, where), self.node(n.right, where)
            ops = {ast.Add: lambda: a + b, ast.Sub: lambda: a - b, ast.Mult: lambda: a * b,
                   ast.Div: lambda: abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1),
                   ast.LShift: lambda: a << b, ast.RShift: lambda: a >> b}
            if type(n.op) in ops:
                return ops[type(n.op)]()
        raise TableError("%s: '%s' is not an expression the tools can evaluate"
                         % (where, ast.unparse(n)))

    def name(self, name, where):
        if name in self.values:
            return self.values[name]
        if name not in self.symbols or name in self.busy:
            raise TableError("%s: %s is not a constant of the firmware's headers" % (where, name))
        self.busy.add(name)
        self.values[name] = self(self.symbols[name], "%s (%s)" % (where, name))
        self.busy.discard(name)
        return self.values[name]


def _c_string(text, where):
    """The value of adjacent C string literals."""
    parts = re.findall(r'"((?:\\.|[^"\\])*)"', text)
    if not parts or re.sub(r'"(?:\\.|[^"\\])*"', "", text).strip():
        raise TableError("%s: expected a string, got %s" % (where, text))
    return "".join(re.sub(r"\\(.)", r"\1", p) for p in parts)


def explore_modes():
    """The rows of explore_modes.h as (value, name, summary), by value; they must number
    0, 1, 2... as the MODE command's byte and host_sim's names do."""
    where = "firmware/include/slam/explore_modes.h"
    rows = []
    for args in _rows(_header("explore_modes.h"), "SLAM_EXPLORE_MODES", where):
        if len(args) < 4:
            raise TableError("%s: a row has %d columns, not X(ENUM, value, name, summary)"
                             % (where, len(args)))
        rows.append((int(args[1], 0), args[2], _c_string(args[3], where), args[0]))
    rows.sort()
    if [r[0] for r in rows] != list(range(len(rows))):
        raise TableError("%s: the modes must be numbered 0, 1, 2... (%s)"
                         % (where, [r[0] for r in rows]))
    return rows


def config_fields(grid=None):
    """The rows of config_fields.h as Field tuples, in the order of slam_config_t. A range
    or default that depends on the grid (start_cell_a...) is computed for `grid`, (A, B) as
    the robot was built with, or else for grid.h's default."""
    where = "firmware/include/slam/config_fields.h"
    text = _header("config_fields.h")
    symbols = _symbols([text, _header("config.h"), _header("grid.h"), _header("fixed.h")])
    modes = explore_modes()
    values = {row[3]: row[0] for row in modes}
    values["EXPLORE_MODES"] = len(modes)
    if grid is not None:
        values["SLAM_GRID_A"], values["SLAM_GRID_B"] = grid
    ev = _Eval(symbols, values)
    fields = []
    for args in _rows(text, "SLAM_CONFIG_FIELDS", where):
        if len(args) < 9:
            raise TableError("%s: a row has %d columns, not X(name, type, default, lo, hi, "
                             "rule, id, live, words): %s" % (where, len(args), args))
        name, typ, dflt, lo, hi, rule, key, live, words = args[:9]
        at = "%s: %s" % (where, name)
        if typ not in ("U8", "U16", "U32", "I32", "Q30") or live not in ("LIVE", "FIXED"):
            raise TableError("%s: type %s, live %s" % (at, typ, live))
        if words == "SLAM_CONFIG_WORDS_MODES":
            words = "%d..%d (%s)" % (modes[0][0], modes[-1][0], ", ".join(m[1] for m in modes))
        else:
            words = _c_string(words, at)
        fields.append(Field(name, typ, ev(dflt, at), ev(lo, at), ev(hi, at), rule,
                            ev(key, at), int(live == "LIVE"), words))
    ids = [f.id for f in fields]
    if len(set(ids)) != len(ids) or len({f.name for f in fields}) != len(fields):
        raise TableError("%s: two rows share an id or a name" % where)
    return fields


def grid_side_max():
    """The most cells a grid has along a side: the bound grid.h's #error states (it
    refuses SLAM_GRID_A or SLAM_GRID_B above it), and the most a tool believes a HELLO or
    a map record. Anything larger is a forgery or noise, and would cost gigabytes."""
    where = "firmware/include/slam/grid.h"
    m = re.search(r"#\s*if\s+SLAM_GRID_A\s*<\s*(\d+)\s*\|\|\s*SLAM_GRID_B\s*<\s*\d+\s*\|\|"
                  r"\s*SLAM_GRID_A\s*>\s*(\d+)", _header("grid.h"))
    if m is None:
        raise TableError("%s: no '#if SLAM_GRID_A < N || ... > M' to take the grid's limits from"
                         % where)
    return int(m.group(1)), int(m.group(2))


FIELDS = config_fields()
MODES = tuple(m[1] for m in explore_modes())
GRID_SIDE_MIN, GRID_SIDE_MAX = grid_side_max()

# The configuration keys GET and SET address: (id, name, type as stored, live), by id.
KEYS = sorted((f.id, f.name, "I32" if f.type == "Q30" else f.type, f.live) for f in FIELDS)
KEY_IDS = {name: k for k, name, _, _ in KEYS}
KEY_BY_ID = {k: (name, typ, live) for k, name, typ, live in KEYS}
Q30_KEYS = tuple(f.name for f in FIELDS if f.type == "Q30")  # decimal factors, sent as raw Q1.30
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
    """CRC-16/CCITT-FALSE, as the firmware computes it: the polynomial 0x1021 from 0xFFFF,
    which is what binascii.crc_hqx() computes in C (CRC_TABLE is the same in Python, for
    the tests that hold the two together)."""
    return binascii.crc_hqx(data, 0xFFFF)


def crc16_table(data):
    """crc16() a byte at a time through CRC_TABLE, as the firmware's byte table does."""
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
    whose CRC fails are counted in `bad`, bytes outside any frame in `skipped`.

    Its work is bounded by what it is fed, whatever the bytes: each sync it tries costs
    one CRC over at most 257 bytes, done in C (binascii), and a position is never looked
    at twice (`pos` walks forward; consumed bytes are dropped once per feed). `steps`
    counts the syncs tried, for the tests that bound the work. (Adversarial bytes, a sync
    whose length byte is 255 at every other position, once cost a Python loop of 257
    bytes per sync: about 100 KB/s.)"""

    def __init__(self):
        self.buf = bytearray()
        self.bad = 0
        self.skipped = 0
        self.steps = 0

    def feed(self, data):
        buf = self.buf
        buf += data
        out = []
        pos = 0
        end = len(buf)
        while True:
            i = buf.find(SYNC, pos)
            if i < 0:
                # A last A5 not yet looked at may be the first half of a sync; one that
                # ended the frame just taken is not.
                keep = 1 if end > pos and buf[end - 1] == SYNC[0] else 0
                self.skipped += end - keep - pos
                pos = end - keep
                break
            self.skipped += i - pos
            pos = i
            if end - pos < 6:
                break
            n = buf[pos + 3]
            if end - pos < 6 + n:
                break
            self.steps += 1
            body = bytes(buf[pos + 2:pos + 4 + n])
            crc = buf[pos + 4 + n] | buf[pos + 5 + n] << 8
            if crc != crc16(body):
                self.bad += 1
                self.skipped += 1
                pos += 1
                continue
            out.append((body[0], body[2:]))
            pos += 6 + n
        del buf[:pos]
        return out


_STATUS_NAMES = ("ticks", "pings", "echoes", "timeouts", "om_hits", "overruns", "saves",
                 "drops", "commands", "refused")


def decode(ftype, p):
    """A frame as a dict; None when its length is not its type's, or a field a tool would
    trust holds what no robot sends (a malformed frame): a HELLO's grid must be
    GRID_SIDE_MIN..GRID_SIDE_MAX cells a side (65535 x 65535 would be 8 GiB of maps), a
    map row must lie within such a grid."""
    n = len(p)
    if ftype == HELLO and n in (19, 39, 42):
        v, a, b, cell, ox, oy, om_max, tm_max = struct.unpack("<BHHIiiBB", p[:19])
        if not (GRID_SIDE_MIN <= a <= GRID_SIDE_MAX and GRID_SIDE_MIN <= b <= GRID_SIDE_MAX):
            return None
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
        if row >= GRID_SIDE_MAX or first + n - 5 > GRID_SIDE_MAX:
            return None
        return dict(type="map_row", map=which, row=row, first=first, cells=bytes(p[5:]))
    if ftype == STATUS and n in (32, 42, 46):
        words = min(n // 4, 10)
        d = dict(zip(_STATUS_NAMES, struct.unpack("<%dI" % words, p[:words * 4])))
        d["type"] = "status"
        if n >= 42:
            d["explore_mode"], d["flags"] = p[40], p[41]
        # Points outside the grid (the home does not fit), sent once there are any.
        d["outside"] = struct.unpack("<I", p[42:46])[0] if n == 46 else 0
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
            line += " mode=%s stopped=%d pending=%d explored=%d" % (
                mode, bool(fr["flags"] & FLAG_STOPPED), bool(fr["flags"] & FLAG_PENDING),
                bool(fr["flags"] & FLAG_EXPLORED))
        if fr.get("outside"):
            line += " outside=%d" % fr["outside"]
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


class CommandError(ToolError, ValueError):
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
        usage = {"mode": "mode " + "|".join(MODES), "get": "get KEY", "set": "set KEY VALUE"}
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
        lo, hi = TYPE_RANGE[typ]
        try:
            if words[1] in Q30_KEYS:
                # As the C text configuration takes a factor: strictly between -2 and 2.
                f = parse_real(words[2], what="set %s" % words[1])
                if not -2.0 < f < 2.0:
                    raise NumberError("set %s: '%s' must lie between -2 and 2"
                                      % (words[1], shown(words[2])))
                v = round(f * (1 << 30))
            else:
                v = parse_int(words[2], what="set %s" % words[1])
        except NumberError as e:
            raise CommandError(str(e)) from None
        if not lo <= v <= hi:
            raise CommandError("set %s: %d does not fit its field (%d .. %d)" % (words[1], v, lo, hi))
        return frame(ctype, struct.pack("<BI", key, v & 0xFFFFFFFF))
    return frame(ctype)
