#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One robot.conf for both programs: the shipped hal/linux/robot-rpi.conf, fed to
sonarslam-linux --check and to host_sim --config, is read by both (the Linux program checks
its wiring; the simulator runs the robot with the file's core keys, skipping [linux]); and
both refuse the same misplaced keys: a core key under [linux], a wiring key before it, an
unknown section.

usage: test_one_robot_conf.py HOST_SIM SONARSLAM_LINUX SRC_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile

host_sim, linux, src = (os.path.abspath(a) for a in sys.argv[1:4])
work = tempfile.mkdtemp(prefix="slam-robotconf-")
failures = []


def check(ok, what):
    print("%s: %s" % ("ok" if ok else "FAIL", what))
    if not ok:
        failures.append(what)


def both(conf):
    """(host_sim's run, the Linux program's --check) on one file."""
    out = os.path.join(work, "run")
    shutil.rmtree(out, ignore_errors=True)
    h = subprocess.run([host_sim, "--config", conf, "--duration", "5", "--out", out,
                        "--no-plot", "--quiet"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    # The check opens the hardware the file names: here there is none, so it fails with
    # exit 1 after reading the file; a file it cannot read is exit 2.
    x = subprocess.run([linux, "--config", conf, "--check"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=60, cwd=work)
    return h, x


shipped = os.path.join(src, "hal", "linux", "robot-rpi.conf")
conf = os.path.join(work, "robot.conf")
shutil.copy(shipped, conf)
h, x = both(conf)
check(h.returncode == 0, "host_sim --config robot-rpi.conf runs: %s" % h.stderr.strip())
check(x.returncode in (0, 1) and "check:" in x.stdout and "robot.conf" not in x.stderr,
      "sonarslam-linux --check reads the same file and checks its wiring (exit %d): %s"
      % (x.returncode, (x.stdout + x.stderr).strip().splitlines()[-1:]))

# The simulator ran the file's robot: its configuration is the file's core keys.
core = {}
section = None
with open(conf) as f:
    for raw in f:
        line = raw.split("#", 1)[0].strip()
        if line.startswith("["):
            section = line
        elif "=" in line and section is None:
            k, v = (s.strip() for s in line.split("=", 1))
            core[k] = v
ran = {}
with open(os.path.join(work, "run", "config.txt")) as f:
    for raw in f:
        line = raw.split("#", 1)[0].strip()
        if "=" in line:
            k, v = (s.strip() for s in line.split("=", 1))
            ran[k] = v
differ = sorted(k for k, v in core.items()
                if k not in ran or (float(v) != float(ran[k])))
check(len(core) >= 20 and not differ,
      "host_sim ran with every one of the file's %d core keys (differ: %s)" % (len(core), differ))

# Misplaced keys: both programs refuse the file, naming the line.
with open(shipped) as f:
    text = f.read()
cases = [
    ("a core key under [linux]", text + "cruise_mm_s = 150\n",
     "it belongs before the first [section]"),
    ("a wiring key before [linux]", "gpio_chip = gpiochip4\n" + text, "unknown key 'gpio_chip'"),
    ("an unknown section", text + "[linx]\n", "unknown section [linx]"),
]
for what, body, says in cases:
    with open(conf, "w") as f:
        f.write(body)
    h, x = both(conf)
    check(h.returncode == 2 and says in h.stderr and "robot.conf:" in h.stderr,
          "%s: host_sim refuses it: %s" % (what, h.stderr.strip()))
    check(x.returncode == 2 and says in x.stderr and "robot.conf:" in x.stderr,
          "%s: sonarslam-linux refuses it: %s" % (what, x.stderr.strip()))

shutil.rmtree(work, ignore_errors=True)
print("%d failed" % len(failures) if failures else "all passed")
sys.exit(1 if failures else 0)
