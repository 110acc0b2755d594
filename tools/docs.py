#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""make docs, make docs-check: the READMEs' generated figures, made again from the build.

usage: tools/docs.py HOST_SIM [--check]

A generated block of a Markdown page lies between `<!-- figures: NAME -->` and
`<!-- /figures -->`; each NAME has a generator below that runs the simulator and returns
the block's text and the pictures it draws. Without --check the blocks and pictures are
rewritten in place. With --check they are made in a temporary folder and compared with
the committed ones: text exactly, except the line of wall time and speed, which follows
the machine; pictures byte for byte (tools/plot_run.py renders with matplotlib's Agg
backend and no version in the file, so the same build on the same Debian draws the same
bytes). The simulator is deterministic: the same build gives the same numbers.

Generators:
  make-sim   README.md: what `make sim` prints; host_sim/figures/default_room.png, its
             figure.png (the README's first picture)
Exit status: 0 up to date (or rewritten); 1 --check found a difference, or a run failed;
2 bad options.
"""
import difflib
import filecmp
import os
import re
import shutil
import subprocess
import sys
import tempfile

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = re.compile(r"(<!-- figures: ([a-z0-9-]+) -->\n)(.*?)(<!-- /figures -->)", re.S)
WALL_TIME = re.compile(r"in [0-9.]+ s of wall time: [0-9]+x real time")


class Failed(Exception):
    pass


def make_sim(host_sim, work):
    """host_sim as make sim runs it (the default room, robot and options): its summary as
    README.md shows it, and its figure."""
    out = os.path.join(work, "sim")
    p = subprocess.run([host_sim, "--out", out], cwd=SRC, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise Failed("host_sim --out %s exited %d:\n%s" % (out, p.returncode, p.stderr))
    text = p.stdout.replace(out, "out/sim").replace(SRC + "/", "").lstrip("\n")
    block = "```\n%s```\n" % text
    return {"README.md": block}, {"host_sim/figures/default_room.png":
                                  os.path.join(out, "figure.png")}


GENERATORS = {"make-sim": make_sim}


def blocks_of(page):
    with open(os.path.join(SRC, page), encoding="utf-8") as f:
        return f.read()


def main(argv):
    if not argv or argv[0] in ("-h", "--help") or len(argv) > 2 or \
            (len(argv) == 2 and argv[1] != "--check"):
        print(__doc__.strip())
        return 0 if argv and argv[0] in ("-h", "--help") else 2
    host_sim = os.path.abspath(argv[0])
    check = len(argv) == 2
    if not os.access(host_sim, os.X_OK):
        print("docs.py: %s is not a program (build host_sim first)" % host_sim, file=sys.stderr)
        return 2
    work = tempfile.mkdtemp(prefix="slam-docs-")
    stale = []
    try:
        texts, pictures = {}, {}
        for name, gen in GENERATORS.items():
            t, pics = gen(host_sim, work)
            for page, block in t.items():
                texts[(page, name)] = block
            pictures.update(pics)
        pages = sorted({page for page, _ in texts})
        for page in pages:
            old = blocks_of(page)
            found = {m.group(2) for m in BLOCK.finditer(old)}
            for (p, name) in texts:
                if p == page and name not in found:
                    raise Failed("%s has no <!-- figures: %s --> block" % (page, name))

            def fill(m, page=page):
                return m.group(1) + texts.get((page, m.group(2)), m.group(3)) + m.group(4)
            new = BLOCK.sub(fill, old)
            if WALL_TIME.sub("", new) != WALL_TIME.sub("", old):
                stale.append(page)
                if check:
                    sys.stdout.writelines(difflib.unified_diff(
                        old.splitlines(True), new.splitlines(True), page + " (committed)",
                        page + " (made now)"))
                else:
                    with open(os.path.join(SRC, page), "w", encoding="utf-8") as f:
                        f.write(new)
        for dest, made in sorted(pictures.items()):
            path = os.path.join(SRC, dest)
            if os.path.exists(path) and filecmp.cmp(path, made, shallow=False):
                continue
            stale.append(dest)
            if not check:
                shutil.copyfile(made, path)
    except (Failed, OSError) as e:
        print("docs.py: %s" % e, file=sys.stderr)
        return 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if check:
        if stale:
            print("docs.py: out of date: %s (make docs makes them again)" % ", ".join(stale))
            return 1
        print("docs.py: the generated figures are up to date (%s)" % ", ".join(GENERATORS))
        return 0
    print("docs.py: %s" % ("rewrote " + ", ".join(stale) if stale else "nothing to change"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
