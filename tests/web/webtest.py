# SPDX-License-Identifier: MIT
"""Shared helpers of the page's tests: headless Chromium through Selenium (Debian's chromium,
chromium-driver and python3-selenium), the page loaded from file://, waits on conditions."""
import base64
import os
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sim"))
from simtest import check, fail  # noqa: E402,F401  (the tests' shared check and fail)

CHROMIUM = "/usr/bin/chromium"
DRIVER = "/usr/bin/chromedriver"
# A loaded 2-core machine can take its time: every wait is for a condition, and gives up
# only after this long.
TIMEOUT_S = 300


def browser(width=1400, height=1000, download_dir=None):
    """A headless Chromium; fails the test with what to install when one is missing.
    Downloads land in download_dir without asking."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        fail("the page's tests need python3-selenium (tools/install-deps.sh test)")
    for path, pkg in ((CHROMIUM, "chromium"), (DRIVER, "chromium-driver")):
        if not os.access(path, os.X_OK):
            fail("the page's tests need %s (%s; tools/install-deps.sh test)" % (pkg, path))
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    profile = tempfile.mkdtemp(prefix="slam-chromium-")
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              "--no-first-run", "--disable-extensions", "--allow-file-access-from-files",
              "--user-data-dir=" + profile, "--window-size=%d,%d" % (width, height)):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    if download_dir is not None:
        opts.add_experimental_option("prefs", {
            "download.default_directory": download_dir, "download.prompt_for_download": False,
            "profile.default_content_setting_values.automatic_downloads": 1})
    drv = webdriver.Chrome(service=Service(DRIVER), options=opts)
    drv.set_script_timeout(TIMEOUT_S)
    drv.set_page_load_timeout(TIMEOUT_S)
    drv.slam_profile = profile
    return drv


def quit(drv):
    try:
        drv.quit()
    finally:
        shutil.rmtree(drv.slam_profile, ignore_errors=True)


def page_url(src, query=""):
    return "file://" + os.path.join(os.path.abspath(src), "tools", "web", "index.html") + query


def load_page(drv, src, query=""):
    drv.get(page_url(src, query))
    wait(drv, "return !!(window.slamview && window.slamview.app)", "the page to start")
    errors(drv)


def errors(drv):
    """Fails the test on any error the page logged (an exception, a failed load)."""
    bad = [e for e in drv.get_log("browser") if e["level"] == "SEVERE"]
    if bad:
        fail("the page logged errors:\n  " + "\n  ".join(e["message"] for e in bad))


def wait(drv, script, what, timeout=TIMEOUT_S):
    """Polls a script until it returns a true value; returns that value."""
    end = time.monotonic() + timeout
    while True:
        v = drv.execute_script(script)
        if v:
            return v
        if time.monotonic() > end:
            errors(drv)
            fail("waited %d s for %s" % (timeout, what))
        time.sleep(0.1)


def to_js(data):
    """Bytes as a base64 string for execute_script (the page turns it back: bytesOf())."""
    return base64.b64encode(bytes(data)).decode("ascii")


# Page-side helpers, prepended to scripts that take bytes.
JS_BYTES = """
const bytesOf = (b64) => Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
const b64Of = (u8) => { let s = ""; for (let i = 0; i < u8.length; i += 8192) {
  s += String.fromCharCode.apply(null, u8.subarray(i, i + 8192)); } return btoa(s); };
"""


# A run whose telemetry ends with the whole of om.pgm: the robot explores, then stands
# and stops changing OM (no echo can fall inside a confidence radius of 20 um, and the pose
# correction, which would hold hits back until the run's end, is off), then sends its map
# again from the first row; the run lasts until that pass is through (256 rows of both maps
# in 200-cell frames, one every 3 ticks: 31 s).
SETTLED_COMMANDS = """# explore, stand, stop changing OM, send the map whole
40 stop
40 set confidence_radius_um 20001
43 map
"""


def settled_run(sim, name="settled"):
    """host_sim's outputs and telemetry log of such a run: (out_dir, log)."""
    cmds = sim.out(name + ".cmds")
    with open(cmds, "w") as f:
        f.write(SETTLED_COMMANDS)
    out = sim.out(name)
    log = sim.out(name + ".tel")
    sim.run("--duration", 80, "--set", "localize=0", "--commands", cmds, "--out", out,
            "--telemetry", log)
    return out, log
