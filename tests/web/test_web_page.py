#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The page in headless Chromium, from file://, as a builder uses it without a robot: it
opens a host_sim run's telemetry, plays it (paced at 1x, then at 100x to its end, and
again with "To the end"), and then the map it drew is the run's om.pgm cell for cell,
the files its Download button saves are om.pgm, om.yaml and tm.pgm byte for byte, its
counts are telemetry.py's, and it tells the run, the robot's state and its answers in words.

  test_web_page.py HOST_SIM SOURCE_DIR [--screenshot FILE | --screenshot-source]

With --screenshot the page plays a ten-minute run of the obstacles room instead and its
picture is written to FILE (the README's, tools/web/screenshot.png), with what it shows
in a tEXt chunk: "source", a SHA-256 of the run's telemetry, the window's size and the
page's files. --screenshot-source prints that digest alone, without Chromium: another
machine's Chromium can draw the same page in other bytes, so make docs-check compares this."""
import hashlib
import json
import os
import subprocess
import sys
import time

import webtest
from webtest import check, fail

if len(sys.argv) < 3:
    sys.exit(__doc__)
sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
sys.path.insert(0, os.path.join(sys.argv[2], "tests", "sim"))
from slamtools import link as slamlink  # noqa: E402
from slamtools import pngtext  # noqa: E402
from simtest import Sim  # noqa: E402

sim = Sim()
APP = "window.slamview.app"


def open_recording(drv, path, speed):
    """Chooses the file in the page's file input at a playback speed; it starts playing."""
    from selenium.webdriver.support.ui import Select
    Select(drv.find_element("id", "speed")).select_by_value(str(speed))
    drv.execute_script("document.getElementById('file').value = '';")
    drv.find_element("id", "file").send_keys(path)
    webtest.wait(drv, "const l = %s.link; return l && l.name === %s && l.playing"
                 % (APP, json.dumps(os.path.basename(path))), "the recording to start playing")


def played(drv):
    webtest.wait(drv, "return %s.link.done && document.getElementById('play').disabled" % APP,
                 "the recording to play to its end")


def read(path):
    with open(path, "rb") as f:
        return f.read()


SHOT_WINDOW = (1400, 1180)
PAGE_FILES = (".html", ".js", ".css")


def shot_run():
    """The screenshot's run, its telemetry's path and the digest of what the picture shows."""
    log = sim.out("shot.tel")
    sim.run("--duration", 600, "--room", sim.room("obstacles.room"), "--seed", 2, "--out",
            sim.out("shot"), "--telemetry", log)
    h = hashlib.sha256(b"window %dx%d\n" % SHOT_WINDOW)
    h.update(read(log))
    web = os.path.join(sim.src, "tools", "web")
    for name in sorted(n for n in os.listdir(web) if n.endswith(PAGE_FILES)):
        h.update(b"\n" + name.encode() + b"\n")
        h.update(read(os.path.join(web, name)))
    return log, h.hexdigest()


def screenshot(target):
    log, source = shot_run()
    drv = webtest.browser(*SHOT_WINDOW)
    try:
        webtest.load_page(drv, sim.src)
        open_recording(drv, log, 100)
        drv.execute_script("%s.link.toEnd()" % APP)
        played(drv)
        webtest.wait(drv, "return document.getElementById('figures').textContent.includes('10 min')",
                     "the words to catch up")
        drv.execute_script("window.scrollTo(0, 0)")
        drv.execute_async_script("requestAnimationFrame(() => requestAnimationFrame(arguments[0]))")
        drv.save_screenshot(target)
        webtest.errors(drv)
    finally:
        webtest.quit(drv)
    pngtext.add_text(target, "source", source)
    print("wrote %s" % target)


if "--screenshot-source" in sys.argv:
    print(shot_run()[1])
    sim.done()
    sys.exit(0)
if "--screenshot" in sys.argv:
    screenshot(os.path.abspath(sys.argv[sys.argv.index("--screenshot") + 1]))
    sim.done()
    sys.exit(0)

out, log = webtest.settled_run(sim)
downloads = sim.out("downloads")
os.makedirs(downloads)
# What Python makes of the same log: the frames, the last STATUS, the answers.
dec = slamlink.Decoder()
frames = [slamlink.decode(t, p) for t, p in dec.feed(read(log))]
good = [f for f in frames if f is not None]
status = [f for f in good if f["type"] == "status"][-1]

drv = webtest.browser(download_dir=downloads)
try:
    webtest.load_page(drv, sim.src)
    check(drv.execute_script("return document.getElementById('figures').textContent") == "No telemetry yet.",
          "the page opens from file:// and waits for telemetry")

    # At 1x the recording plays at its own pace: part of it, not all at once.
    open_recording(drv, log, 1)
    pos, fed, total, done = webtest.wait(
        drv, "const l = %s.link; return l.position >= 1.0 && [l.position, l.sent, l.bytes.length, l.done]"
        % APP, "a second of the recording to play")
    check(not done and 0 < fed < total, "at 1x, %.1f s into the %.0f s recording, %d of its %d bytes "
          "are in" % (pos, drv.execute_script("return %s.link.duration" % APP), fed, total))
    from selenium.webdriver.support.ui import Select
    Select(drv.find_element("id", "speed")).select_by_value("100")
    played(drv)

    # The drawn map: the OM layer, one pixel a cell, in the exported greys.
    drawn = bytes(drv.execute_script("return Array.from(%s.view.layers.om.greys())" % APP))
    om_pgm = read(os.path.join(out, "om.pgm"))
    head = b"P5\n256 256\n255\n"
    pixels = om_pgm[len(head):]
    occupied, free = pixels.count(bytes([slamlink.MAP_OCCUPIED])), pixels.count(bytes([slamlink.MAP_FREE]))
    check(om_pgm.startswith(head) and drawn == pixels and occupied > 20 and free > 500,
          "played to the end at 100x, the drawn OM is the run's om.pgm cell for cell (%d occupied, "
          "%d free)" % (occupied, free))

    # The Download button: the same files the other tools write.
    drv.find_element("id", "download").click()
    names = ("om.pgm", "om.yaml", "tm.pgm")
    end = time.monotonic() + webtest.TIMEOUT_S
    # Chromium may reserve a download's name before its bytes are all in: wait for each
    # file to reach the size of the run's, then compare the bytes.
    def whole(n):
        p = os.path.join(downloads, n)
        return os.path.exists(p) and os.path.getsize(p) == os.path.getsize(os.path.join(out, n))
    while not (all(whole(n) for n in names)
               and not any(f.endswith(".crdownload") for f in os.listdir(downloads))):
        if time.monotonic() > end:
            fail("the downloads did not come whole: %s" % {f: os.path.getsize(os.path.join(downloads, f))
                                                           for f in os.listdir(downloads)})
        time.sleep(0.1)
    for n in names:
        check(read(os.path.join(downloads, n)) == read(os.path.join(out, n)),
              "Download the map: %s is the run's %s byte for byte" % (n, n))

    # Its counts are telemetry.py's; the run, the robot and its answers in words.
    frames_js, bad_js = drv.execute_script("const s = %s.stream; return [s.frames, s.bad]" % APP)
    check(frames_js == len(good) and bad_js == dec.bad + frames.count(None),
          "the page counts %d frames and %d bad, as telemetry.py does" % (frames_js, bad_js))
    webtest.wait(drv, "return document.getElementById('figures').textContent.includes('1 min 2')",
                 "the words to show the run's end")
    text = {k: drv.execute_script("return document.getElementById(%s).textContent" % json.dumps(k))
            for k in ("figures", "robot-state", "link-counts", "answers")}
    pings = "{:,}".format(status["pings"])
    check(pings + " pings" in text["figures"] and "%d occupied cells" % occupied in text["figures"]
          and "m² seen free" in text["figures"] and "The robot has driven" in text["figures"],
          "the run in words: %s" % text["figures"])
    check(text["robot-state"].startswith("Mode: walls") and "Stopped" in text["robot-state"],
          "the robot's state: %s" % text["robot-state"])
    check("0 bad frames" in text["link-counts"], "the link's counts: %s" % text["link-counts"])
    check("stop: done" in text["answers"] and "confidence_radius_um = 20001" in text["answers"]
          and "map: done" in text["answers"], "the robot's answers in words: %s" % text["answers"])

    # "To the end" at once, after Clear, draws the same map.
    drv.find_element("id", "clear").click()
    open_recording(drv, log, 1)
    drv.find_element("id", "to-end").click()
    played(drv)
    drawn = bytes(drv.execute_script("return Array.from(%s.view.layers.om.greys())" % APP))
    check(drawn == pixels, "To the end: the same map at once")

    # A damaged recording: the page counts what it skipped, as telemetry.py does.
    damaged = sim.out("damaged.tel")
    data = bytearray(read(log))
    for k in range(1000, len(data), 5003):
        data[k] ^= 0x40
    with open(damaged, "wb") as f:
        f.write(data)
    drv.find_element("id", "clear").click()
    open_recording(drv, damaged, 100)
    played(drv)
    p = subprocess.run(["/usr/bin/python3", os.path.join(sim.src, "tools", "telemetry.py"), "dump",
                        damaged], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    bad_js = drv.execute_script("return %s.stream.bad" % APP)
    webtest.wait(drv, "return document.getElementById('link-counts').textContent.includes('%d bad')"
                 % bad_js, "the counts to show")
    check(bad_js > 10 and ("%d bad frames skipped" % bad_js) in p.stderr,
          "a damaged recording: the page shows %d bad frames, as telemetry.py dump counts them"
          % bad_js)
    webtest.errors(drv)
finally:
    webtest.quit(drv)
sim.done()
