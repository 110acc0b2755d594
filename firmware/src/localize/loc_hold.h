/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The held-back hits of the pose correction (localize.h): a ring of the last LOC_HOLD hits
 * as points of the odometry frame (loc_hold_t). A hit enters it when heard, gives OM the
 * first half of its log-odds step when it leaves the matched window (the newest
 * LOC_WINDOW), the rest when it leaves the ring, each at the correction of that time; and
 * the newest tell exploration of the obstacle ahead that OM does not hold yet.
 *
 * Hits are numbered from 0, the oldest held, to count − 1, the newest.
 *
 * Internal to the core. Above loc_filter.h and loc_walls.h.
 */
#ifndef SLAM_LOC_HOLD_H
#define SLAM_LOC_HOLD_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/localize.h"

#ifndef LOC_WINDOW
#define LOC_WINDOW 60u /**< the newest held-back hits: what a match matches */
#endif
#define LOC_AHEAD_REACH_UM 350000 /**< held-back hits this far ahead of the axle are told */

/* How far from the grid's origin a held-back hit reaches, either way, at the least: a
 * grid's length and more beyond any side. A larger grid doubles it until it holds twice the
 * longer side (loc_hold_init()). */
#define LOC_REACH_CELLS 512u
_Static_assert(LOC_WINDOW <= LOC_HOLD && LOC_HOLD % 32u == 0u && LOC_HOLD <= UINT16_MAX,
               "shadowed holds a bit per held-back hit");

/** Empty, with the points' unit for the configured cell size. */
void loc_hold_init(loc_hold_t *h, const slam_config_t *cfg);

/** Held-back hit i where correction @p c puts it in the map, µm. */
void loc_hold_point(const loc_hold_t *h, const grid_t *g, const loc_corr_t *c, unsigned i,
                    int32_t *x, int32_t *y);

/**
 * A hit at (x, y), a point of the odometry frame (µm), held back; @p shadowed: it lies just
 * behind a wall OM holds (mapper_t's shadowed), so it is matched but never mapped. When the
 * ring is full the oldest leaves it and enters OM at correction @p corr; the hit that leaves
 * the window gives OM its early half.
 * @retval true   held
 * @retval false  a grid's length and more off the grid: counted outside, nothing held
 */
bool loc_hold_add(loc_hold_t *h, mapper_t *m, grid_t *g, const loc_corr_t *corr, int32_t x,
                  int32_t y, bool shadowed);

/** The early halves in OM, those of the held-back hits past the window: taken out where
 *  they lie, or put back at correction @p corr, where they then lie. */
void loc_hold_halves(loc_hold_t *h, grid_t *g, const loc_corr_t *corr, bool take_back);

/** Every held-back hit into OM at correction @p corr; the ring is empty after. */
void loc_hold_flush(loc_hold_t *h, mapper_t *m, grid_t *g, const loc_corr_t *corr);

/** The obstacle ahead of the robot at odometry pose @p ping among the hits OM does not hold
 *  yet (localize.h's overview says which), in the map frame under @p corr, into @p pt:
 *  {LOC_AHEAD_NONE, 0} when none. */
void loc_hold_ahead(const loc_hold_t *h, const grid_t *g, const loc_corr_t *corr,
                    const odom_pose_t *ping, int32_t pt[2]);

#endif /* SLAM_LOC_HOLD_H */
