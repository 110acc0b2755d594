/* SPDX-License-Identifier: MIT */
/* The robot's state as a program owns it: `size` of this object is the core's static RAM. */
#include "slam/robot.h"

robot_t bench_robot;
