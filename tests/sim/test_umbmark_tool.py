#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/umbmark.py: the formulas against their first-order model, the exact solution
against its own model written out anew, a worked example computed by hand, the signs proven by
simulation (a robot with a known E_d and E_b gets them back from its own UMBmark, both
ways of each), a calibration in force composed, and bad input answered with file:line and
exit 2, nothing written."""
import math
import os
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
tool = os.path.join(sim.src, "tools", "umbmark.py")
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import umbmark  # noqa: E402


def run_tool(*args):
    return subprocess.run(["/usr/bin/python3", tool] + [str(a) for a in args],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def write(name, text):
    path = sim.out(name)
    with open(path, "w") as f:
        f.write(text)
    return path


def keys(text):
    out = {}
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if "=" in line:
            k, v = (s.strip() for s in line.split("=", 1))
            out[k] = float(v)
    return out


# ---- the command line ---------------------------------------------------------------------
p = run_tool("--help")
check(p.returncode == 0 and "usage: tools/umbmark.py" in p.stdout and "Borenstein" in p.stdout
      and "Exit status" in p.stdout, "--help: usage, sources and exit status")
p = run_tool()
check(p.returncode == 2, "no arguments: the usage, exit 2")
p = run_tool("--template")
lines = [s for s in p.stdout.splitlines() if s and not s.startswith("#")]
check(p.returncode == 0 and lines[0] == "direction,x_mm,y_mm" and lines.count("cw,,") == 5
      and lines.count("ccw,,") == 5, "--template: a header and five empty runs each way")

# ---- the formulas against the first-order model they invert ---------------------------------
L, b = 2000.0, 130.0
alpha, beta = math.radians(1.5), math.radians(-0.8)
model = {"cw": [(-2 * L * (alpha + beta), -2 * L * (alpha + beta))] * 5,
         "ccw": [(-2 * L * (alpha - beta), 2 * L * (alpha - beta))] * 5}
a = umbmark.analyse(model, L, b)
check(abs(a["alpha_first_deg"] - 1.5) < 1e-9 and abs(a["beta_first_deg"] + 0.8) < 1e-9
      and abs(a["alpha_x_deg"] - a["alpha_y_deg"]) < 1e-9,
      "first order: alpha and beta come back from the model, the x and y forms alike "
      "(%.6f, %.6f deg)" % (a["alpha_first_deg"], a["beta_first_deg"]))
check(abs(a["e_max_syst"] - max(math.hypot(*model["cw"][0]), math.hypot(*model["ccw"][0]))) < 1e-9,
      "E_max,syst is the larger distance of the two centres of gravity (%.1f mm)" % a["e_max_syst"])


# ---- the exact model [8], written out here on its own: legs as arcs, three corner turns -----
def run_end(alpha, beta, side, turn):
    """End of a square of four arcs (heading turning by beta along each) and three turns of
    turn x (90 deg - alpha), as complex numbers: the start pose's frame, x + iy."""
    pos, heading = 0j, 0.0
    chord = side * (math.sin(beta / 2) / (beta / 2) if beta else 1.0)  # an arc's chord
    for leg in range(4):
        pos += chord * complex(math.cos(heading + beta / 2), math.sin(heading + beta / 2))
        heading += beta + (turn * (math.pi / 2 - alpha) if leg < 3 else 0.0)
    return pos.real, pos.imag


ends = {"cw": [run_end(alpha, beta, L, -1)] * 5, "ccw": [run_end(alpha, beta, L, 1)] * 5}
a = umbmark.analyse(ends, L, b)
check(abs(a["alpha_deg"] - 1.5) < 1e-7 and abs(a["beta_deg"] + 0.8) < 1e-7 and a["fit_mm"] < 1e-6
      and abs(a["alpha_first_deg"] - 1.5) > 1e-3,
      "exact: alpha and beta come back from the model's own ends (%.8f, %.8f deg; first order "
      "%.4f, %.4f)" % (a["alpha_deg"], a["beta_deg"], a["alpha_first_deg"], a["beta_first_deg"]))
R = (L / 2) / math.sin(beta / 2)
e_b = 90.0 / 88.5
e_d = (R + b * e_b / 2) / (R - b * e_b / 2)
check(abs(a["e_b"] - e_b) < 1e-9 and abs(a["e_d"] - e_d) < 1e-9 and a["e_d"] < 1.0,
      "E_b = 90/(90 - alpha) = %.6f, E_d = (R + b/2)/(R - b/2) = %.6f (legs curving right: "
      "the left wheel larger)" % (a["e_b"], a["e_d"]))
check(abs(a["cal"][0] - 2 / (a["e_d"] + 1)) < 1e-12
      and abs(a["cal"][1] - 2 / (1 / a["e_d"] + 1)) < 1e-12 and abs(a["cal"][2] - a["e_b"]) < 1e-12,
      "c_L = 2/(E_d + 1), c_R = 2/(1/E_d + 1), cal_base = E_b")
a2 = umbmark.analyse(ends, L, b, cal=(0.99, 1.01, 1.02))
check(abs(a2["cal"][0] - 0.99 * a2["c_l"]) < 1e-12 and abs(a2["cal"][2] - 1.02 * a2["e_b"]) < 1e-12,
      "on top of a calibration in force, the factors multiply")

# ---- a worked example, computed by hand ----------------------------------------------------
# L = 1000 mm, b = 100 mm. cw runs (-30, -30) and (-50, -50): centre (-40, -40), r = 40 sqrt 2
# = 56.569 mm; ccw runs (-10, 10) and (-30, 30): centre (-20, 20), r = 28.284 mm.
# First order: alpha = (-40 + -20) / -4000 = 0.015 rad from x, (-40 - 20) / -4000 = 0.015 from
# y: 0.859437 deg; beta = (-40 - -20) / -4000 = 0.005 rad from x, (-40 + 20) / -4000 = 0.005
# from y: 0.286479 deg. The exact model moves them a little (checked above); from them
# E_b = 90 / (90 - alpha), b = 100 E_b, R = 500 / sin(beta / 2), E_d = (R + b/2) / (R - b/2).
hand = write("hand.csv", "direction,x_mm,y_mm\ncw,-30,-30\ncw,-50,-50\nccw,-10,10\nccw,-30,30\n")
p = run_tool(hand, "--side-mm", 1000, "--base-mm", 100)
got = keys(p.stdout)
h = umbmark.calibrate(hand, side_mm=1000.0, base_mm=100.0)[0]
# (figure: value by hand, within the digits written down)
expect = {"e_max_syst": (56.569, 5e-4), "r_ccw": (28.284, 5e-4),
          "alpha_first_deg": (0.859437, 5e-7), "beta_first_deg": (0.286479, 5e-7)}
bad_figures = ["%s %.7f, by hand %g" % (k, h[k], v) for k, (v, tol) in expect.items()
               if abs(h[k] - v) > tol]
hb = 100.0 * 90.0 / (90.0 - h["alpha_deg"])
hr = 500.0 / math.sin(math.radians(h["beta_deg"]) / 2)
he_d = (hr + hb / 2) / (hr - hb / 2)
check(p.returncode == 0 and not bad_figures and "E_max,syst = 56.6 mm" in p.stdout
      and abs(h["alpha_deg"] - 0.859437) < 0.05 and abs(h["beta_deg"] - 0.286479) < 0.05
      and abs(got["cal_left"] - 2 / (he_d + 1)) < 1e-6
      and abs(got["cal_right"] - 2 / (1 / he_d + 1)) < 1e-6
      and abs(got["cal_base"] - hb / 100.0) < 1e-6,
      "a worked example: the tool's figures and lines agree with the hand computation %s\n%s"
      % (bad_figures, p.stdout))

# ---- the signs, by simulation: the tape measures what a known robot does --------------------
for ed, eb in ((1.004, 1.02), (0.996, 0.98)):
    out = sim.out("umb-%g-%g" % (ed, eb))
    sim.run("--explore", "umbmark", "--ideal", "--error", "ed=%g" % ed, "--error", "eb=%g" % eb,
            "--set", "square_side_um=1500000", "--set", "umbmark_pause_s=1", "--duration", 3000,
            "--out", out)
    p = run_tool(os.path.join(out, "umbmark.csv"), "--config", os.path.join(out, "config.txt"))
    got = keys(p.stdout)
    est = umbmark.calibrate(os.path.join(out, "umbmark.csv"), os.path.join(out, "config.txt"))[0]
    # Within 3 % of each error: what the exact model and a +-5 mm tape allow (the first-order
    # formulas alone are 3-5 % off here).
    check(p.returncode == 0 and abs(est["e_d"] - ed) < 0.03 * abs(ed - 1)
          and abs(est["e_b"] - eb) < 0.03 * abs(eb - 1)
          and abs(got["cal_base"] - est["e_b"]) < 1e-6,
          "a robot with E_d %g and E_b %g: UMBmark measures %.5f and %.5f" % (ed, eb, est["e_d"],
                                                                            est["e_b"]))

# ---- a real robot's configuration, and --out ----------------------------------------------
runs = write("runs.csv", "# measured by hand\ndirection,x_mm,y_mm\ncw,-120,-95\ncw,-131,-88\n"
                         "\nCCW , 40, -30 # a comment\nccw,35,-41\n")
conf = write("robot.conf", "square_side_um = 1200000\nwheel_base_um = 140000\n"
                           "cal_left = 1.0\ncal_right = 1.0\ncal_base = 1.01\n"
                           "[linux]\ngpio_chip = pinctrl-bcm2711  # a Linux robot's key\n"
                           "wheel_base_um = 999  # not the robot's: a section is another program's\n")
dest = sim.out("cal.conf")
p = run_tool(runs, "--config", conf, "--out", dest)
with open(dest) as f:
    written = f.read()
check(p.returncode == 0 and written == p.stdout.replace("# written to %s\n" % dest, "")
      and "L = 1200 mm" in written and "b = 140.0 mm" in written
      and "(Borenstein & Feng drive 5 each way)" in written
      and set(keys(written)) == {"cal_left", "cal_right", "cal_base"},
      "robot.conf gives L, b and the calibration in force; --out holds what was printed")
# The file written keeps the mode a new file gets under the umask, as any program's
# output does (a temporary file of mkstemp is 0600: another user could not read it).
for mask in (0o022, 0o002, 0o077):
    dest_m = sim.out("cal-%03o.conf" % mask)
    p = subprocess.run(["/bin/sh", "-c", "umask %03o && exec /usr/bin/python3 \"$@\"" % mask, "sh",
                        tool, runs, "--config", conf, "--out", dest_m],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    mode = os.stat(dest_m).st_mode & 0o777 if p.returncode == 0 else None
    check(mode == 0o666 & ~mask, "--out under umask %03o: mode %s, as a new file gets (%03o)"
          % (mask, "%03o" % mode if mode is not None else p.stderr.strip(), 0o666 & ~mask))
p = run_tool(runs, "--side-mm", 1200)
check(p.returncode == 0 and keys(p.stdout)["cal_base"] != keys(written)["cal_base"],
      "--side-mm without a configuration: no calibration in force")

# --apply: the calibration written into the robot's own file, in place of its cal_ lines
# (or before its first section), every other line and the file's mode as they were.
original = ("# my robot\nwheel_base_um = 140000   # measured\nsquare_side_um = 1200000\n"
            "cal_base = 1.01  # from last year\n\n[linux]\ngpio_chip = pinctrl-rp1\n")
target = write("apply.conf", original)
os.chmod(target, 0o640)
p = run_tool(runs, "--config", target, "--apply")
with open(target) as f:
    applied = f.read()
new = keys(p.stdout)
want = ("# my robot\nwheel_base_um = 140000   # measured\nsquare_side_um = 1200000\n"
        "cal_base = %s  # from last year\ncal_left = %s\ncal_right = %s\n\n[linux]\n"
        "gpio_chip = pinctrl-rp1\n") % tuple(
    "%.6f" % new[k] for k in ("cal_base", "cal_left", "cal_right"))
check(p.returncode == 0 and applied == want and os.stat(target).st_mode & 0o777 == 0o640
      and "its next run uses them" in p.stdout,
      "--apply rewrites cal_base where it was, adds the other two after the robot's keys, "
      "keeps the rest and the mode:\n%s" % applied)
check(keys(run_tool(runs, "--config", target).stdout)["cal_left"] != new["cal_left"],
      "the next analysis starts from the calibration applied")
p = run_tool(runs, "--apply")
check(p.returncode == 2 and "give one" in p.stderr, "--apply without --config: exit 2")
# A configuration without the square's side: the robot drove the firmware's default.
p = run_tool(runs, "--config", write("noside.conf", "wheel_base_um = 140000\n"))
check(p.returncode == 0 and "L = 1500 mm" in p.stdout,
      "a robot.conf without square_side_um: the firmware's default side, 1.5 m")

# ---- bad input: the file and line, exit 2, nothing written --------------------------------
bad = [
    ("cw,1,2\nccw,3\n", "bad.csv:2:", "expected 'cw|ccw,x_mm,y_mm'"),
    ("cw,1,2\nup,3,4\n", "bad.csv:2:", "neither cw nor ccw"),
    ("cw,1,2\nccw,three,4\n", "bad.csv:2:", "x_mm: 'three' is not a decimal number"),
    ("cw,1,nan\nccw,3,4\n", "bad.csv:1:", "y_mm: 'nan' is not a decimal number"),
    ("cw,1,0x10\nccw,3,4\n", "bad.csv:1:", "y_mm: '0x10' is not a decimal number"),
    ("cw,1,1e400\nccw,3,4\n", "bad.csv:1:", "y_mm: '1e400' is out of range"),
    ("cw,,\nccw,3,4\n", "bad.csv:1:", "missing"),
    ("cw,1,2\ndirection,x_mm,y_mm\nccw,3,4\n", "bad.csv:2:", "header must come before"),
    ("cw,1,2\ncw,3,4\n", "bad.csv:", "no ccw runs"),
    ("cw,-900000,10\nccw,5,5\n", "bad.csv:", "small angles"),
]
with open(dest) as f:
    before = f.read()
for text, where, what in bad:
    path = write("bad.csv", text)
    p = run_tool(path, "--side-mm", 1500, "--out", dest)
    with open(dest) as f:
        same = f.read() == before
    check(p.returncode == 2 and where in p.stderr and what in p.stderr and same
          and "Traceback" not in p.stderr,
          "bad runs: %s" % p.stderr.strip())
for args, what in (((runs,), "side of the square is unknown"),
                   ((runs, "--side-mm", "-3"), "--side-mm must be a positive"),
                   ((runs, "--bogus"), "unknown option"),
                   ((sim.out("nothing.csv"), "--side-mm", 1), "cannot read"),
                   ((runs, "--config", write("c.conf", "square_side_um 100\n")), "c.conf:1:")):
    p = run_tool(*args)
    check(p.returncode == 2 and what in p.stderr and "Traceback" not in p.stderr,
          "bad options: %s" % p.stderr.strip().splitlines()[0])
sim.done()
