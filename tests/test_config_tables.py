#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""C, the text configuration and the Python tools agree on every configuration field
(name, order, type, default, range, telemetry key, live, words) and every exploration mode:
tests/config_view.c prints what the compiled C does with config_fields.h and
explore_modes.h, and tools/slamtools/link.py's own reading of those headers must match it.

usage: test_config_tables.py CONFIG_VIEW SOURCE_DIR [HOST_SIM]"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

if len(sys.argv) < 3:
    sys.exit(__doc__)
view, src = sys.argv[1], sys.argv[2]
host_sim = sys.argv[3] if len(sys.argv) > 3 else None
sys.path.insert(0, os.path.join(src, "tools"))
from slamtools import link as slamlink  # noqa: E402

failures = []


def check(cond, msg):
    print(("ok: " if cond else "FAIL: ") + msg)
    if not cond:
        failures.append(msg)


out = subprocess.run([view], stdout=subprocess.PIPE, text=True, check=True).stdout
grid, keys, c_fields, c_modes = None, None, [], []
for line in out.splitlines():
    kind, *cols = line.split("\t")
    if kind == "grid":
        grid = tuple(int(x) for x in cols)
    elif kind == "keys":
        keys = tuple(int(x) for x in cols)
    elif kind == "field":
        name, typ, dflt, lo, hi, key, live, words = cols
        c_fields.append(slamlink.Field(name, typ, int(dflt), int(lo), int(hi), None, int(key),
                                       int(live), words))
    elif kind == "mode":
        c_modes.append((int(cols[0]), cols[1]))

py_fields = slamlink.config_fields(grid)
check([f.name for f in c_fields] == [f.name for f in py_fields],
      "the text configuration writes the %d fields slamlink reads, in the same order"
      % len(py_fields))
for c, p in zip(c_fields, py_fields):
    bad = ["%s: C %r, slamlink %r" % (col, getattr(c, col), getattr(p, col))
           for col in ("type", "default", "lo", "hi", "id", "live", "words")
           if getattr(c, col) != getattr(p, col)]
    check(not bad, "%s: type, default, range, key, live and words agree%s"
          % (p.name, "".join("\n    " + b for b in bad)))
check(keys == (max(f.id for f in py_fields), len(py_fields)),
      "TELEM_CONFIG_KEY_MAX is the highest id, and GET knows exactly the fields' ids (%s)"
      % (keys,))
check(sorted((f.id, f.name, "I32" if f.type == "Q30" else f.type, f.live) for f in c_fields)
      == slamlink.KEYS, "slamlink.KEYS are the keys GET and SET take: (id, name, type, live)")
check(c_modes == list(enumerate(slamlink.MODES)),
      "the modes of explore_modes.h, as C numbers them, are slamlink.MODES: %s" % (c_modes,))

# Where a field's words state its whole range (no rule, nothing after the range but a note
# in brackets), the words say the table's lo and hi.
for f in py_fields:
    m = re.match(r"^(-?[\d.]+)\.\.(-?[\d.]+)( \(.*\))?$", f.words)
    if f.rule != "NONE" or m is None:
        continue
    scale = float(1 << 30) if f.type == "Q30" else 1.0
    check(float(m.group(1)) == f.lo / scale and float(m.group(2)) == f.hi / scale,
          "%s: the words '%s' give the range %d..%d" % (f.name, f.words, f.lo, f.hi))

# host_sim --commands takes every key by name and lists the modes when one is wrong: a
# file whose last line is a bad mode is refused at that line, after every key was taken.
if host_sim:
    with tempfile.TemporaryDirectory(prefix="slam-config-tables-") as work:
        cmds = os.path.join(work, "all.cmds")
        lines = ["0 get %s" % f.name for f in py_fields] + ["0 mode walls", "0 mode spiral"]
        with open(cmds, "w") as fh:
            fh.write("\n".join(lines) + "\n")
        p = subprocess.run([host_sim, "--no-plot", "--quiet", "--commands", cmds, "--out",
                            os.path.join(work, "out")], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        want = "%s:%d: mode: 'spiral' is not one of %s" % (cmds, len(lines),
                                                            ", ".join(slamlink.MODES))
        check(p.returncode == 2 and want in p.stderr,
              "host_sim --commands knows every key and the mode names: %s" % p.stderr.strip())

# A tree without the headers: a clear error that names the file, not a traceback deep
# inside the parser.
with tempfile.TemporaryDirectory(prefix="slam-config-tables-") as work:
    os.mkdir(os.path.join(work, "tools"))
    shutil.copytree(os.path.join(src, "tools", "slamtools"), os.path.join(work, "tools", "slamtools"),
                    ignore=shutil.ignore_patterns("__pycache__"))
    p = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, %r)\n"
                        "from slamtools import link" % os.path.join(work, "tools")],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    last = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
    check(p.returncode != 0 and last.startswith("slamtools.link.TableError: cannot read ") and
          "config_fields.h" in last, "slamlink away from the source tree says why: %s" % last)

if failures:
    print("%d of the checks failed" % len(failures))
    sys.exit(1)
