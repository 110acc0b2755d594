/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A match of the pose correction (localize.h): the window, the newest LOC_WINDOW held-back
 * hits, against the wall lines of OM without the hits' early halves, by a sequential Kalman
 * update iterated LOC_PASSES times; its gates (a hit's lever, the far face of a wall) and
 * its refusals (too few walls, too large a step). Counts in loc_match_t.
 *
 * Internal to the core. Above loc_filter.h, loc_walls.h and loc_hold.h.
 */
#ifndef SLAM_LOC_MATCH_H
#define SLAM_LOC_MATCH_H

#include "slam/localize.h"

#ifndef LOC_EVERY
#define LOC_EVERY 4u /**< new hits between two matches */
#endif
#ifndef LOC_PASSES
#define LOC_PASSES 3u /**< associations and updates of a match */
#endif
#ifndef LOC_MIN_POINTS
#define LOC_MIN_POINTS 10u /**< hits on a wall line a match needs */
#endif
#ifndef LOC_MAX_STEP_MDEG
#define LOC_MAX_STEP_MDEG 3000 /**< a larger turn of the pose is refused */
#endif
#ifndef LOC_MAX_STEP_UM
#define LOC_MAX_STEP_UM 150000 /**< and so is a larger shift */
#endif

/** A hit was held back from a ping at odometry pose @p ping: every LOC_EVERY of them, once
 *  the window is full, the early halves leave OM, the window is matched, and the halves go
 *  back where the correction then puts them. */
void loc_match_hit(loc_t *l, grid_t *g, const odom_pose_t *ping);

#endif /* SLAM_LOC_MATCH_H */
