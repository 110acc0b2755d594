#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The live path, end to end: host_sim --link makes the simulated robot's UART a
pseudo-terminal, tools/telemetry.py serve bridges it to a WebSocket and serves the page,
the page (headless Chromium, from the bridge's own HTTP address) connects by itself and
draws the robot as it drives; its Stop button stops the simulated robot: the robot
answers, STATUS says stopped, the pose the page shows no longer changes, nor does the true
pose host_sim logs. Ctrl-C (SIGTERM) ends the linked run with its outputs; the bridge
tells the page the link closed."""
import csv
import json
import os
import re
import select
import signal
import subprocess
import sys
import time

import webtest
from webtest import check, fail

sys.path.insert(0, os.path.join(sys.argv[2], "tools"))
sys.path.insert(0, os.path.join(sys.argv[2], "tests", "sim"))
from slamtools import link as slamlink  # noqa: E402
from simtest import Sim  # noqa: E402

sim = Sim()
STATE = "window.slamview.state"
procs = []


def start(cmd):
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    procs.append(p)
    return p


def line_matching(proc, pattern, what):
    """The first line of proc's stdout that matches, waiting for it."""
    end = time.monotonic() + webtest.TIMEOUT_S
    while time.monotonic() < end:
        if proc.poll() is not None:
            fail("%s ended (%d) before saying it: %s" % (what, proc.returncode, proc.stderr.read()))
        ready, _, _ = select.select([proc.stdout], [], [], 0.5)
        if ready:
            m = re.search(pattern, proc.stdout.readline())
            if m:
                return m
    fail("waited %d s for %s" % (webtest.TIMEOUT_S, what))


def ended(proc, what):
    try:
        return proc.wait(timeout=webtest.TIMEOUT_S)
    except subprocess.TimeoutExpired:
        fail("%s did not end" % what)


link = sim.out("robot.pty")
tee = sim.out("live.tel")
out = sim.out("live")
drv = None
try:
    # The robot, live at twice the real pace; the pose correction off, so that a robot that
    # stands keeps its pose estimate exactly.
    host = start([sim.bin, "--no-plot", "--quiet", "--link", link, "--realtime", "2",
                  "--duration", "3600", "--set", "localize=0", "--telemetry", tee, "--out", out])
    end = time.monotonic() + webtest.TIMEOUT_S
    while not os.path.islink(link):
        if host.poll() is not None or time.monotonic() > end:
            fail("host_sim --link made no %s: %s" % (link, host.stderr.read() if host.poll() is not None else ""))
        time.sleep(0.05)
    check(os.readlink(link).startswith("/dev/pts/"), "host_sim --link: %s -> %s" % (link, os.readlink(link)))

    record = sim.out("record.log")
    bridge = start(["/usr/bin/python3", os.path.join(sim.src, "tools", "telemetry.py"), "serve", link,
                    "--port", "0", "--record", record])
    url = line_matching(bridge, r"(http://127\.0\.0\.1:\d+/)", "the bridge's address").group(1)

    drv = webtest.browser()
    drv.get(url)
    webtest.wait(drv, "const s = %s; return s.geo && s.pose && s.status" % STATE,
                 "the page, served by the bridge, to connect and take the robot's frames")
    said = drv.execute_script("return document.getElementById('link-state').textContent")
    check("serving the robot on " + link in said, "the page connects by itself: '%s'" % said)
    first = drv.execute_script("return %s.pose" % STATE)
    webtest.wait(drv, "const p = %s.pose; return Math.hypot(p.x_um - %d, p.y_um - %d) > 20000"
                 % (STATE, first["x_um"], first["y_um"]), "the robot to drive")
    check(not drv.execute_script("return %s.status.flags & 1" % STATE), "the robot drives")

    drv.find_element("css selector", "button[data-cmd=stop]").click()
    webtest.wait(drv, "return %s.answers.some((a) => a.text === 'stop: done')" % STATE,
                 "the robot's answer to Stop")
    t_stop = webtest.wait(drv, "const s = %s.status; return (s.flags & 1) && s.ticks" % STATE,
                          "STATUS to say stopped")
    webtest.wait(drv, "return document.getElementById('robot-state').textContent.includes('Stopped')",
                 "the page to say the robot stopped")
    check(True, "Stop: the robot answers and the page says it is stopped (at %.1f s)" % (t_stop / 100))
    # Half a second for the brakes (500 mm/s² from 200 mm/s), then three seconds standing.
    webtest.wait(drv, "return %s.ticks >= %d" % (STATE, t_stop + 100), "a second to pass")
    p1 = drv.execute_script("return %s.pose" % STATE)
    webtest.wait(drv, "return %s.pose.ticks >= %d" % (STATE, p1["ticks"] + 300), "three seconds to pass")
    p2 = drv.execute_script("return %s.pose" % STATE)
    check((p1["x_um"], p1["y_um"], p1["heading"]) == (p2["x_um"], p2["y_um"], p2["heading"]),
          "the pose the page shows no longer changes (%.1f s to %.1f s)" % (p1["ticks"] / 100, p2["ticks"] / 100))

    # The other controls: Set, Get and the mode, with the robot's answers in words, and a
    # value that does not fit refused on the page.
    from selenium.webdriver.support.ui import Select

    def answered(text, what):
        webtest.wait(drv, "return document.getElementById('answers').textContent.includes(%s)"
                     % json.dumps(text), what)

    def set_key(key, value):
        Select(drv.find_element("id", "key")).select_by_value(key)
        field = drv.find_element("id", "value")
        field.clear()
        field.send_keys(value)
        drv.find_element("id", "set").click()

    set_key("cruise_mm_s", "150")
    answered("cruise_mm_s = 150", "the answer to Set")
    drv.find_element("id", "get").click()
    webtest.wait(drv, "return %s.answers.filter((a) => a.text === 'cruise_mm_s = 150').length === 2"
                 % STATE, "the answer to Get")
    webtest.wait(drv, "return document.getElementById('key-note').textContent.endsWith("
                 "'the robot said 150')", "the key's note to show the value in force")
    set_key("cell_um", "100000")
    answered("set cell_um refused: this key takes effect only when the robot starts",
             "the robot's refusal in words")
    sent = drv.execute_script("return window.slamview.app.sent.length")
    set_key("cruise_mm_s", "fast")
    answered("'fast' is not a whole number", "the page's own refusal")
    set_key("turn_mm_s", "0")
    answered("0 is out of its range, 1..5000", "a value out of the field's range refused")
    check(drv.execute_script("return window.slamview.app.sent.length") == sent,
          "Set and Get answered in words; values that do not fit are refused on the page, unsent")
    Select(drv.find_element("id", "mode")).select_by_value("tm")
    drv.find_element("id", "mode-send").click()
    answered("mode: done", "the answer to the mode")
    webtest.wait(drv, "return %s.status.explore_mode === %d" % (STATE, slamlink.MODES.index("tm")),
                 "STATUS to report mode tm")
    check(True, "Set mode tm: the robot answers and reports it")

    # Ctrl-C ends the linked run with its outputs; the link goes, and the bridge says so.
    host.send_signal(signal.SIGTERM)
    check(ended(host, "host_sim") == 0 and not os.path.lexists(link),
          "SIGTERM ends the linked run cleanly and removes %s" % os.path.basename(link))
    with open(os.path.join(out, "trajectory.csv")) as f:
        traj = [(round(float(r["t_s"]) * 100), float(r["true_x_m"]), float(r["true_y_m"]))
                for r in csv.DictReader(f)]
    still = [(x, y) for k, x, y in traj if k >= t_stop + 100]
    check(len(still) > 30 and max(abs(x - still[0][0]) + abs(y - still[0][1]) for x, y in still) < 1e-6,
          "the simulated robot stood from a second after the stop to the run's end (%d poses, "
          "trajectory.csv)" % len(still))
    frames = [f for f in (slamlink.decode(t, p) for t, p in slamlink.Decoder().feed(open(tee, "rb").read()))
              if f is not None]
    acks = [i for i, f in enumerate(frames) if f["type"] == "ack" and f["command"] == slamlink.COMMANDS["stop"][0]]
    later = [f for f in frames[acks[0]:] if f["type"] == "status"] if acks else []
    check(len(acks) == 1 and later and all(f["flags"] & slamlink.FLAG_STOPPED for f in later),
          "--telemetry holds what went out on the link: one ACK of STOP, every STATUS after it stopped")
    webtest.wait(drv, "return document.getElementById('link-state').textContent.includes('closed')",
                 "the bridge to tell the page the link closed")
    webtest.errors(drv)

    # A page that joins late gets the robot's map at once: the bridge's catch-up frames,
    # then the live bytes, draw what the whole stream so far draws.
    from slamtools import bridge as ws_bridge
    data = open(tee, "rb").read()
    cut = len(data) * 2 // 3 + 7  # in the middle of a frame
    catchup = ws_bridge.Catchup()
    for k in range(0, cut, 4096):
        catchup.feed(data[k:min(k + 4096, cut)])

    def maps(stream):
        grids, geo = {}, None
        for t, p in slamlink.Decoder().feed(stream):
            f = slamlink.decode(t, p)
            if f and f["type"] == "hello":
                geo = (f["a"], f["b"])
            elif f and f["type"] == "map_row":
                grids[(f["map"], f["row"], f["first"])] = f["cells"]
        return geo, grids

    whole = maps(data)
    joined = maps(catchup.frames() + data[cut:])
    check(joined == whole and len(whole[1]) > 100,
          "a page joining late: the bridge's catch-up and the live bytes after it give every map "
          "row the whole stream gives (%d segments)" % len(whole[1]))
    # --record: what the bridge read is what host_sim sent, in order (a terminal's full
    # buffer may have dropped some before the bridge came).
    recorded = [(t, bytes(p)) for t, p in slamlink.Decoder().feed(open(record, "rb").read())]
    sent = iter((t, bytes(p)) for t, p in slamlink.Decoder().feed(data))
    in_order = all(any(f == g for g in sent) for f in recorded)
    check(len(recorded) > 100 and in_order,
          "serve --record: its %d frames are frames host_sim sent, in their order" % len(recorded))
    bridge.send_signal(signal.SIGTERM)
    ended(bridge, "the bridge")
    err = bridge.stderr.read()
    check("connected" in err and "Traceback" not in err, "the bridge ends on SIGTERM: %s"
          % json.dumps(err.strip().splitlines()[-3:]))

    # A recording through the bridge: the page gets the whole file, and a command the
    # answer that a recording takes none.
    bridge = start(["/usr/bin/python3", os.path.join(sim.src, "tools", "telemetry.py"), "serve", tee,
                    "--port", "0"])
    url = line_matching(bridge, r"(http://127\.0\.0\.1:\d+/)", "the bridge's address").group(1)
    drv.get(url)
    webtest.wait(drv, "return document.getElementById('link-state').textContent.includes('the end of')",
                 "the bridge to send the whole recording")
    check(drv.execute_script("return window.slamview.app.stream.frames") == len(frames),
          "serve FILE: the page gets every frame of the recording (%d)" % len(frames))
    drv.find_element("css selector", "button[data-cmd=stop]").click()
    webtest.wait(drv, "return document.getElementById('link-state').textContent.includes("
                 "'a recording takes no commands')", "the bridge to refuse the command")
    check(True, "serve FILE: a command gets the answer that a recording takes none")
    webtest.errors(drv)
    bridge.send_signal(signal.SIGTERM)
    ended(bridge, "the bridge")
finally:
    if drv is not None:
        webtest.quit(drv)
    for p in procs:
        if p.poll() is None:
            p.kill()
            p.wait()
sim.done()
