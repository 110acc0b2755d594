# SPDX-License-Identifier: MIT
"""What the host-side tools share: one error type (errors), one PGM/YAML map reader
(pgm), the robot's link (link), host_sim runs and their statistics (runs), the scorer
(mapscore), UMBmark's calibration (umbmark), the generated rooms (roomgen, furnish,
roomfile), the tools of any Cortex-M image (cortex_m) and of the STM32F4 (stm32f4), and one
command line over several modules (commands). The scripts in tools/ are thin command lines
over it; tools/README.md says how to write one."""
