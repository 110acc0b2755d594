#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Checks that every C file of the project is laid out as .clang-format says (test_format).

usage: tools/check_format.py [--fix]

Runs Debian bookworm's clang-format (14) over the .c and .h files of firmware/, hal/,
host_sim/, tests/ and tools/ and names each file it would change, with the command that
lays it out; --fix lays them out in place. A list laid out by hand stays between
`/* clang-format off */` and `/* clang-format on */`. Another major version of clang-format
lays some lines out otherwise, so the check is skipped there (exit 77, with the reason).
Exit status: 0 every file as it says, 1 files to lay out, 2 bad options or no clang-format,
77 skipped.
"""
import os
import re
import subprocess
import sys

from slamtools.errors import FAILED, ToolError, main as tool_main

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ("firmware", "hal", "host_sim", "tests", "tools")
VERSION = 14  # the clang-format .clang-format was written for
SKIPPED = 77


def c_files():
    """The project's C sources and headers, in a stable order."""
    found = []
    for top in FOLDERS:
        for root, dirs, files in os.walk(os.path.join(SRC, top)):
            dirs[:] = sorted(d for d in dirs if not d.startswith("."))
            found += [os.path.join(root, f) for f in sorted(files) if f.endswith((".c", ".h"))]
    return found


def clang_format_major():
    try:
        out = subprocess.run(["clang-format", "--version"], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True).stdout
    except OSError:
        raise ToolError("clang-format is not installed (tools/install-deps.sh test)")
    m = re.search(r"version (\d+)\.", out)
    if not m:
        raise ToolError("cannot tell clang-format's version from %r" % out.strip())
    return int(m.group(1))


def check(argv):
    if argv and argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if argv not in ([], ["--fix"]):
        raise ToolError("usage: tools/check_format.py [--fix]")
    major = clang_format_major()
    if major != VERSION:
        print("check_format: skipped: clang-format %d lays out some lines otherwise than %d, "
              "which .clang-format was written for" % (major, VERSION))
        return SKIPPED
    files = c_files()
    style = "--style=file:" + os.path.join(SRC, ".clang-format")
    if argv == ["--fix"]:
        subprocess.run(["clang-format", "-i", style] + files, check=True)
        print("check_format: laid out %d files" % len(files))
        return 0
    p = subprocess.run(["clang-format", "--dry-run", style] + files, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    bad = sorted({os.path.relpath(m.group(1), SRC)
                  for m in re.finditer(r"^(/.*?\.[ch]):\d+:\d+: (?:warning|error)", p.stdout,
                                       re.M)})
    if p.returncode != 0 and not bad:
        raise ToolError("clang-format failed:\n%s" % p.stdout.strip(), FAILED)
    if bad:
        print("check_format: %d of %d files are not laid out as .clang-format says:"
              % (len(bad), len(files)))
        for f in bad:
            print("  %s" % f)
        print("lay them out: clang-format -i FILE (or tools/check_format.py --fix)")
        return FAILED
    print("check_format: all %d C files laid out as .clang-format says" % len(files))
    return 0


if __name__ == "__main__":
    tool_main(check, sys.argv[1:])
