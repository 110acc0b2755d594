#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The README's calibration, followed word for word: its marked shell blocks run as they
stand, starting from the shipped Pi configuration, and the calibration they make is the one
the next run uses.

usage: test_readme_calibration.py HOST_SIM SRC_DIR
       test_readme_calibration.py --fill RUNS.csv TAPE.csv   (the person, filling runs.csv)

README.md's "Calibration" holds two fenced blocks, each after a `<!-- test: NAME -->` line:
- `calibration`: the simulator's journey. Run in a scratch folder where hal/ and tools/ are
  the source tree's and build/host/host_sim/host_sim is the one under test.
- `calibration-robot`: the robot's journey, on a robot.conf copied from
  hal/linux/robot-rpi.conf as hal/linux/README.md says. The robot and the person with the
  tape are simulated: `sudo` is a shell function that runs the program's command line in
  host_sim instead (the same robot.conf, so the run drives UMBmark only if the block set
  explore_mode = 5), then fills the person's runs.csv, line by line in its order, with what
  host_sim's tape read.
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

# What the simulated robot's wheels are (hal/host/README.md, error levels): the calibration
# must find them within a tape's worth (test_calibrate.py holds the exact figures).
E_D, E_B, TOLERANCE = 1.005, 1.03, 0.002
BLOCK = re.compile(r"^<!-- test: ([a-z-]+) -->\n```sh\n(.*?)^```", re.M | re.S)


def fill(runs_path, tape_path):
    """The person: one measured run into each empty line of the template, in order; a run
    the robot drove the other way than the template's line, or a line too few, is an error."""
    if not os.path.exists(tape_path):
        sys.exit("the robot drove no UMBmark (no %s): was explore_mode 5?" % tape_path)
    with open(tape_path) as f:
        tape = [ln.strip() for ln in f if re.match(r"^c?cw,", ln)]
    with open(runs_path) as f:
        lines = f.read().splitlines()
    done = 0
    for i, ln in enumerate(lines):
        m = re.match(r"^(c?cw),\s*,\s*$", ln)
        if not m:
            continue
        if done >= len(tape) or tape[done].split(",")[0] != m.group(1):
            sys.exit("%s:%d: the template wants a %s run here; the tape has %s"
                     % (runs_path, i + 1, m.group(1),
                        tape[done] if done < len(tape) else "no more runs"))
        lines[i] = tape[done]
        done += 1
    if done != len(tape):
        sys.exit("%s: %d runs measured, %d lines to fill" % (runs_path, len(tape), done))
    with open(runs_path, "w") as f:
        f.write("\n".join(lines) + "\n")


if len(sys.argv) == 4 and sys.argv[1] == "--fill":
    fill(sys.argv[2], sys.argv[3])
    sys.exit(0)

from simtest import Sim, check, fail  # noqa: E402

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import umbmark  # noqa: E402

with open(os.path.join(sim.src, "README.md")) as f:
    blocks = dict(BLOCK.findall(f.read()))
for name in ("calibration", "calibration-robot"):
    if name not in blocks:
        fail("README.md has no ```sh block after <!-- test: %s -->" % name)


def scratch(name):
    """A folder laid out as the source tree the README's commands are typed in."""
    d = sim.out(name)
    os.makedirs(os.path.join(d, "build", "host", "host_sim"))
    for part in ("firmware", "hal", "tools", "host_sim"):  # the tools read firmware headers
        os.symlink(os.path.join(sim.src, part), os.path.join(d, part))
    os.symlink(os.path.abspath(sim.bin), os.path.join(d, "build", "host", "host_sim", "host_sim"))
    return d


def run_block(name, cwd, prelude=""):
    script = "set -e -o pipefail\n" + prelude + blocks[name]
    p = subprocess.run(["/bin/bash", "-c", script], cwd=cwd, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        fail("README.md's block '%s' failed (exit %d):\n%s\n--- its output:\n%s"
             % (name, p.returncode, blocks[name], p.stdout[-4000:]))
    print("ok: README.md's block '%s' runs as written" % name)
    return p.stdout


def check_calibrated(name, conf, run_out):
    """robot.conf holds the wheels' calibration, and the run after it read that one."""
    cal = umbmark.read_config(conf)
    e_d = cal["cal_right"] / cal["cal_left"]  # c_R / c_L = E_d
    check(abs(e_d - E_D) <= TOLERANCE and abs(cal["cal_base"] - E_B) <= TOLERANCE,
          "%s: robot.conf calibrated: cal_left %.6f, cal_right %.6f, cal_base %.6f "
          "(the wheels: E_d %.3f, E_b %.3f)" % (name, cal["cal_left"], cal["cal_right"],
                                               cal["cal_base"], E_D, E_B))
    used = umbmark.read_config(os.path.join(run_out, "config.txt"))
    check(all(abs(used[k] - cal[k]) < 5e-7 for k in ("cal_left", "cal_right", "cal_base")),
          "%s: the next run uses it (its config.txt: cal_left %.6f, cal_right %.6f, "
          "cal_base %.6f)" % (name, used["cal_left"], used["cal_right"], used["cal_base"]))


# The simulator's journey.
d = scratch("sim")
run_block("calibration", d)
check_calibrated("simulator", os.path.join(d, "robot.conf"), os.path.join(d, "out", "calibrated"))

# The robot's journey, its robot.conf made as hal/linux/README.md says.
d = scratch("robot")
subprocess.run(["cp", os.path.join(sim.src, "hal", "linux", "robot-rpi.conf"),
                os.path.join(d, "robot.conf")], check=True)
prelude = r'''
sudo() {
    case "$1" in */sonarslam-linux) shift ;; *) echo "sudo: not the robot's program: $1"; return 1 ;; esac
    build/host/host_sim/host_sim "$@" --out robot-run --no-plot --quiet
    %s %s --fill runs.csv robot-run/umbmark.csv
}
''' % ("/usr/bin/python3", os.path.abspath(__file__))
run_block("calibration-robot", d, prelude)
conf = os.path.join(d, "robot.conf")
with open(conf) as f:
    modes = re.findall(r"^explore_mode = (\d+)$", f.read(), re.M)
check(modes == ["4"],
      "robot: robot.conf follows the walls again (explore_mode = 4)")
sim.run("--config", conf, "--duration", "60", "--out", os.path.join(d, "next"))
check_calibrated("robot", conf, os.path.join(d, "next"))
sim.done()
