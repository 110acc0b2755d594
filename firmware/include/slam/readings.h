/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The completed sonar readings on their way from the tick to the background loop.
 *
 * Mapping a reading can be too much work for the 10 ms tick: in OM_MODE_EVIDENCE its beam
 * clears a ray of cells, and the pose correction (localize.h) matches every few hits
 * against OM. So the tick posts each completed reading (the odometry pose of its ping, the
 * servo angle, the range) into this small single-producer, single-consumer ring, O(1), and
 * robot_idle() drains it, reading by reading:
 *
 *   1. the tick: readq_post() copies the reading in and says whether the background loop
 *      had finished every reading before it (READQ_CURRENT); if so, what the loop
 *      published after the last of them (the pose correction) is the one to adopt;
 *   2. the loop: readq_take() copies the oldest reading out and frees its slot;
 *   3. the loop maps it (through localization, or readq_map()) and publishes what the
 *      tick must know;
 *   4. the loop: readq_done() counts it finished, after what it published: the tick
 *      (an interrupt on an MCU) never sees a count whose publication is half written.
 *
 * Every backend then uses the same published results for the same reading, whenever its
 * background loop happens to run, as long as the loop finishes a reading within a
 * reading's time (readings are at least 60 ms apart). A tick that finds it behind counts
 * the reading late; a reading that finds the ring full is lost and counted.
 *
 * The queue is in use (deferred) when localization is configured or OM holds free-space
 * evidence; otherwise the tick maps each reading itself (mapper_tick()).
 */
#ifndef SLAM_READINGS_H
#define SLAM_READINGS_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/odometry.h"

#define READQ_SLOTS 8u /**< a ring of eight: seven readings wait at most */

/** A completed reading, as the tick hands it over. */
typedef struct {
    odom_pose_t ping;  /**< odometry pose at the ping */
    uint32_t range_um; /**< 0 on a timeout */
    bam32_t servo;     /**< servo angle θo */
    bool echo;         /**< false: a timeout */
} readq_reading_t;

/** What became of a posted reading. */
typedef enum {
    READQ_CURRENT = 0, /**< queued; the loop had finished every reading before it */
    READQ_LATE,        /**< queued; the loop had not: counted late */
    READQ_DROPPED,     /**< the ring was full: lost, counted dropped (and late) */
} readq_post_t;

/** The ring and its counters. */
typedef struct {
    volatile readq_reading_t slot[READQ_SLOTS];
    volatile uint8_t head;     /**< the tick writes it */
    volatile uint8_t tail;     /**< the background loop writes it */
    bool deferred;             /**< readings are mapped by robot_idle(), not the tick */
    uint32_t posted;           /**< readings the tick posted that the ring took */
    volatile uint32_t drained; /**< readings the background loop has finished */
    uint32_t dropped;          /**< readings lost: the ring was full */
    uint32_t late;             /**< readings whose tick found the background loop behind */
} readq_t;

/** Empty, and in use (deferred) when cfg->localize is set or OM holds free-space evidence. */
void readq_init(readq_t *q, const slam_config_t *cfg);

/** Tick: hand a completed reading to the background loop. ISR-safe, O(1). */
readq_post_t readq_post(readq_t *q, const readq_reading_t *rd);

/**
 * Background loop: the oldest reading, copied into @p rd, its slot free again.
 * @retval true   a reading
 * @retval false  none waits
 */
bool readq_take(readq_t *q, readq_reading_t *rd);

/** Background loop: the reading taken last is finished, and all it publishes written. */
void readq_done(readq_t *q);

/** A reading mapped as the mapper alone maps it (mapper_reading(), mapper_timeout()): the
 *  way with localization off. Not from the tick (a beam's ray). */
void readq_map(const readq_reading_t *rd, mapper_t *m, grid_t *g);

#endif /* SLAM_READINGS_H */
