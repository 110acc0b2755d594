#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Property-based tests of the Python side of the link (tools/slamtools/link.py), with Debian's
python3-hypothesis: the telemetry decoder (Decoder, decode, describe), the command
encoder (command) and the rule for numbers (parse_int, parse_real).

usage: tests/fuzz/fuzz_slamlink.py [--examples N] [--seed S] [PROPERTY...]

make fuzz runs every property with 100 000 generated cases (tools/fuzz.py); make test a
few hundred each, always the same (a fixed seed), as the CTest test fuzz_slamlink_quick.
Prints one line a property: its name and the cases it ran. Exit status: 0 every property
held, 1 one failed (hypothesis prints the smallest input it found), 2 bad options or no
hypothesis (tools/install-deps.sh fuzz installs it).
"""
import argparse
import os
import re
import struct
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from slamtools import link as slamlink  # noqa: E402

try:
    from hypothesis import HealthCheck, example, given, settings, strategies as st
except ImportError:
    print("fuzz_slamlink: needs python3-hypothesis (tools/install-deps.sh fuzz)", file=sys.stderr)
    sys.exit(2)

FRAME_TYPES = st.integers(0, 255)
PAYLOADS = st.binary(max_size=255)
FRAMES = st.lists(st.tuples(FRAME_TYPES, PAYLOADS), max_size=12)
# Bytes that make resynchronisation work: syncs, lengths, pieces of real frames.
NOISE = st.lists(st.one_of(st.binary(max_size=40), st.just(slamlink.SYNC),
                           st.sampled_from([b"\xa5", b"\x5a", b"\xff", b"\x00"]),
                           FRAMES.map(lambda fs: b"".join(slamlink.frame(t, p) for t, p in fs))),
                 max_size=30).map(b"".join)


def chunked(data, cuts):
    """data cut at the given offsets (sorted, within it)."""
    points = sorted({c % (len(data) + 1) for c in cuts})
    out, last = [], 0
    for c in points + [len(data)]:
        out.append(data[last:c])
        last = c
    return out


def feed_all(chunks):
    dec = slamlink.Decoder()
    got = []
    for c in chunks:
        got += dec.feed(c)
    return dec, got


# ---- the decoder ----------------------------------------------------------------------------

@given(FRAMES, st.lists(st.integers(0, 10**6), max_size=20))
@example([(221, b"\xd0\xd0")], [])  # its CRC ends in A5: that byte was kept after the frame
def frames_round_trip(frames, cuts):
    """Frames as the firmware sends them come back exactly, however the bytes are cut."""
    data = b"".join(slamlink.frame(t, p) for t, p in frames)
    dec, got = feed_all(chunked(data, cuts))
    assert got == [(t, bytes(p)) for t, p in frames]
    assert dec.bad == 0 and dec.skipped == 0 and len(dec.buf) == 0


@given(NOISE, st.lists(st.integers(0, 10**6), max_size=20))
def noise_is_accounted_for(data, cuts):
    """Any bytes: every frame found was in them with its CRC, every byte is a frame's, a
    skipped one or still held, the cut does not matter, and the work is bounded."""
    whole, frames = feed_all([data])
    dec, got = feed_all(chunked(data, cuts))
    assert got == frames and dec.bad == whole.bad and dec.skipped == whole.skipped
    used = sum(6 + len(p) for _, p in frames)
    assert whole.skipped + used + len(whole.buf) == len(data)
    assert whole.steps <= len(data) // 2 + 1
    pos = 0
    for t, p in frames:  # in order, each whole in the input
        pos = data.index(slamlink.frame(t, p), pos) + 6 + len(p)


@given(FRAME_TYPES, PAYLOADS)
def decode_never_breaks(ftype, payload):
    """decode() of any frame is None or a dict that describe() puts in words; the sizes a
    tool would allocate by stay within a grid."""
    fr = slamlink.decode(ftype, payload)
    if fr is None:
        return
    assert isinstance(fr, dict)
    line = slamlink.describe(fr)
    assert isinstance(line, str) and line
    if fr["type"] == "hello":
        assert slamlink.GRID_SIDE_MIN <= fr["a"] <= slamlink.GRID_SIDE_MAX
        assert slamlink.GRID_SIDE_MIN <= fr["b"] <= slamlink.GRID_SIDE_MAX
    if fr["type"] == "map_row":
        assert fr["row"] < slamlink.GRID_SIDE_MAX
        assert fr["first"] + len(fr["cells"]) <= slamlink.GRID_SIDE_MAX


# ---- the command encoder --------------------------------------------------------------------

WORD = st.one_of(st.text(max_size=12), st.sampled_from(list(slamlink.COMMANDS)),
                 st.sampled_from(list(slamlink.KEY_IDS)), st.sampled_from(list(slamlink.MODES)),
                 st.integers(-2**40, 2**40).map(str),
                 st.floats(allow_nan=True, allow_infinity=True).map(repr))


@given(st.lists(WORD, max_size=5))
def commands_refuse_cleanly(words):
    """command() of any words is a frame of a known command, or a CommandError."""
    try:
        data = slamlink.command(words)
    except slamlink.CommandError as e:
        assert str(e)
        return
    dec, got = feed_all([data])
    assert len(got) == 1 and got[0][0] in slamlink.COMMAND_NAMES
    assert words[0] in slamlink.COMMANDS


KEYS = st.sampled_from(sorted(slamlink.KEY_IDS))


@given(KEYS, st.data())
def set_encodes_its_value(key, data):
    """set KEY VALUE: a value within its field's type goes out as the key's id and the value's
    32 bits; a factor as its Q1.30 integer."""
    kid = slamlink.KEY_IDS[key]
    typ = slamlink.KEY_BY_ID[kid][1]
    if key in slamlink.Q30_KEYS:
        v = data.draw(st.floats(-1.999, 1.999, allow_nan=False))
        text = "%.9f" % v
        raw = round(float(text) * (1 << 30))
    else:
        lo, hi = slamlink.TYPE_RANGE[typ]
        raw = data.draw(st.integers(lo, hi))
        text = str(raw)
    frame = slamlink.command(["set", key, text])
    _, got = feed_all([frame])
    assert got == [(0x14, struct.pack("<BI", kid, raw & 0xFFFFFFFF))]


# ---- the rule for numbers -----------------------------------------------------------------

WHOLE = re.compile(r"[+-]?[0-9]+")
REAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
NUMBERISH = st.one_of(st.text(alphabet="0123456789+-.eExX_ \tabcdfinINF\u0661", max_size=14),
                      st.text(max_size=8), st.integers().map(str),
                      st.floats().map(repr), st.floats().map(str))


@given(NUMBERISH)
def numbers_follow_the_rule(text):
    """parse_int and parse_real take exactly the decimal forms of hal_common/number.h."""
    try:
        v = slamlink.parse_int(text)
        assert WHOLE.fullmatch(text) and v == int(text)
    except slamlink.NumberError as e:
        assert not WHOLE.fullmatch(text) and "\n" not in str(e)
    try:
        v = slamlink.parse_real(text)
        assert REAL.fullmatch(text) and v == float(text)
    except slamlink.NumberError:
        assert not REAL.fullmatch(text) or float(text) in (float("inf"), float("-inf"))


PROPERTIES = {f.__name__: f for f in (frames_round_trip, noise_is_accounted_for,
                                      decode_never_breaks, commands_refuse_cleanly,
                                      set_encodes_its_value, numbers_follow_the_rule)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--examples", type=int, default=200, help="cases a property (default 200)")
    ap.add_argument("--seed", type=int, default=None,
                    help="a fixed seed (default: fresh each run; make test gives one)")
    ap.add_argument("properties", nargs="*", metavar="PROPERTY",
                    help="some of: " + " ".join(PROPERTIES) + " (default: all)")
    args = ap.parse_args()
    if args.examples <= 0:
        ap.error("--examples needs a positive number")
    for name in args.properties:
        if name not in PROPERTIES:
            ap.error("unknown property '%s'" % name)
    failed = 0
    for name in args.properties or list(PROPERTIES):
        prop = PROPERTIES[name]
        runs = [0]
        inner = prop.hypothesis.inner_test

        def counted(*a, _inner=inner, **k):
            runs[0] += 1
            return _inner(*a, **k)

        prop.hypothesis.inner_test = counted
        test = settings(max_examples=args.examples, deadline=None, database=None,
                        derandomize=args.seed is not None,
                        suppress_health_check=list(HealthCheck))(prop)
        if args.seed is not None:
            from hypothesis import seed
            test = seed(args.seed)(test)
        t0 = time.monotonic()
        try:
            test()
            outcome = "held"
        except Exception as e:  # hypothesis re-raises the falsifying case's error
            outcome = "FAILED: %r" % e
            failed += 1
        print("| %s | %d | %.0f | %s |" % (name, runs[0], time.monotonic() - t0, outcome),
              flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
