#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The STM32F4's tools, over those of any Cortex-M image (slamtools/stm32f4/).

usage: tools/stm32f4.py COMMAND [ARGS...]         (tools/stm32f4.py COMMAND --help: its usage)
  qemu    runs the images in QEMU's STM32F405 (netduinoplus2): the self-test against the
          host build of the same replay, a boot, a run by hand
  tick    counts robot_tick()'s instructions in unicorn over the chip's memory map, and
          the HAL calls of the tick in the robot image
  bench   the image measured against its budgets: tick instructions (QEMU and unicorn),
          sizes, stack (make bench; --static-only for the ctest stm32f4_budgets)

Flashing and debugging are tools/stm32f4/flash.sh and debug.sh (make flash, make debug).
Exit status 2 for a wrong command line or input, 1 for a failure or a budget exceeded.
"""
import sys

from slamtools import commands
from slamtools.errors import main as tool_main

COMMANDS = {"qemu": "slamtools.stm32f4.qemu", "tick": "slamtools.stm32f4.tick_unicorn",
            "bench": "slamtools.stm32f4.bench_arm"}

if __name__ == "__main__":
    tool_main(commands.run, __doc__, COMMANDS, sys.argv)
