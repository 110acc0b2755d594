# SPDX-License-Identifier: MIT
"""What the tools know of any Cortex-M image, whatever its chip: an ELF reader (elf32), the
QEMU runner of the self-test and of a boot (qemu_run), the tick counted in unicorn over a
chip's memory map (unicorn_run), the stack depth of its call paths (stack_depth) and a HAL
trace as C data for the replay HAL (trace2c). tools/cortex_m.py is their command line; a
chip's own modules (slamtools/stm32f4/) give the machine and the memory map."""
