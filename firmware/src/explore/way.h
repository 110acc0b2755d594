/* SPDX-License-Identifier: MIT */
/* The walls mode's way to the nearest frontier the robot can reach (way.c), above the
 * bottom layer and below seek.c: the tick's half (asking, reading the answer) and setting
 * up; the background loop's half is explore_way_work() in slam/explore.h. */
#ifndef SLAM_EXPLORE_WAY_H
#define SLAM_EXPLORE_WAY_H

#include "base.h"

/* No request yet; way cells sized to the run's grid and cell. */
void explore_way_init(explore_way_t *w, const explore_cfg_t *cfg);

/* Tick: ask for the way from where the robot stands (an earlier request is dropped). */
void explore_way_ask(explore_way_t *w, const odom_pose_t *pose, uint32_t now);

/* Tick: the answer to the last request, once the background loop has given it (true). */
bool explore_way_answer(const explore_way_t *w, explore_way_result_t *result, int32_t *x_um,
                        int32_t *y_um);

#endif /* SLAM_EXPLORE_WAY_H */
