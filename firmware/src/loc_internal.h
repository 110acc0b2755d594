/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What the pose correction's two halves share: loc_tick.c (its state, the tick's side)
 * and localize.c (the background loop's). Internal to the core.
 */
#ifndef SLAM_LOC_INTERNAL_H
#define SLAM_LOC_INTERNAL_H

#include <stdint.h>

#include "slam/localize.h"

/* How far from the grid's origin a held-back hit reaches, either way: a grid's length and
 * more beyond any side. */
#define LOC_REACH_CELLS 512u
_Static_assert(SLAM_GRID_A <= LOC_REACH_CELLS / 2u && SLAM_GRID_B <= LOC_REACH_CELLS / 2u,
               "a held-back hit reaches a grid's length beyond the grid");

/** One more in a counter that stops at UINT32_MAX. */
void loc_count(uint32_t *c);

#endif /* SLAM_LOC_INTERNAL_H */
