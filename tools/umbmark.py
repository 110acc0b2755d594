#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""UMBmark: odometry's systematic errors from the return errors measured with a tape,
and the calibration that corrects them.

usage: tools/umbmark.py RUNS.csv [--config FILE [--apply]] [--side-mm MM] [--base-mm MM]
                        [--out FILE]
       tools/umbmark.py --template [N]

RUNS.csv holds one line per run of the bidirectional square test (the robot's
EXPLORE_UMBMARK, the CALIBRATE command): `direction,x_mm,y_mm`, direction cw or ccw, and
the return error as Borenstein and Feng define it, the true final position minus the
position odometry computed (epsilon = abs - calc), in mm, in the frame of the start pose:
x ahead along the start heading, y to its left. A header line `direction,x_mm,y_mm`,
blank lines and `#` comments are allowed. `--template` prints one to fill in.

The side L of the square and the nominal wheel base b come from --config (the robot's
robot.conf, or host_sim's config.txt: square_side_um and wheel_base_um; a key the file
does not set is the firmware's default, which the robot ran with), or --side-mm and
--base-mm. --config also gives the calibration in force during the runs (cal_left,
cal_right, cal_base): the new one corrects what is left on top of it.

Written (to stdout, or to --out FILE): the figures as `#` comments and the correction as
`key = value` lines, cal_left, cal_right and cal_base, which host_sim --calibration or
--config, and the Linux robot's robot.conf read. --apply also writes them into the
--config file itself, in place of its own cal_ lines (added before its first [section]
where it has none), every other line as it was: the calibration the robot's next run uses.
Exit status: 0 done; 1 the output could not be written; 2 bad input (file:line).

How, with sources. B&F: Borenstein & Feng, "Measurement and correction of systematic
odometry errors in mobile robots", IEEE Trans. Robotics and Automation 12(6), 869-880,
1996: its UMBmark section (the bidirectional square path) and its section on correcting
Type A and Type B errors. WAI: the same method in Borenstein, Everett & Feng, "Where am I?
Sensors and methods for mobile robot positioning", 1996, chapter 5 "Dead-reckoning"
(Fig. 5.9 draws both error types). The formulas are numbered [1] to [8] below, each with
the part of the sources it comes from (the code cites these numbers); where a formula is
this tool's own, it says so.

1. The return error of a run, eps = abs - calc; the centres of gravity of the n runs each
   way, x_cg,cw = (1/n) sum eps_x,cw and so on; their distances from the origin
   r_cg = sqrt(x_cg^2 + y_cg^2); the measure of systematic error
   E_max,syst = max(r_cg,cw, r_cg,ccw)  [1] (B&F's UMBmark section, and WAI's).
2. Type A error alpha: what each nominal 90-degree turn lacks (rad), caused by the wheel
   base, the same sign both ways; Type B error beta: the heading a straight leg gains,
   caused by unequal wheels, a left turn both ways (B&F, correction section; WAI Fig. 5.9).
   To first order, in the frame above, a left (ccw) turn positive, the robot turning
   90 - alpha degrees where odometry turns 90:
       cw:   x = -2L(alpha + beta),  y = -2L(alpha + beta)
       ccw:  x = -2L(alpha - beta),  y = +2L(alpha - beta)
   (each small rotation d at a point p moves the end point e by d * J(e - p); the turns at
   the three corners, and each leg's curvature at its middle: this tool's derivation,
   checked against the simulated robot by the tests). Solved with x, these are B&F's
   alpha = (x_cg,cw + x_cg,ccw) / (-4L)  [2]  and  beta = (x_cg,cw - x_cg,ccw) / (-4L)  [3]
   (B&F, correction section; WAI pp. 140-141);
   with y, by the same geometry (this tool's),
   alpha = (y_cg,cw - y_cg,ccw) / (-4L),  beta = (y_cg,cw + y_cg,ccw) / (-4L).
   The mean of the two is the least-squares solution of all four to first order: their
   second-order terms, as large as a fifth of alpha for a 1.5 m square, largely cancel,
   but not wholly (in the simulator, E_b 1.03094 for a robot of 1.03 without slip or
   noise: a 0.09 % error that every turn of a long run adds up).
   So the tool then solves the same model exactly  [8] (this tool's): each leg an arc of
   length L whose heading turns by beta, each of the three corners a turn of 90 - alpha
   degrees; the alpha and beta whose four end coordinates (x and y, cw and ccw) best fit
   the two centres of gravity in least squares, by Gauss-Newton from the first-order
   solution. The first-order figures are printed beside it.
3. From the exact alpha and beta: the radius of a curved leg  R = (L/2) / sin(beta/2)  [4]
   (an arc of length L, as [8] takes it, has R = L / beta: the same to 1e-4 for the small
   beta UMBmark measures), the wheel diameter ratio
   E_d = D_R / D_L = (R + b/2) / (R - b/2)  [5], and the wheel base error
   E_b = b_actual / b_nominal = 90 / (90 - alpha), alpha in degrees  [6] (B&F, correction
   section; WAI pp. 140-141). b here is the wheel base odometry believes after the
   correction, nominal x cal_base x E_b.
4. The correction factors of each wheel's distance per count, c_L = 2 / (E_d + 1) and
   c_R = 2 / (1/E_d + 1), which keep the mean diameter  [7] (B&F, correction section;
   firmware/include/slam/odometry.h applies them), and the wheel base times E_b. On top of
   a calibration in force (this tool's): cal_left' = cal_left c_L,
   cal_right' = cal_right c_R, cal_base' = cal_base E_b.
The signs are proven by simulation: tests/sim/test_umbmark_tool.py gives the simulated
robot a known E_d and E_b and gets them back from its own UMBmark.
"""
import sys

from slamtools import link, umbmark
from slamtools.errors import FAILED, ToolError, main as tool_main


def usage_error(msg):
    return ToolError("%s\n(tools/umbmark.py --help says how)" % msg)


def main(argv):
    args = list(argv)
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    opts = {"--config": None, "--side-mm": None, "--base-mm": None, "--out": None}
    runs = None
    do_apply = False
    i = 0
    while i < len(args):
        a = args[i]
        if a == "--apply":
            do_apply = True
            i += 1
            continue
        if a == "--template":
            n = umbmark.RUNS_EACH_WAY
            if i + 1 < len(args):
                try:
                    n = link.parse_int(args[i + 1], 1, 50, what="--template N")
                except link.NumberError as e:
                    raise usage_error(str(e))
            sys.stdout.write(umbmark.template(n))
            return 0
        if a in opts:
            if i + 1 >= len(args) or args[i + 1].startswith("--"):
                raise usage_error("%s needs a value" % a)
            opts[a] = args[i + 1]
            i += 2
            continue
        if a.startswith("-"):
            raise usage_error("unknown option '%s'" % a)
        if runs is not None:
            raise usage_error("one runs file only ('%s' and '%s')" % (runs, a))
        runs = a
        i += 1
    if runs is None:
        raise usage_error("which runs file? (tools/umbmark.py --template > runs.csv makes one)")
    if do_apply and opts["--config"] is None:
        raise usage_error("--apply writes the calibration into the --config file: give one")
    mm = {}
    for k in ("--side-mm", "--base-mm"):
        if opts[k] is not None:
            try:
                mm[k] = link.parse_real(opts[k], what=k)
            except link.NumberError as e:
                raise usage_error(str(e))
            if mm[k] <= 0:
                raise usage_error("%s must be a positive number of mm" % k)
    _, text = umbmark.calibrate(runs, opts["--config"], mm.get("--side-mm"), mm.get("--base-mm"))
    sys.stdout.write(text)
    if opts["--out"] is not None:
        try:
            umbmark.write_atomic(opts["--out"], text)
        except OSError as e:
            raise ToolError("cannot write %s: %s" % (opts["--out"], e.strerror), FAILED)
        print("# written to %s" % opts["--out"])
    if do_apply:
        new = umbmark.apply(opts["--config"], text)
        try:
            umbmark.write_keeping_mode(opts["--config"], new)
        except OSError as e:
            raise ToolError("cannot write %s: %s" % (opts["--config"], e.strerror), FAILED)
        print("# cal_left, cal_right and cal_base written into %s: its next run uses them"
              % opts["--config"])
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
