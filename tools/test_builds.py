#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""make test: configure, build and test each CMake preset, a line a build.

usage: tools/test_builds.py [--jobs N] PRESET...

For each preset: `cmake --preset P`, `cmake --build --preset P -j N` and `ctest --preset P`,
their output to build/P/test.log (ctest's results also to build/P/ctest.xml, JUnit), and
one line on the terminal:
    host        209 tests passed in 4 min 10 s (build 1 min 02 s); 1 skipped: test_x (why)
A skipped test's reason is the line its output starts with "SKIP:" (its last line
otherwise). Anything still running after 30 s says how far it is every 30 s. A failed
build prints its errors; failed tests print their whole output, and the run goes on to
the next build. host-m32's tests run only where the kernel runs 32-bit programs (a
virtual machine without IA-32 emulation cannot): there it is built and says its tests were
not run.
Exit status: 0 every build passed; 1 a build or a test failed; 2 bad options.
"""
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET

from slamtools.errors import FAILED, ToolError, main as tool_main

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRESS_S = float(os.environ.get("TEST_PROGRESS_S", "30"))
NAME_WIDTH = 11


def duration(s):
    s = int(round(s))
    if s < 60:
        return "%d s" % s
    return "%d min %02d s" % (s // 60, s % 60)


class Step:
    """One command whose output goes to the log; every PROGRESS_S seconds, while it runs,
    a line saying what it does and how far it is."""

    def __init__(self, preset, log):
        self.preset = preset
        self.log = log
        self.what = ""
        self.started = time.monotonic()  # progress counts from the build's start
        self.lock = threading.Lock()

    def status(self):
        with self.lock:
            what = self.what
        return what() if callable(what) else what

    def set(self, what):
        with self.lock:
            self.what = what

    def run(self, cmd, on_line=None):
        """Runs cmd, its output appended to the log (each line also to on_line); returns
        its exit status."""
        done = threading.Event()

        def tick():
            while not done.wait(PROGRESS_S):
                print("  %-*s ... %s, %s so far" % (NAME_WIDTH, self.preset, self.status(),
                                                   duration(time.monotonic() - self.started)),
                      flush=True)

        ticker = threading.Thread(target=tick, daemon=True)
        ticker.start()
        self.log.write("$ %s\n" % " ".join(cmd))
        self.log.flush()
        env = dict(os.environ)
        env.pop("MAKEFLAGS", None)  # make's own flags are not the build's
        env.pop("MAKELEVEL", None)
        p = subprocess.Popen(cmd, cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True, errors="replace", env=env)
        for line in p.stdout:
            self.log.write(line)
            if on_line:
                on_line(line)
        rc = p.wait()
        done.set()
        ticker.join()
        self.log.flush()
        return rc


def can_run_m32(work):
    """Whether this kernel runs a 32-bit program (a VM without IA-32 emulation cannot)."""
    probe = os.path.join(work, "m32_probe")
    with open(probe + ".c", "w") as f:
        f.write("int main(void) { return 0; }\n")
    cc = os.environ.get("CC", "cc")
    if subprocess.run([cc, "-m32", probe + ".c", "-o", probe],
                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode != 0:
        return False
    try:
        return subprocess.run([probe], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL).returncode == 0
    except OSError:
        return False


def skip_reason(out):
    lines = [ln.strip() for ln in (out or "").splitlines() if ln.strip()]
    for ln in lines:
        if ln.startswith("SKIP:"):
            return ln[5:].strip()
    return lines[-1] if lines else "no reason given"


def results(xml_path):
    """(name, status, seconds, output) of each test in ctest's JUnit file; status is
    run, fail or notrun (skipped, or disabled)."""
    try:
        root = ET.parse(xml_path).getroot()
    except (OSError, ET.ParseError):
        return []
    out = []
    for tc in root.iter("testcase"):
        so = tc.find("system-out")
        out.append((tc.get("name"), tc.get("status"), float(tc.get("time") or 0.0),
                    so.text if so is not None and so.text else ""))
    return out


def build_and_test(preset, jobs):
    """Returns (ok, the build's line)."""
    bdir = os.path.join(SRC, "build", preset)
    os.makedirs(bdir, exist_ok=True)
    log_path = os.path.join(bdir, "test.log")
    rel_log = os.path.relpath(log_path, SRC)
    t0 = time.monotonic()
    with open(log_path, "w") as log:
        step = Step(preset, log)
        step.set("configuring")
        rc = step.run(["cmake", "--preset", preset])
        if rc == 0:
            def build_line(line):
                m = re.match(r"^\[\s*(\d+)%\]", line)
                if m:
                    step.set("building, %s %%" % m.group(1))
            step.set("building")
            rc = step.run(["cmake", "--build", "--preset", preset, "-j", str(jobs)], build_line)
        build_s = time.monotonic() - t0
        if rc != 0:
            with open(log_path) as f:
                text = f.read()
            errors = [ln for ln in text.splitlines()
                      if re.search(r"error|Error|undefined reference|warning:", ln)]
            print("%-*s BUILD FAILED after %s (all of it: %s):" % (NAME_WIDTH, preset,
                                                                   duration(build_s), rel_log))
            for ln in (errors[-40:] or text.splitlines()[-40:]):
                print("    " + ln)
            return False, None
        if preset == "host-m32":
            with tempfile.TemporaryDirectory() as work:
                runs32 = can_run_m32(work)
            if not runs32:
                line = ("%-*s built in %s; its tests NOT run: this kernel cannot run 32-bit "
                        "programs" % (NAME_WIDTH, preset, duration(build_s)))
                print(line, flush=True)
                return True, line
        xml_path = os.path.join(bdir, "ctest.xml")
        running = {}
        count = [0, 0]  # done, total

        def test_line(line):
            m = re.match(r"^\s*Start\s+\d+:\s+(\S+)", line)
            if m:
                running[m.group(1)] = time.monotonic()
            m = re.match(r"^\s*(\d+)/(\d+) Test\s+#\d+:\s+(\S+)", line)
            if m:
                count[0], count[1] = int(m.group(1)), int(m.group(2))
                running.pop(m.group(3), None)

        def test_status():
            now = time.monotonic()
            slow = sorted(list(running.items()), key=lambda kv: kv[1])
            return "%d/%s tests done%s" % (
                count[0], count[1] or "?",
                "; running " + ", ".join("%s (%s)" % (n, duration(now - t)) for n, t in slow)
                if slow else "")
        step.set(test_status)
        t1 = time.monotonic()
        rc = step.run(["ctest", "--preset", preset, "--output-junit", xml_path], test_line)
        test_s = time.monotonic() - t1
    tests = results(xml_path)
    failed = [t for t in tests if t[1] == "fail"]
    skipped = [t for t in tests if t[1] == "notrun"]
    passed = [t for t in tests if t[1] == "run"]
    skips = ""
    if skipped:
        skips = "; %d skipped: %s" % (len(skipped), ", ".join(
            "%s (%s)" % (t[0], skip_reason(t[3])) for t in skipped))
    total = duration(time.monotonic() - t0)
    if rc == 0 and not failed and tests:
        line = ("%-*s %d tests passed in %s (build %s, tests %s)%s"
                % (NAME_WIDTH, preset, len(passed), total, duration(build_s), duration(test_s),
                   skips))
        print(line, flush=True)
        return True, line
    print("%-*s FAILED: %d of %d tests (%s; all output: %s)%s"
          % (NAME_WIDTH, preset, len(failed), len(tests), total, rel_log, skips))
    if not tests:
        with open(log_path) as f:
            for ln in f.read().splitlines()[-40:]:
                print("    " + ln)
    for name, _, secs, out in failed:
        print("---- %s %s failed after %.1f s; its output:" % (preset, name, secs))
        print(out.rstrip())
    if failed:
        print("---- end of %s's failures" % preset, flush=True)
    return False, None


def main(argv):
    jobs = 2
    presets = []
    i = 0
    while i < len(argv):
        if argv[i] in ("-h", "--help"):
            print(__doc__.strip())
            return 0
        if argv[i] == "--jobs" and i + 1 < len(argv) and argv[i + 1].isdigit():
            jobs = int(argv[i + 1])
            i += 2
            continue
        if argv[i].startswith("-"):
            raise ToolError("unknown option '%s' (--help)" % argv[i])
        presets.append(argv[i])
        i += 1
    if not presets:
        raise ToolError("which presets? (--help)")
    t0 = time.monotonic()
    print("make test: %d build%s (%s), a line each; logs in build/PRESET/test.log"
          % (len(presets), "s" if len(presets) > 1 else "", ", ".join(presets)), flush=True)
    bad = [p for p in presets if not build_and_test(p, jobs)[0]]
    took = duration(time.monotonic() - t0)
    if bad:
        print("make test FAILED in %s: %s (logs: %s)" % (
            ", ".join(bad), took, ", ".join("build/%s/test.log" % p for p in bad)))
        return FAILED
    print("make test: %s passed in %s" % ("all %d builds" % len(presets) if len(presets) > 1
                                         else presets[0], took))
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
