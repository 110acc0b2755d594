# SPDX-License-Identifier: MIT
"""UMBmark's calibration of odometry (Borenstein & Feng 1996): the runs file read, the
centres of gravity, E_d and E_b by the first-order formulas and the exact model, and the
calibration lines written or applied. tools/umbmark.py's --help gives every formula and
its source; tools/calibrate_sim.py runs the whole procedure on the simulated robot."""
import math
import os
import tempfile

from . import link
from .errors import ToolError

RUNS_EACH_WAY = 5  # B&F drive five runs each way
CAL_RANGE = (0.5, 1.5)  # what slam_config_check() accepts for cal_left, cal_right, cal_base
HEADER = "direction,x_mm,y_mm"


def template(n=RUNS_EACH_WAY):
    lines = ["# UMBmark return errors, one line per run: the true final position minus the",
             "# position odometry computed, mm, in the frame of the start pose (x ahead along",
             "# the start heading, y to its left). Measure the point midway between the wheels.",
             HEADER]
    lines += ["cw,," for _ in range(n)] + ["ccw,," for _ in range(n)]
    return "\n".join(lines) + "\n"


def number(text, what, where):
    """A decimal number, by the rule every tool reads numbers with (link.parse_real)."""
    try:
        return link.parse_real(text, what="%s: %s" % (where, what))
    except link.NumberError as e:
        raise ToolError(str(e)) from None


def read_runs(path):
    """{'cw': [(x, y), ...], 'ccw': [...]} from a runs file, mm."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise ToolError("%s: cannot read: %s" % (path, getattr(e, "strerror", None) or e))
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
                raise ToolError("%s: the header must come before the runs" % where)
            continue
        seen_data = True
        if len(fields) != 3:
            raise ToolError("%s: expected 'cw|ccw,x_mm,y_mm', got '%s'" % (where, line))
        direction = fields[0].lower()
        if direction not in runs:
            raise ToolError("%s: direction '%s' is neither cw nor ccw" % (where, fields[0]))
        if not fields[1] or not fields[2]:
            raise ToolError("%s: the run's x_mm and y_mm are missing (measure them)" % where)
        runs[direction].append((number(fields[1], "x_mm", where), number(fields[2], "y_mm", where)))
    for d, other in (("cw", "ccw"), ("ccw", "cw")):
        if not runs[d]:
            raise ToolError("%s: no %s runs (and %d %s): UMBmark needs runs in both directions; "
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
        raise ToolError("%s: cannot read: %s" % (path, getattr(e, "strerror", None) or e))
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
            raise ToolError("%s:%d: expected 'key = value', got '%s'" % (path, no, line))
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
        raise ToolError("the return errors mean turns wrong by %.0f deg and legs curving by %.0f deg: "
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
            raise ToolError("the correction would make %s %.4f, outside %g..%g: the errors are too "
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
    return float(next(f.default for f in link.FIELDS if f.name == key))


def calibrate(runs_path, config=None, side_mm=None, base_mm=None):
    """The analysis of a runs file with the robot's configuration: (figures, text)."""
    cfg = read_config(config) if config else {}
    if side_mm is None:
        if not config:
            raise ToolError("the side of the square is unknown: give --side-mm, or --config with "
                      "the robot's configuration")
        side_mm = cfg.get("square_side_um", firmware_default("square_side_um")) / 1000.0
    if base_mm is None:
        base_mm = cfg.get("wheel_base_um", firmware_default("wheel_base_um")) / 1000.0
    if side_mm <= 0 or base_mm <= 0:
        raise ToolError("the side of the square and the wheel base must be positive")
    cal = tuple(cfg.get(k, 1.0) for k in ("cal_left", "cal_right", "cal_base"))
    runs = read_runs(runs_path)
    try:
        a = analyse(runs, side_mm, base_mm, cal)
    except ToolError as e:
        raise ToolError("%s: %s" % (runs_path, e))
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
        raise ToolError("%s: cannot read: %s" % (config, getattr(e, "strerror", None) or e))
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
