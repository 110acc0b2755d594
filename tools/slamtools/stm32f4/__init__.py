# SPDX-License-Identifier: MIT
"""The STM32F4's tools over slamtools/cortex_m/: its QEMU machine (qemu), its memory map in
unicorn and the HAL calls of the tick counted there (tick_unicorn), and the image measured
against its budgets (bench_arm). tools/stm32f4.py is their command line."""
