/* SPDX-License-Identifier: MIT */
/* The configuration of the tests' scripted worlds: the robot starts at the world's origin. */
#ifndef TEST_WORLD_ORIGIN_H
#define TEST_WORLD_ORIGIN_H

#include "slam/config.h"

/* slam_config_default() with the start pose at (0, 0), where these tests' walls, scripted
 * poses and expected cells put it (the default start is half a cell off, SLAM_START_UM, so
 * that the grid's lines lie on whole multiples of L; (0, 0) is then the centre of the start
 * cell just as well). */
static inline void test_config_default(slam_config_t *c)
{
    slam_config_default(c);
    c->start_x_um = 0;
    c->start_y_um = 0;
}

#endif
