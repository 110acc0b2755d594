# SPDX-License-Identifier: MIT
# Marks hal/host as a backend (-DROBOT_BOARD=host): the simulated robot, built for the PC
# with the simulator, the tests and the benchmark.
set(SLAM_BOARD_MCU OFF)
