/* SPDX-License-Identifier: MIT */
/* EXPLORE_UMBMARK: umbmark.c drives the robot through the test and robot.c hands the
 * exploration no tick meanwhile; should a tick come, the robot stands still. */
#include "modes.h"

EXPLORE_STANDING_MODE(umbmark)
