# SPDX-License-Identifier: MIT
"""Runs the STM32F4 images in QEMU's emulated STM32F405 (-M netduinoplus2).

usage:
  tools/stm32f4.py qemu selftest ELF HOST_REPLAY [--out DIR] [--tick-budget N]
      Run the self-test image, run the host build of the same replay (replay_host), and
      compare the two reports byte for byte; OM and TM are also decoded, checked against
      their CRC-32 and compared cell by cell. Prints robot_tick() instructions (mean and
      worst, from TIM2 under -icount) and fails when the worst exceeds the budget.
  tools/stm32f4.py qemu boot ELF [--status N]
      Boot the robot image, wait for its text banner and then N telemetry STATUS frames on
      USART1 (decoded by slamtools/link.py), check that the ticks advance without
      overruns and that the HELLO frame describes the grid, then stop it.
  tools/stm32f4.py qemu run ELF [--seconds S]
      Run an image for a person: USART1 and semihosting to this terminal.

The runs are slamtools/cortex_m/qemu_run.py's (tools/cortex_m.py qemu), on the machine
named here. QEMU's only STM32F4 machines (netduinoplus2, olimex-stm32-h405) are F405s: the
generic_f405 board's images. Under -icount shift=0,sleep=off TIM2-5 count one per executed
instruction.
"""
from ..cortex_m import qemu_run

MACHINE = "netduinoplus2"

parse_report = qemu_run.parse_report


def run_selftest_image(elf, out_dir, seconds=120):
    """Run the self-test image on the F405; returns (exit status, report text)."""
    return qemu_run.run_selftest_image(elf, out_dir, MACHINE, seconds)


def main(argv):
    return qemu_run.main(argv, MACHINE, __doc__)
