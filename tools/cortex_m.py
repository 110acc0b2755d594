#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The tools for any Cortex-M image, whatever its chip (slamtools/cortex_m/).

usage: tools/cortex_m.py COMMAND [ARGS...]        (tools/cortex_m.py COMMAND --help: its usage)
  qemu         runs an image in one of QEMU's machines: the self-test against the host build
               of the same replay, a boot, a run by hand (--machine NAME)
  trace2c      a HAL trace as C data for the replay HAL (the build runs it)
  stack-depth  the worst-case stack depth of an image's call paths, from GCC's own numbers

A chip's own tools (tools/stm32f4.py) name its QEMU machine and give its memory map.
Exit status 2 for a wrong command line or input, 1 for a failure while running.
"""
import sys

from slamtools import commands
from slamtools.errors import main as tool_main

COMMANDS = {"qemu": "slamtools.cortex_m.qemu_run", "trace2c": "slamtools.cortex_m.trace2c",
            "stack-depth": "slamtools.cortex_m.stack_depth"}

if __name__ == "__main__":
    tool_main(commands.run, __doc__, COMMANDS, sys.argv)
