#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Prints the quarter-wave sine table of firmware/src/fixed.c (257 Q1.30 entries).

Entry i is round(sin(i/256 * pi/2) * 2^30). Paste the output between the table markers
in fixed.c when the table size or format changes.
"""
import math
import sys

from slamtools.errors import ToolError, main as tool_main

N = 256


def main(argv):
    if argv in (["-h"], ["--help"]):
        print(__doc__.strip())
        return 0
    if argv:
        raise ToolError("takes no arguments (--help)")
    vals = [round(math.sin(i / N * math.pi / 2) * (1 << 30)) for i in range(N + 1)]
    print("static const q1_30_t fix_sin_table[%d] = {" % (N + 1))
    for i in range(0, N + 1, 6):
        print("    " + ", ".join("%d" % v for v in vals[i:i + 6]) + ",")
    print("};")
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
