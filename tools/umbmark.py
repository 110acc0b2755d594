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
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slamlink  # noqa: E402  (the one rule for numbers)

RUNS_EACH_WAY = 5  # B&F drive five runs each way
CAL_RANGE = (0.5, 1.5)  # what slam_config_check() accepts for cal_left, cal_right, cal_base
HEADER = "direction,x_mm,y_mm"


class Bad(Exception):
    """Bad input: the message names the file and line."""


def template(n=RUNS_EACH_WAY):
    lines = ["# UMBmark return errors, one line per run: the true final position minus the",
             "# position odometry computed, mm, in the frame of the start pose (x ahead along",
             "# the start heading, y to its left). Measure the point midway between the wheels.",
             HEADER]
    lines += ["cw,," for _ in range(n)] + ["ccw,," for _ in range(n)]
    return "\n".join(lines) + "\n"


def number(text, what, where):
    """A decimal number, by the rule every tool reads numbers with (slamlink.parse_real)."""
    try:
        return slamlink.parse_real(text, what="%s: %s" % (where, what))
    except slamlink.NumberError as e:
        raise Bad(str(e)) from None


def read_runs(path):
    """{'cw': [(x, y), ...], 'ccw': [...]} from a runs file, mm."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise Bad("%s: cannot read: %s" % (path, getattr(e, "strerror", None) or e))
    runs = {"cw": [], "ccw": []}
    seen_data = False
    for no, raw in enumerate(lines, 1):
        where = "%s:%d" % (path, no)
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f.strip() for f in line.split(",")]
        if [f.lower() for f in fields] == HEADER.split(","):
            if seen_data:
                raise Bad("%s: the header must come before the runs" % where)
            continue
        seen_data = True
        if len(fields) != 3:
            raise Bad("%s: expected 'cw|ccw,x_mm,y_mm', got '%s'" % (where, line))
        direction = fields[0].lower()
        if direction not in runs:
            raise Bad("%s: direction '%s' is neither cw nor ccw" % (where, fields[0]))
        if not fields[1] or not fields[2]:
            raise Bad("%s: the run's x_mm and y_mm are missing (measure them)" % where)
        runs[direction].append((number(fields[1], "x_mm", where), number(fields[2], "y_mm", where)))
    for d, other in (("cw", "ccw"), ("ccw", "cw")):
        if not runs[d]:
            raise Bad("%s: no %s runs (and %d %s): UMBmark needs runs in both directions; "
                      "was the test cut short?" % (path, d, len(runs[other]), other))
    return runs


def read_config(path):
    """The keys of a `key = value` file this tool uses, as numbers; others are ignored."""
    wanted = {"square_side_um", "wheel_base_um", "cal_left", "cal_right", "cal_base"}
    out = {}
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise Bad("%s: cannot read: %s" % (path, getattr(e, "strerror", None) or e))
    section = None
    for no, raw in enumerate(lines, 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line  # a program's own keys (robot.conf's [linux]): not the robot's
            continue
        if section is not None:
            continue
        if "=" not in line:
            raise Bad("%s:%d: expected 'key = value', got '%s'" % (path, no, line))
        key, value = (s.strip() for s in line.split("=", 1))
        if key in wanted:
            out[key] = number(value, key, "%s:%d" % (path, no))
    return out


def centre(points):
    n = len(points)
    return sum(p[0] for p in points) / n, sum(p[1] for p in points) / n


def square_end(alpha, beta, side, turn):
    """Where the model of [8] ends a run: four legs of length side, each an arc whose
    heading turns by beta, and three corner turns of turn (+1 ccw, -1 cw) x (90 deg - alpha);
    (x, y) in the frame of the start pose, mm."""
    x = y = heading = 0.0
    for leg in range(4):
        if beta == 0.0:
            ahead, left = side, 0.0
        else:
            radius = side / beta
            ahead, left = radius * math.sin(beta), radius * (1.0 - math.cos(beta))
        x += ahead * math.cos(heading) - left * math.sin(heading)
        y += ahead * math.sin(heading) + left * math.cos(heading)
        heading += beta
        if leg < 3:
            heading += turn * (math.pi / 2.0 - alpha)
    return x, y


def exact_fit(cg_cw, cg_ccw, side, alpha, beta):
    """[8]: the alpha and beta (rad) whose model ends fit both centres of gravity in least
    squares, by Gauss-Newton from a first-order (alpha, beta); and the largest residual
    left, mm."""
    measured = cg_cw + cg_ccw

    def ends(a, b):
        return square_end(a, b, side, -1.0) + square_end(a, b, side, 1.0)

    step = 1e-7  # rad: a forward difference far above rounding, far below the angles
    for _ in range(20):
        now = ends(alpha, beta)
        res = [f - m for f, m in zip(now, measured)]
        cols = [[(f - g) / step for f, g in zip(ends(alpha + step, beta), now)],
                [(f - g) / step for f, g in zip(ends(alpha, beta + step), now)]]
        # The normal equations, 2 x 2: (J^T J) d = J^T res.
        a11 = sum(c * c for c in cols[0])
        a12 = sum(c * d for c, d in zip(cols[0], cols[1]))
        a22 = sum(d * d for d in cols[1])
        g1 = sum(c * r for c, r in zip(cols[0], res))
        g2 = sum(d * r for d, r in zip(cols[1], res))
        det = a11 * a22 - a12 * a12
        if det == 0.0:
            break
        d_alpha = (a22 * g1 - a12 * g2) / det
        d_beta = (a11 * g2 - a12 * g1) / det
        alpha -= d_alpha
        beta -= d_beta
        if abs(d_alpha) < 1e-13 and abs(d_beta) < 1e-13:
            break
    left = max(abs(f - m) for f, m in zip(ends(alpha, beta), measured))
    return alpha, beta, left


def analyse(runs, side_mm, base_mm, cal=(1.0, 1.0, 1.0)):
    """Every figure of UMBmark and the new calibration; the module docstring says how."""
    L = side_mm
    xcw, ycw = centre(runs["cw"])  # [1]
    xccw, yccw = centre(runs["ccw"])
    r_cw, r_ccw = math.hypot(xcw, ycw), math.hypot(xccw, yccw)  # [1]
    alpha_x = (xcw + xccw) / (-4.0 * L)  # [2]
    alpha_y = (ycw - yccw) / (-4.0 * L)  # the same from y (docstring, 2.)
    beta_x = (xcw - xccw) / (-4.0 * L)  # [3]
    beta_y = (ycw + yccw) / (-4.0 * L)  # the same from y (docstring, 2.)
    alpha_first = (alpha_x + alpha_y) / 2.0
    beta_first = (beta_x + beta_y) / 2.0
    if not -45.0 < math.degrees(alpha_first) < 45.0 or abs(beta_first) >= math.pi / 4:
        raise Bad("the return errors mean turns wrong by %.0f deg and legs curving by %.0f deg: "
                  "far beyond UMBmark's small angles (check the signs, the units (mm) and "
                  "the side of the square)"
                  % (math.degrees(alpha_first), math.degrees(beta_first)))
    alpha, beta, fit_mm = exact_fit((xcw, ycw), (xccw, yccw), L, alpha_first, beta_first)  # [8]
    alpha_deg = math.degrees(alpha)
    e_b = 90.0 / (90.0 - alpha_deg)  # [6]
    b = base_mm * cal[2] * e_b
    if beta == 0.0:
        radius, e_d = math.inf, 1.0
    else:
        radius = (L / 2.0) / math.sin(beta / 2.0)  # [4]
        e_d = (radius + b / 2.0) / (radius - b / 2.0)  # [5]
    c_l = 2.0 / (e_d + 1.0)  # [7]
    c_r = 2.0 / (1.0 / e_d + 1.0)  # [7]
    new = (cal[0] * c_l, cal[1] * c_r, cal[2] * e_b)
    for name, v in zip(("cal_left", "cal_right", "cal_base"), new):
        if not CAL_RANGE[0] <= v <= CAL_RANGE[1]:
            raise Bad("the correction would make %s %.4f, outside %g..%g: the errors are too "
                      "large to be a robot's (check the signs and units of the runs)"
                      % (name, v, CAL_RANGE[0], CAL_RANGE[1]))
    return {
        "n_cw": len(runs["cw"]), "n_ccw": len(runs["ccw"]), "side_mm": L, "base_mm": base_mm,
        "cg_cw": (xcw, ycw), "cg_ccw": (xccw, yccw), "r_cw": r_cw, "r_ccw": r_ccw,
        "e_max_syst": max(r_cw, r_ccw),  # [1]
        "alpha_deg": alpha_deg, "alpha_first_deg": math.degrees(alpha_first),
        "beta_first_deg": math.degrees(beta_first), "fit_mm": fit_mm,
        "alpha_x_deg": math.degrees(alpha_x),
        "alpha_y_deg": math.degrees(alpha_y),
        "beta_deg": math.degrees(beta), "beta_x_deg": math.degrees(beta_x),
        "beta_y_deg": math.degrees(beta_y),
        "radius_mm": radius, "e_d": e_d, "e_b": e_b, "c_l": c_l, "c_r": c_r,
        "cal_before": tuple(cal), "cal": new,
    }


def report(a, source):
    """The figures as comment lines, then the calibration as key = value lines."""
    radius = "straight" if math.isinf(a["radius_mm"]) else "%.1f m" % (a["radius_mm"] / 1000.0)
    few = "" if min(a["n_cw"], a["n_ccw"]) >= RUNS_EACH_WAY else \
        "  (Borenstein & Feng drive %d each way)" % RUNS_EACH_WAY
    lines = [
        "# UMBmark (Borenstein & Feng 1996): %d cw and %d ccw runs of %s%s"
        % (a["n_cw"], a["n_ccw"], source, few),
        "# square side L = %.0f mm, nominal wheel base b = %.1f mm" % (a["side_mm"], a["base_mm"]),
        "# centre of gravity cw : x %8.1f mm, y %8.1f mm, r %7.1f mm"
        % (a["cg_cw"][0], a["cg_cw"][1], a["r_cw"]),
        "# centre of gravity ccw: x %8.1f mm, y %8.1f mm, r %7.1f mm"
        % (a["cg_ccw"][0], a["cg_ccw"][1], a["r_ccw"]),
        "# E_max,syst = %.1f mm" % a["e_max_syst"],
        "# alpha = %.4f deg a 90-deg turn (first order %.4f; from x: %.4f, from y: %.4f)"
        % (a["alpha_deg"], a["alpha_first_deg"], a["alpha_x_deg"], a["alpha_y_deg"]),
        "# beta  = %.4f deg a leg (first order %.4f; from x: %.4f, from y: %.4f)"
        % (a["beta_deg"], a["beta_first_deg"], a["beta_x_deg"], a["beta_y_deg"]),
        "# the exact model fits both centres of gravity within %.1f mm" % a["fit_mm"],
        "# R = %s, E_d = D_R/D_L = %.6f, E_b = %.6f" % (radius, a["e_d"], a["e_b"]),
        "# c_L = %.6f, c_R = %.6f; in force during the runs: cal_left %.6f, cal_right %.6f, "
        "cal_base %.6f" % ((a["c_l"], a["c_r"]) + a["cal_before"]),
        "cal_left = %.6f" % a["cal"][0],
        "cal_right = %.6f" % a["cal"][1],
        "cal_base = %.6f" % a["cal"][2],
    ]
    return "\n".join(lines) + "\n"


def umask_mode():
    """The mode open() gives a new file: 0666 less the process's umask."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def write_atomic(path, text):
    """Write a whole file or nothing: a temporary file beside it, renamed over it. The file
    gets the mode open() would give it (mkstemp makes 0600, which would lock other users
    out of a shared calibration)."""
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".umbmark-", dir=d)
    try:
        os.fchmod(fd, umask_mode())
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def firmware_default(key):
    """A configuration field's default, from firmware/include/slam/config_fields.h."""
    import slamlink
    return float(next(f.default for f in slamlink.FIELDS if f.name == key))


def calibrate(runs_path, config=None, side_mm=None, base_mm=None):
    """The analysis of a runs file with the robot's configuration: (figures, text)."""
    cfg = read_config(config) if config else {}
    if side_mm is None:
        if not config:
            raise Bad("the side of the square is unknown: give --side-mm, or --config with "
                      "the robot's configuration")
        side_mm = cfg.get("square_side_um", firmware_default("square_side_um")) / 1000.0
    if base_mm is None:
        base_mm = cfg.get("wheel_base_um", firmware_default("wheel_base_um")) / 1000.0
    if side_mm <= 0 or base_mm <= 0:
        raise Bad("the side of the square and the wheel base must be positive")
    cal = tuple(cfg.get(k, 1.0) for k in ("cal_left", "cal_right", "cal_base"))
    runs = read_runs(runs_path)
    try:
        a = analyse(runs, side_mm, base_mm, cal)
    except Bad as e:
        raise Bad("%s: %s" % (runs_path, e))
    return a, report(a, runs_path)


CAL_KEYS = ("cal_left", "cal_right", "cal_base")


def apply(config, text):
    """The configuration file's text with its cal_ lines replaced by those of `text` (the
    tool's output), each where the file had it; one it lacks goes after the last line of
    the robot's own keys, before the first [section]. Comments and every other line stay."""
    new = {}
    for line in text.splitlines():
        if "=" in line and not line.startswith("#"):
            k, v = (x.strip() for x in line.split("=", 1))
            new[k] = v
    try:
        with open(config, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise Bad("%s: cannot read: %s" % (config, getattr(e, "strerror", None) or e))
    done = set()
    section_at = len(lines)
    last_key = -1
    for i, raw in enumerate(lines):
        line = raw.split("#", 1)[0].strip()
        if line.startswith("[") and line.endswith("]"):
            section_at = i
            break
        if "=" in line:
            last_key = i
            k = line.split("=", 1)[0].strip()
            if k in CAL_KEYS:
                comment = raw[len(raw.split("#", 1)[0]):]
                lines[i] = "%s = %s%s" % (k, new[k], "  " + comment if comment else "")
                done.add(k)
    missing = ["%s = %s" % (k, new[k]) for k in CAL_KEYS if k not in done]
    at = last_key + 1 if last_key >= 0 else min(section_at, len(lines))
    lines[at:at] = missing
    return "\n".join(lines) + "\n"


def write_keeping_mode(path, text):
    """write_atomic(), the file keeping the mode it had (it is the user's own file)."""
    mode = os.stat(path).st_mode & 0o7777
    write_atomic(path, text)
    os.chmod(path, mode)


def usage_error(msg):
    print("umbmark.py: %s\n(tools/umbmark.py --help says how)" % msg, file=sys.stderr)
    return 2


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
            n = RUNS_EACH_WAY
            if i + 1 < len(args):
                try:
                    n = slamlink.parse_int(args[i + 1], 1, 50, what="--template N")
                except slamlink.NumberError as e:
                    return usage_error(str(e))
            sys.stdout.write(template(n))
            return 0
        if a in opts:
            if i + 1 >= len(args) or args[i + 1].startswith("--"):
                return usage_error("%s needs a value" % a)
            opts[a] = args[i + 1]
            i += 2
            continue
        if a.startswith("-"):
            return usage_error("unknown option '%s'" % a)
        if runs is not None:
            return usage_error("one runs file only ('%s' and '%s')" % (runs, a))
        runs = a
        i += 1
    if runs is None:
        return usage_error("which runs file? (tools/umbmark.py --template > runs.csv makes one)")
    if do_apply and opts["--config"] is None:
        return usage_error("--apply writes the calibration into the --config file: give one")
    mm = {}
    for k in ("--side-mm", "--base-mm"):
        if opts[k] is not None:
            try:
                mm[k] = slamlink.parse_real(opts[k], what=k)
            except slamlink.NumberError as e:
                return usage_error(str(e))
            if mm[k] <= 0:
                return usage_error("%s must be a positive number of mm" % k)
    try:
        _, text = calibrate(runs, opts["--config"], mm.get("--side-mm"), mm.get("--base-mm"))
    except Bad as e:
        print("umbmark.py: %s" % e, file=sys.stderr)
        return 2
    sys.stdout.write(text)
    if opts["--out"] is not None:
        try:
            write_atomic(opts["--out"], text)
        except OSError as e:
            print("umbmark.py: cannot write %s: %s" % (opts["--out"], e.strerror), file=sys.stderr)
            return 1
        print("# written to %s" % opts["--out"])
    if do_apply:
        try:
            write_keeping_mode(opts["--config"], apply(opts["--config"], text))
        except Bad as e:
            print("umbmark.py: %s" % e, file=sys.stderr)
            return 2
        except OSError as e:
            print("umbmark.py: cannot write %s: %s" % (opts["--config"], e.strerror),
                  file=sys.stderr)
            return 1
        print("# cal_left, cal_right and cal_base written into %s: its next run uses them"
              % opts["--config"])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
