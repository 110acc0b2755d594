/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The handover of the pose correction (localize.h) from the background loop to the tick:
 * what the loop publishes after each reading, which the tick adopts with the next one
 * (loc_adopt()). loc_tick.c also sets the whole state up (loc_init()).
 *
 * Internal to the core. Above loc_filter.h and loc_hold.h.
 */
#ifndef SLAM_LOC_TICK_H
#define SLAM_LOC_TICK_H

#include <stdint.h>

#include "slam/localize.h"

/** Background loop: what the tick adopts once the reading just mapped counts as finished
 *  (readq_done()): correction @p corr, and the obstacle ahead @p ahead (loc_hold_ahead()). */
void loc_tick_publish(loc_tick_t *t, const loc_corr_t *corr, const int32_t ahead[2]);

#endif /* SLAM_LOC_TICK_H */
