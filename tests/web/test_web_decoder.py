#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The page's decoder (tools/web/protocol.js, in headless Chromium) agrees with the Python
one (tools/slamtools/link.py, which tools/telemetry.py dump runs) frame for frame on every
recorded stream the tests have: the telemetry fuzz corpus, host_sim runs (the paper's
hit counts, commands answered and refused), and those streams damaged (bytes flipped, cut,
dropped, doubled, noise): the same frames, the same counts of bad frames and skipped
bytes, the same bytes left over, and never an exception; fed whole, a byte at a time and
in random pieces. The page's dump lines, through slamlink.describe(), are dump's own."""
import json
import os
import random
import subprocess
import sys

import webtest
from webtest import check, fail

if len(sys.argv) < 3:
    sys.exit("usage: %s HOST_SIM SOURCE_DIR" % sys.argv[0])
HOST_SIM, SRC = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SRC, "tools"))
from slamtools import link as slamlink  # noqa: E402

sys.path.insert(0, os.path.join(SRC, "tests", "sim"))
from simtest import Sim  # noqa: E402

sim = Sim()


def python_decode(data, chunks):
    """What slamlink does with the stream: frames (None for a malformed one) and counts."""
    dec = slamlink.Decoder()
    frames = []
    i = 0
    for n in chunks:
        for ftype, payload in dec.feed(data[i:i + n]):
            fr = slamlink.decode(ftype, payload)
            frames.append({"malformed": ftype, "length": len(payload)} if fr is None else
                          dict(fr, cells=list(fr["cells"])) if fr["type"] == "map_row" else fr)
        i += n
    return {"frames": frames, "bad": dec.bad, "skipped": dec.skipped, "left": len(dec.buf)}


JS_DECODE = webtest.JS_BYTES + """
const P = window.slamview.protocol;
const data = bytesOf(arguments[0]);
const chunks = arguments[1];
const dec = new P.Decoder();
const frames = [];
const stream = new P.Stream(() => {});
let i = 0;
for (const n of chunks) {
  const piece = data.subarray(i, i + n);
  for (const f of dec.feed(piece)) {
    const fr = P.decode(f.type, f.payload);
    if (fr === null) {
      frames.push({malformed: f.type, length: f.payload.length});
    } else {
      if (fr.type === "map_row") { fr.cells = Array.from(fr.cells); }
      frames.push(fr);
    }
  }
  stream.feed(piece);
  i += n;
}
return JSON.stringify({frames: frames, bad: dec.bad, skipped: dec.skipped, left: dec.pending,
  stream: {frames: stream.frames, bad: stream.bad}});
"""


def chunkings(size, rng):
    """The stream whole, a byte at a time (when small), and in random pieces."""
    out = [("whole", [max(size, 1)])]
    if size <= 40000:
        out.append(("bytewise", [1] * size))
    pieces = []
    while sum(pieces) < size:
        pieces.append(rng.choice((1, 2, 3, 5, 7, 64, 255, 261, 1000, 4096)))
    out.append(("pieces", pieces))
    return out


def damaged(good, rng):
    """A recorded stream damaged as a cable, a wrong baud rate or a cut log damages it."""
    hello_end = 6 + good[3]
    out = []
    flips = bytearray(good)
    for _ in range(200):
        k = rng.randrange(len(flips))
        flips[k] ^= 1 << rng.randrange(8)
    out.append(("bits flipped", bytes(flips)))
    drops = bytearray(good)
    for _ in range(100):
        del drops[rng.randrange(len(drops))]
    out.append(("bytes dropped", bytes(drops)))
    doubled = bytearray(good)
    for _ in range(100):
        k = rng.randrange(len(doubled))
        doubled[k:k] = doubled[k:k + 1]
    out.append(("bytes doubled", bytes(doubled)))
    out.append(("cut in a frame", good[:len(good) // 2 + 3]))
    out.append(("a last A5", good[:20000] + b"\xa5"))
    out.append(("wrong lengths", good[:hello_end] + slamlink.frame(slamlink.POSE, b"\x01\x02\x03")
                + slamlink.frame(slamlink.STATUS, bytes(33)) + slamlink.frame(slamlink.HELLO, bytes(20))
                + good[hello_end:30000]))
    out.append(("a row far outside", good[:hello_end] + slamlink.frame(
        slamlink.MAP_ROW, bytes([0, 0x60, 0xEA, 0, 0]) + b"\x05" * 10) + good[hello_end:20000]))
    out.append(("noise", bytes(rng.randrange(256) for _ in range(20000)) + b"\xa5\x5a\x02\x10"
                + bytes(20)))
    out.append(("syncs only", b"\xa5\x5a" * 3000))
    out.append(("empty", b""))
    slices = bytearray()
    for _ in range(60):  # pieces of the stream spliced at random, as a flaky link splices them
        k = rng.randrange(len(good))
        slices += good[k:k + rng.randrange(1, 400)]
    out.append(("spliced", bytes(slices)))
    return out


# The streams: the fuzz corpus, then host_sim runs, then those damaged.
streams = []
corpus = os.path.join(SRC, "tests", "fuzz", "corpus", "telemetry")
for name in sorted(os.listdir(corpus)):
    with open(os.path.join(corpus, name), "rb") as f:
        streams.append(("corpus " + name, f.read()))
cmds = sim.out("run.cmds")
with open(cmds, "w") as f:
    f.write("2 stop\n3 get cruise_mm_s\n4 set cruise_mm_s 120\n5 set cell_um 100000\n"
            "6 set cruise_mm_s 400\n7 hex a55a5e00ffff\n8 start\n9 mode tm\n10 map\n"
            "11 set cal_left 0.9901\n12 get cal_left\n")
runs = [("default room 40 s", ["--duration", 40, "--seed", 3]),
        ("commands", ["--duration", 30, "--seed", 4, "--commands", cmds]),
        ("paper's hit counts", ["--duration", 30, "--paper", "--room", sim.room("obstacles.room")])]
for name, args in runs:
    log = sim.out(name.replace(" ", "_").replace("'", "") + ".bin")
    sim.run("--out", sim.out("run"), "--telemetry", log, *args)
    with open(log, "rb") as f:
        streams.append(("host_sim " + name, f.read()))
rng = random.Random(33)
streams += [("default room, " + what, data)
            for what, data in damaged(streams[len(streams) - len(runs)][1], rng)]

drv = webtest.browser()
try:
    webtest.load_page(drv, SRC)
    kinds = set()
    for name, data in streams:
        for how, chunks in chunkings(len(data), rng):
            if not data:
                chunks = [0]
            want = python_decode(data, chunks)
            got = json.loads(drv.execute_script(JS_DECODE, webtest.to_js(data), chunks))
            stream = got.pop("stream")
            if got != want:
                for k, (a, b) in enumerate(zip(got["frames"], want["frames"])):
                    if a != b:
                        fail("%s, %s: frame %d differs\n  page:   %s\n  python: %s"
                             % (name, how, k, a, b))
                fail("%s, %s: the page gives %s, Python %s" % (
                    name, how, {k: v for k, v in got.items() if k != "frames"} | {"frames": len(got["frames"])},
                    {k: v for k, v in want.items() if k != "frames"} | {"frames": len(want["frames"])}))
            malformed = sum(1 for f in want["frames"] if "malformed" in f)
            if stream != {"frames": len(want["frames"]) - malformed, "bad": want["bad"] + malformed}:
                fail("%s, %s: the page's Stream counts %s, Python %d frames, %d bad"
                     % (name, how, stream, len(want["frames"]) - malformed, want["bad"] + malformed))
            kinds.update(f.get("type", "malformed") for f in want["frames"])
        print("ok: %s (%d bytes): the same %d frames, %d bad CRC, %d malformed, %d bytes skipped, "
              "%d left" % (name, len(data), len(want["frames"]), want["bad"], malformed,
                           want["skipped"], want["left"]))
    check(kinds >= {"hello", "pose", "reading", "map_row", "status", "ack", "error", "config",
                    "unknown", "malformed"},
          "the streams hold every kind of frame, malformed ones too: %s" % sorted(kinds))

    # telemetry.py dump itself, against the page's frames described by slamlink.
    tool = os.path.join(SRC, "tools", "telemetry.py")
    for name, data in streams:
        if name.startswith("host_sim") or "flipped" in name:
            path = sim.out("dump.bin")
            with open(path, "wb") as f:
                f.write(data)
            p = subprocess.run(["/usr/bin/python3", tool, "dump", path], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
            got = json.loads(drv.execute_script(JS_DECODE, webtest.to_js(data), [len(data)]))
            lines = [slamlink.describe(dict(f, cells=bytes(f["cells"])) if f.get("type") == "map_row" else f)
                     for f in got["frames"] if "malformed" not in f]
            bad = got["stream"]["bad"]
            said = ("%d bad frames skipped" % bad) in p.stderr if bad else "bad frames" not in p.stderr
            check(p.returncode == 0 and lines == p.stdout.splitlines() and said,
                  "%s: the page's %d frames are telemetry.py dump's lines, and its %d bad frames "
                  "dump's count" % (name, len(lines), bad))
    webtest.errors(drv)
finally:
    webtest.quit(drv)
sim.done()
