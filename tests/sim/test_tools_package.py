#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The tools' common ground: every script of tools/ starts with Debian's python3, sits in
tools/ and finds the package slamtools there without editing sys.path, and ends through
its one error rule (slamtools.errors.main); the one PGM reader refuses a malformed map with
the one error type, naming the file; a PNG's text chunk (the screenshot's digest) is
written and read back, and a file that is no whole PNG is refused."""
import os
import re
import subprocess
import sys

from simtest import Sim, check

sim = Sim()
TOOLS = os.path.join(sim.src, "tools")
sys.path.insert(0, TOOLS)
from slamtools import errors, pgm, pngtext  # noqa: E402

PATH_EDIT = re.compile(r"sys\.path(\.insert|\.append|\[|\s*=|\.extend)")
# A script's last statement: the entry point run by slamtools.errors.main, imported as
# tool_main or reached as errors.main.
ENDS_THROUGH_MAIN = re.compile(r'\nif __name__ == "__main__":\n    (tool_main|errors\.main)\([^\n]*\)\n$')
IMPORTS_MAIN = re.compile(r"^from slamtools\.errors import [^\n]*\bmain as tool_main\b|"
                          r"^from slamtools import [^\n]*\berrors\b", re.M)

scripts, modules = [], []
for folder, dirs, files in os.walk(TOOLS):
    dirs[:] = [d for d in dirs if d not in ("__pycache__", "proto")]
    for name in files:
        if name.endswith(".py"):
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, TOOLS)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            # Every file of the package is a module to import; every other one a program.
            (modules if rel.startswith("slamtools" + os.sep) else scripts).append((rel, text))

check(len(scripts) >= 20, "%d scripts found in tools/" % len(scripts))
bad = [rel for rel, text in scripts if not text.startswith("#!/usr/bin/python3\n")]
check(not bad, "every script starts with #!/usr/bin/python3: %s" % (bad or "yes"))
bad = [rel for rel, text in scripts + modules if PATH_EDIT.search(text)]
check(not bad, "no script or module of tools/ edits sys.path: %s" % (bad or "none does"))
# Python puts a script's own folder first on the path: only in tools/ does that find the
# package. A family of commands is one script over slamtools.commands (cortex_m.py).
bad = [rel for rel, _ in scripts if os.sep in rel]
check(not bad, "every script sits in tools/ itself, none in a subfolder: %s" % (bad or "yes"))
bad = [rel for rel, text in modules if '__name__ == "__main__"' in text or text.startswith("#!")]
check(not bad, "the package holds no script: %s" % (bad or "none"))
# The one error rule: a script ends through errors.main, which turns a ToolError into
# `prog: message` and its status; nothing else of tools/ ends the program itself.
bad = [rel for rel, text in scripts
       if not (ENDS_THROUGH_MAIN.search(text) and IMPORTS_MAIN.search(text))]
check(not bad, "every script ends through slamtools.errors.main: %s" % (bad or "yes"))
bad = [rel for rel, text in scripts + modules
       if "sys.exit(" in text and rel != os.path.join("slamtools", "errors.py")]
check(not bad, "no script or module but errors.py calls sys.exit: %s" % (bad or "none does"))

# One PGM reader: every malformed file is a ToolError (exit 2) that names it.
CASES = (("text.pgm", b"P2\n2 2\n255\n0 0 0 0\n"), ("short.pgm", b"P5\n4 4\n255\n\0\0"),
         ("maxval.pgm", b"P5\n2 2\n65535\n" + bytes(8)), ("header.pgm", b"P5\n2"),
         ("huge.pgm", b"P5\n65535 65535\n255\n" + bytes(4)), ("zero.pgm", b"P5\n0 3\n255\n"),
         ("empty.pgm", b""), ("comment.pgm", b"P5\n# never ends"))


def check_refused(read, cases, what):
    """Each (name, bytes) written to a file that read() refuses with a ToolError (exit 2)
    naming it."""
    for name, data in cases:
        path = sim.out(name)
        with open(path, "wb") as f:
            f.write(data)
        try:
            read(path)
            check(False, "%s: read, but it is %s" % (name, what))
        except errors.ToolError as e:
            check(e.exit_code == 2 and path in str(e), "%s refused: %s" % (name, e))


check_refused(pgm.read, CASES, "malformed")
path = sim.out("good.pgm")
with open(path, "wb") as f:
    f.write(b"P5\n# a comment\n3 2\n255\n" + bytes(range(6)))
img = pgm.read(path)
check(img.shape == (2, 3) and img[1, 2] == 5 and pgm.encode(img) == b"P5\n3 2\n255\n" + bytes(range(6)),
      "a PGM with a comment reads as 2 x 3, first row first, and writes back without it")
try:
    pgm.read(sim.out("no-such.pgm"))
    check(False, "a missing file was read")
except errors.ToolError as e:
    check(e.exit_code == 2 and "no-such.pgm" in str(e), "a missing file: %s" % e)

# A PNG's text chunk: added before IEND, read back, the picture's own chunks unchanged.
shot = os.path.join(sim.src, "tools", "web", "screenshot.png")
with open(shot, "rb") as f:
    png = f.read()
copy = sim.out("copy.png")
with open(copy, "wb") as f:
    f.write(png)
pngtext.add_text(copy, "probe", "a b c")
texts = pngtext.read_text(copy)
with open(copy, "rb") as f:
    kinds = [k for k, _, _ in pngtext.chunks(f.read(), copy)]
check(texts.get("probe") == "a b c" and "source" in texts and kinds[-2:] == [b"tEXt", b"IEND"]
      and [k for k, _, _ in pngtext.chunks(png, shot)] == kinds[:-2] + [b"IEND"],
      "a text chunk added to the screenshot reads back before its IEND: %s" % texts)
check_refused(pngtext.read_text, (("cut.png", png[:len(png) // 2]), ("text.png", b"not a png")),
              "no whole PNG")

# A tool ends on it as every tool does: `prog: message`, exit 2, no traceback.
p = subprocess.run(["/usr/bin/python3", os.path.join(TOOLS, "mapscore.py"), sim.out("short.pgm"),
                    sim.out("nowhere")], capture_output=True, text=True)
check(p.returncode == 2 and p.stderr.startswith("mapscore: ") and "Traceback" not in p.stderr,
      "mapscore.py on bad input: exit 2, one message (%s)" % p.stderr.strip())

# So do the command lines over several modules, the command named before the message.
bad_trace = sim.out("bad.trace")
with open(bad_trace, "w") as f:
    f.write("sonarslam-trace 2\n")
RUNS = ((["cortex_m.py", "trace2c", bad_trace, sim.out("scenario.c")],
         "cortex_m trace2c: %s:1: not a version 1" % bad_trace),
        (["stm32f4.py", "bench", sim.out("no-build"), "--static-only"],
         "stm32f4 bench: %s" % sim.out("no-build")),
        (["stm32f4.py", "qemu", "--bogus"], "stm32f4 qemu: unknown command"),
        (["cortex_m.py", "stack-depth", sim.out("no.elf"), "--root"],
         "cortex_m stack-depth: --root needs a value"),
        (["cortex_m.py", "flash"], "cortex_m: unknown command 'flash'"))
for argv, start in RUNS:
    p = subprocess.run(["/usr/bin/python3", os.path.join(TOOLS, argv[0])] + argv[1:],
                       capture_output=True, text=True)
    check(p.returncode == 2 and p.stderr.startswith(start) and "Traceback" not in p.stderr,
          "%s: exit 2, one message (%s)" % (" ".join(argv[:2]), p.stderr.strip()))
sim.done()
