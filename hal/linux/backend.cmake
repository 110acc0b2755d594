# SPDX-License-Identifier: MIT
# Marks hal/linux as a backend (-DROBOT_BOARD=linux): a Raspberry-Pi-class robot, built with
# the machine's own compiler, with the tests and the benchmark.
set(SLAM_BOARD_MCU OFF)
