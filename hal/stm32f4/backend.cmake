# SPDX-License-Identifier: MIT
# Marks hal/stm32f4 as a backend (-DROBOT_BOARD=stm32f4, the stm32f4 preset): a bare-metal
# MCU, built with the cross toolchain; its images are tested in QEMU by tests/stm32f4.
set(SLAM_BOARD_MCU ON)
