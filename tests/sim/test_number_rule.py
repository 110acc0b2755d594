#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One rule for numbers in text, in every reader: decimal only, the whole text, no blanks.

tools/slamtools/link.py's parse_int() and parse_real() against tests/data/numbers.txt (the table
tests/test_number.c holds the C rule to), then each reader given '0x10' (which strtod, and
Python's int(x, 0), read as 16) and ' 5': refused with a message, exit 2, nothing written.
"""
import os
import shutil
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
sys.path.insert(0, os.path.join(sim.src, "tools"))
from slamtools import link as slamlink  # noqa: E402

# ---- the Python rule against the shared table ---------------------------------------------
cases = 0
with open(os.path.join(sim.src, "tests", "data", "numbers.txt"), encoding="utf-8") as f:
    for line in f:
        line = line.rstrip("\n")
        if not line or line.startswith("#"):
            continue
        kind, rest = line.split("|", 1)
        text, want = rest.rsplit("|", 1)
        text = text.encode("latin-1").decode("unicode_escape").encode("latin-1").decode(
            "utf-8", errors="surrogateescape")
        parse = slamlink.parse_int if kind == "int" else slamlink.parse_real
        lo, hi = (-2**63, 2**63 - 1) if kind == "int" else (None, None)
        try:
            got = parse(text, lo, hi)
            verdict = "ok"
        except slamlink.NumberError as e:
            verdict = "range" if "out of range" in str(e) else "bad"
        expect = want if want in ("bad", "range") else "ok"
        if verdict != expect or (expect == "ok" and got != (int(want) if kind == "int" else float(want))):
            check(False, "%s %r: %s, expected %s" % (kind, text, verdict, want))
        cases += 1
check(cases >= 50, "slamlink.parse_int/parse_real follow every case of tests/data/numbers.txt (%d)"
      % cases)

# ---- every C reader refuses hexadecimal and blanks --------------------------------------
room = sim.out("hex.room")
with open(room, "w") as f:
    f.write("wall 0 0 0x10 0\nwall 0 0 0 4\nwall 16 0 16 4\nwall 0 4 16 4\nstart 1 1 0\n")
conf = sim.out("hex.conf")
with open(conf, "w") as f:
    f.write("cell_um = 0x10\n")
cal = sim.out("hex-cal.conf")
with open(cal, "w") as f:
    f.write("cal_left = 0x1p0\n")
cmds = sim.out("hex-cmds.txt")
with open(cmds, "w") as f:
    f.write("0x10 stop\n")
for args, says in [
    (["--room", room], "hex.room:1: '0x10' is not a number"),
    (["--duration", "0x10"], "--duration: '0x10' is not a decimal number"),
    (["--duration", " 5"], "--duration: ' 5' is not a decimal number"),
    (["--duration", "5 "], "--duration: '5 ' is not a decimal number"),
    (["--seed", "0x10"], "--seed: '0x10' is not a whole number"),
    (["--cell", "0x32"], "--cell: '0x32' is not a decimal number"),
    (["--start", "0x1", "1", "0"], "--start: '0x1' is not a decimal number"),
    (["--error", "noise=0x0"], "--error noise: '0x0' is not a number"),
    (["--realtime", "0x10", "--duration", "1"], "--realtime FACTOR: '0x10'"),
    (["--set", "cruise_mm_s=0x10"], "cruise_mm_s = '0x10': expected a whole number"),
    (["--set", "cruise_mm_s= 150"], "cruise_mm_s = ' 150': expected a whole number"),
    (["--set", "cal_left=0x1p0"], "cal_left = '0x1p0': expected a decimal number"),
    (["--set", "cal_left=inf"], "cal_left = 'inf': expected a decimal number"),
    (["--config", conf], "hex.conf:1: cell_um = '0x10': expected a whole number"),
    (["--calibration", cal], "hex-cal.conf:1: cal_left = '0x1p0': expected a decimal number"),
    (["--commands", cmds], "hex-cmds.txt:1: expected a time in seconds"),
]:
    out = sim.out("never")
    p = sim.run(*args, "--out", out, expect=2)
    check(says in p.stderr and not os.path.exists(out),
          "%s: exit 2, says \"%s\"" % (" ".join(args), says))

# The replay's readings.csv: a log with one number in hexadecimal.
run = sim.out("run")
sim.run("--duration", "3", "--out", run)
with open(os.path.join(run, "readings.csv")) as f:
    lines = f.read().splitlines(True)
fields = lines[1].split(",")
fields[1] = "0x41"  # servo_deg 65
lines[1] = ",".join(fields)
bad = sim.out("hexlog")
os.makedirs(bad)
shutil.copy(os.path.join(run, "config.txt"), bad)
with open(os.path.join(bad, "readings.csv"), "w") as f:
    f.writelines(lines)
p = sim.run("--replay", os.path.join(bad, "readings.csv"), "--out", sim.out("never"), expect=2)
check("readings.csv:2: malformed reading: servo_deg" in p.stderr,
      "--replay: a servo angle of 0x41 is a malformed reading")

# The tools: a SET value, umbmark's runs.
tool = os.path.join(sim.src, "tools", "telemetry.py")
for value, says in (("0x10", "is not a whole decimal number"), (" 150", "is not a whole decimal number"),
                    ("1_50", "is not a whole decimal number")):
    p = subprocess.run(["/usr/bin/python3", tool, "frame", "set", "cruise_mm_s", value],
                       capture_output=True, text=True)
    check(p.returncode == 2 and says in p.stderr and "Traceback" not in p.stderr,
          "telemetry.py frame set cruise_mm_s %r: refused (%s)" % (value, p.stderr.strip()))
p = subprocess.run(["/usr/bin/python3", tool, "send", "/dev/null", "stop", "--wait", "0x10"],
                   capture_output=True, text=True)
check(p.returncode == 2 and "'0x10' is not a decimal number" in p.stderr,
      "telemetry.py --wait 0x10: refused by argparse with the rule's words")
sim.done()
