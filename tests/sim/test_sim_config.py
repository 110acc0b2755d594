#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim's firmware configuration: one source of truth.

The configuration is built in one order, a later one overriding an earlier one: the
calibration file, the --config file, the options given, each --set. The --config file's
values stand unless an option sets them; two options that set one
value differently are refused; a key given twice is refused (in a file or with --set);
what the banner and metrics.json report is what the firmware ran with; and every seed is
its own run, even with every error source off.
"""
import filecmp
import json
import os
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import umbmark  # noqa: E402  (the calibration file's reader)


def config_of(out):
    """config.txt of a run as a dict."""
    vals = {}
    with open(os.path.join(out, "config.txt")) as f:
        for line in f:
            if "=" in line and not line.startswith("#"):
                k, v = line.split("=", 1)
                vals[k.strip()] = v.strip()
    return vals


def write(name, text):
    path = sim.out(name)
    with open(path, "w") as f:
        f.write(text)
    return path


# B3: the file's cell_um, explore_mode and explore_seed stand.
conf = write("b3.conf", "cell_um = 100000\nexplore_mode = 2\nexplore_seed = 77\n")
out = sim.out("b3")
p = sim.run("--config", conf, "--duration", 5, "--out", out)
c = config_of(out)
m = sim.metrics(out)
check(c["cell_um"] == "100000" and c["explore_mode"] == "2" and c["explore_seed"] == "77",
      "the file's cell_um, explore_mode and explore_seed stand")
check(m["scenario"]["cell_mm"] == 100 and m["scenario"]["explore"] == "tm",
      "metrics.json reports what the firmware ran with (100 mm, tm)")
out = sim.out("b3-opt")
sim.run("--config", conf, "--cell", 50, "--explore", "random", "--seed", 4, "--duration", 5,
        "--out", out)
c = config_of(out)
check(c["cell_um"] == "50000" and c["explore_mode"] == "1" and c["explore_seed"] != "77",
      "an option sets what it names over the file")

# B4: one value set two ways must agree; the report says what the firmware used.
p = sim.run("--set", "cell_um=100000", "--cell", 50, "--out", sim.out("never"), expect=2)
check("--set cell_um=100000 disagrees with --cell 50" in p.stderr and
      not os.path.exists(sim.out("never")), "--set cell_um and --cell disagreeing: exit 2")
p = sim.run("--set", "explore_mode=2", "--explore", "random", "--out", sim.out("never"), expect=2)
check("disagrees with --explore random" in p.stderr, "--set explore_mode and --explore disagreeing: exit 2")
out = sim.out("b4")
p = sim.run("--set", "cell_um=100000", "--cell", 100, "--duration", 5, "--out", out)
m = sim.metrics(out)
check(m["scenario"]["cell_mm"] == 100 and abs(m["scenario"]["grid"]["origin"][0]) > 0,
      "agreeing values are fine, and metrics.json says 100 mm")

# B5: a key twice, in a file and on the command line.
conf = write("b5.conf", "wheel_base_um = 140000\n# measured again:\nwheel_base_um = 135000\n")
p = sim.run("--config", conf, "--out", sim.out("never"), expect=2)
check(conf + ":3: wheel_base_um is given twice (first on line 1)" in p.stderr,
      "a core key twice in --config: exit 2, file:line and key")
p = sim.run("--set", "om_max=8", "--set", "om_max=7", "--out", sim.out("never"), expect=2)
check("om_max is given twice" in p.stderr, "a key twice with --set: exit 2")

# The start pose is the scenario's: a file that says otherwise is refused, naming its line.
conf = write("start.conf", "om_max = 9\nstart_x_um = 123\n")
p = sim.run("--config", conf, "--out", sim.out("never"), expect=2)
check(conf + ":2: start_x_um = 123 disagrees with the run's start pose" in p.stderr,
      "a start pose in --config that is not the room's: exit 2, file:line")

# A run's own config.txt as --config gives the same run (its values all agree).
a = sim.out("again-a")
b = sim.out("again-b")
sim.run("--duration", 30, "--seed", 6, "--out", a)
sim.run("--duration", 30, "--seed", 6, "--config", os.path.join(a, "config.txt"), "--out", b)
check(filecmp.cmp(os.path.join(a, "readings.csv"), os.path.join(b, "readings.csv"), shallow=False),
      "a run's config.txt fed back with its seed gives the same readings")

# Range errors give the key, the value, the range and who set it.
for args, says in [
    (["--set", "cell_um=0"], "--set cell_um=0: cell_um = 0 is out of its valid range: 20000..1000000"),
    (["--set", "sweep_stops=1"], "sweep_stops = 1 is out of its valid range: 1..16, and 1 only when"),
    (["--set", "top_speed_mm_s=150"],
     "--set top_speed_mm_s=150: cruise_mm_s = 200 is out of its valid range: 1..5000, at most "
     "top_speed_mm_s (top_speed_mm_s = 150)"),
    (["--paper", "--set", "om_max=2"],
     "--paper: post_threshold = 3 is out of its valid range: 0..254, below om_max when om_mode is 0"),
    # A start cell at the grid's edge: the grid grows to fit the room, unless its size is set.
    (["--set", "start_cell_a=255", "--set", "grid_a=256"],
     "--set start_cell_a=255: with the start in cell 255 along x, the grid of 256 cells"),
    (["--set", "grid_a=60"], "--set grid_a=60: with the start in cell 30 along x, the grid of 60 cells"),
    (["--set", "wheel_base_um=99999999999999999999"], "out of its valid range: 50000..1000000"),
    (["--set", "wheel_base_um=-130000"], "wheel_base_um = '-130000': out of its valid range: 50000..1000000"),
    (["--set", "no_such_key=1"], "unknown key 'no_such_key' (the keys are the fields of firmware/include/slam/config_fields.h"),
]:
    p = sim.run(*args, "--out", sim.out("never"), expect=2)
    check(says in p.stderr, "%s: exit 2, says '%s'" % (" ".join(args), says))

# The default seed is seed 1: the same run with and without --seed 1.
a = sim.out("default-seed")
b = sim.out("seed-1")
sim.run("--duration", 30, "--out", a)
sim.run("--duration", 30, "--seed", 1, "--out", b)
check(filecmp.cmp(os.path.join(a, "readings.csv"), os.path.join(b, "readings.csv"), shallow=False),
      "host_sim and host_sim --seed 1 are one run")

# B6: every seed is its own run, with every error off too (in the random mode, which draws
# on the exploration seed at every turn).
logs = {}
for seed in (0, 1, 2, 3, 4294967296):
    out = sim.out("seed-%d" % seed)
    sim.run("--ideal", "--explore", "random", "--seed", seed, "--duration", 60, "--out", out)
    with open(os.path.join(out, "readings.csv")) as f:
        logs[seed] = f.read()
    logs["cfg%d" % seed] = config_of(out)["explore_seed"]
for a, b in ((0, 1), (2, 3), (1, 4294967296)):
    check(logs[a] != logs[b] and logs["cfg%d" % a] != logs["cfg%d" % b],
          "--ideal --seed %d and %d: different exploration seeds and runs" % (a, b))
# The order: the calibration file, then --config, then --set, each later one overriding.
def near(c, key, value):
    return abs(float(c[key]) - value) < 1e-4


cal = write("order-cal.conf", "cal_left = 0.99\ncal_right = 1.01\ncal_base = 1.02\n")
conf = write("order.conf", "cal_left = 0.98\n")
out = sim.out("order-cal")
sim.run("--calibration", cal, "--duration", 5, "--out", out)
c = config_of(out)
check(near(c, "cal_left", 0.99) and near(c, "cal_right", 1.01) and near(c, "cal_base", 1.02),
      "the calibration file's values reach the firmware")
out = sim.out("order-all")
sim.run("--calibration", cal, "--config", conf, "--set", "cal_base=1.01", "--duration", 5,
        "--out", out)
c = config_of(out)
check(near(c, "cal_left", 0.98) and near(c, "cal_right", 1.01) and near(c, "cal_base", 1.01),
      "--config overrides the calibration file, --set overrides both")
out = sim.out("order-default")
sim.run("--config", conf, "--duration", 5, "--out", out)
c = config_of(out)
shipped = umbmark.read_config(os.path.join(sim.src, "host_sim", "calibration", "default_robot.conf"))
check(near(c, "cal_left", 0.98) and near(c, "cal_right", shipped["cal_right"]),
      "--config overrides the default robot's calibration key by key")
bad = write("bad-cal.conf", "cal_right = 1.0\ncal_left = 2\n")
p = sim.run("--calibration", bad, "--out", sim.out("never"), expect=2)
check("bad-cal.conf:2" in p.stderr and "cal_left" in p.stderr and
      not os.path.exists(sim.out("never")),
      "a calibration value out of range: exit 2, naming the file's line and key")

# The grid's size. A 4 x 4 m room fits the usual 256 x 256 grid, and config.txt says so.
square = write("square4.room", "wall 0 0 4 0\nwall 4 0 4 4\nwall 4 4 0 4\nwall 0 4 0 0\n"
               "start 2 2 0\n")
out = sim.out("grid256")
sim.run("--room", square, "--duration", 5, "--out", out)
c = config_of(out)
check(c["grid_a"] == "256" and c["grid_b"] == "256", "a room that fits: the 256 x 256 grid")
# grid_a and grid_b given: the run's grid is theirs, the room centred on it.
out = sim.out("grid100")
sim.run("--room", square, "--set", "grid_a=100", "--set", "grid_b=90", "--duration", 5,
        "--out", out)
c = config_of(out)
with open(os.path.join(out, "om.pgm"), "rb") as f:
    head = f.read(20).split(b"\n")
check(c["grid_a"] == "100" and c["grid_b"] == "90" and c["start_cell_a"] == "50" and
      head[1] == b"100 90", "grid_a = 100, grid_b = 90: a 100 x 90 map, the start at its middle")
# A room wider than 12.8 m grows the grid, and nothing falls outside it.
wide = write("wide.room", "wall 0 0 20 0\nwall 20 0 20 3\nwall 20 3 0 3\nwall 0 3 0 0\n"
             "start 1 1.5 0\n")
out = sim.out("grid_wide")
sim.run("--room", wide, "--duration", 60, "--out", out)
c = config_of(out)
with open(os.path.join(out, "metrics.json")) as f:
    m = json.load(f)
check(int(c["grid_a"]) * 0.05 >= 20.0 and c["grid_b"] == "256" and
      m["scenario"]["grid"]["a"] == int(c["grid_a"]) and m["robot"]["outside_grid"] == 0,
      "a 20 m room: the grid grown along x to hold it, no point outside (grid_a = %s)"
      % c["grid_a"])

sim.done()
