#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/check_layers.py fails on a cycle: a small source tree built here, with a folder
whose files call each other in a cycle, one whose files call only downward, and one whose
object is missing.

usage: test_check_layers.py SRC_ROOT CC NM
"""
import os
import subprocess
import sys
import tempfile

ROOT, CC, NM = sys.argv[1:4]
CHECK = os.path.join(ROOT, "tools", "check_layers.py")
failures = 0


def check(ok, what):
    global failures
    print("%s: %s" % ("ok" if ok else "FAILED", what))
    failures += 0 if ok else 1


def tree(base, files):
    """Writes src/<path> for each file and builds it to obj/src/<path>.o."""
    objects = []
    for path, text in files.items():
        c = os.path.join(base, "src", path)
        os.makedirs(os.path.dirname(c), exist_ok=True)
        with open(c, "w") as f:
            f.write(text)
        o = os.path.join(base, "obj", "src", path + ".o")
        os.makedirs(os.path.dirname(o), exist_ok=True)
        subprocess.run([CC, "-c", c, "-o", o], check=True)
        objects.append(o)
    return os.path.join(base, "src"), objects


def run(src, objects):
    return subprocess.run(["/usr/bin/python3", CHECK, src, ";".join(objects), "--nm", NM],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


LAYERED = {
    "flat.c": "int flat(void) { return 1; }\n",  # a single-file module: not a folder's
    "down/top.c": "int mid(void);\nint top(void) { return mid() + 1; }\n",
    "down/mid.c": "int low(void);\nint mid(void) { return low() + 1; }\n",
    "down/low.c": "static int own(void) { return 1; }\nint low(void) { return own(); }\n",
    "down/deep/self.c": "int self(int n) { return n > 0 ? self(n - 1) : 0; }\n",
}
# A folder within a module calling back into it closes a cycle too.
NESTED = {
    "down/low.c": "int self(int n);\nint low(void) { return self(2); }\n",
    "down/deep/self.c": "int top(void);\nint self(int n) { return n > 0 ? self(n - 1) : top(); }\n",
}
CYCLE = {
    "loop/a.c": "int loop_b(void);\nint loop_a(void) { return loop_b(); }\n",
    "loop/b.c": "int loop_c(void);\nint loop_b(void) { return loop_c(); }\n",
    "loop/c.c": "extern int loop_a_count;\nint loop_a(void);\n"
                "int loop_c(void) { return loop_a_count; }\n",
    "loop/d.c": "int loop_a_count = 3;\nint loop_a(void);\nint loop_d(void) { return loop_a(); }\n",
}

with tempfile.TemporaryDirectory(prefix="check-layers-") as tmp:
    src, objects = tree(os.path.join(tmp, "good"), LAYERED)
    p = run(src, objects)
    check(p.returncode == 0, "files that call only downward pass (exit %d)" % p.returncode)
    check("1: mid.c; 2: top.c)" in p.stdout,
          "their layers are printed, bottom first: %r" % p.stdout.strip())
    check("down: 4 files in 3 layers" in p.stdout and "0: deep/self.c low.c;" in p.stdout,
          "a folder within a module's folder is part of the module")

    src, objects = tree(os.path.join(tmp, "bad"), dict(LAYERED, **CYCLE))
    p = run(src, objects)
    check(p.returncode == 1, "a cycle fails (exit %d)" % p.returncode)
    check("loop: a cycle: a.c -> b.c -> c.c -> d.c -> a.c" in p.stdout,
          "the cycle is named, a reference to data counting as a call: %r" % p.stdout.strip())
    check("c.c calls d.c (loop_a_count)" in p.stdout, "with the symbol that closes it")
    check("down: 4 files in 3 layers" in p.stdout, "the other folders are still reported")

    src, objects = tree(os.path.join(tmp, "nested"), dict(LAYERED, **NESTED))
    p = run(src, objects)
    check(p.returncode == 1 and
          "down: a cycle: deep/self.c -> top.c -> mid.c -> low.c -> deep/self.c" in p.stdout,
          "a cycle through a folder within the module is found: %r" % p.stdout.strip())

    src, objects = tree(os.path.join(tmp, "bad2"), dict(LAYERED, **CYCLE))
    p = run(src, [o for o in objects if not o.endswith("b.c.o")])
    check(p.returncode == 2 and "loop/b.c: no object" in p.stderr,
          "a source without its object is bad input (exit %d): %r"
          % (p.returncode, p.stderr.strip()))

sys.exit(1 if failures else 0)
