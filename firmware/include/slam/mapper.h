/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Algorithm C.1 of the paper: the map update, once per control period.
 *
 *   Step 1: TM at the robot's cell += 1 (Eq. 1-2, 7): exactly one TM update a tick.
 *   Step 2: for a sonar reading completed this tick with range_min <= d < rc, OM at the
 *           obstacle cell += 1 (Eq. 3-5, 1-2, 6), using the pose at the moment of the
 *           ping, not the pose when the echo came back.
 *
 * The paper reads six readings per call; here the sweep delivers at most one a tick, so
 * every reading is mapped in the tick it completes and the work per tick stays O(1).
 *
 * In OM_MODE_EVIDENCE a reading also gives free-space evidence (grid.h): the cell the
 * robot stands on, and the cells along the beam's axis over the last 0.5 m before one cell
 * short of an echo inside the confidence sector, or before rc for an echo beyond it (nearer
 * the robot, readings from farther away cross the same cells; measured over the shipped
 * rooms, clearing the whole beam raised F1 from the true poses by 0.002, at twice the
 * cost). A timeout lowers only the robot's cell: most timeouts are walls met at grazing
 * incidence, which the beam did cross. A reading touches at most 0.5 m / L + 3 cells.
 */
#ifndef SLAM_MAPPER_H
#define SLAM_MAPPER_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/grid.h"
#include "slam/odometry.h"
#include "slam/sonar.h"
#include "slam/sweep.h"

/** What became of one reading. */
typedef enum {
    MAPPER_HIT = 0, /**< OM of the obstacle cell was incremented */
    MAPPER_FAR,     /**< d >= rc: outside the confidence sector, no hit */
    MAPPER_NEAR,    /**< d < range_min: not trusted, OM untouched */
    MAPPER_OUTSIDE, /**< the obstacle point is outside the grid, OM untouched */
    MAPPER_TIMEOUT, /**< no echo, OM untouched */
} mapper_outcome_t;

/** Mapper state and counters. */
typedef struct {
    sonar_t sonar;         /**< sensor geometry */
    uint32_t cell_um;      /**< L: a hit's beam is cleared up to one cell short of it */
    odom_pose_t ping_pose; /**< the pose when the last ping was triggered */
    uint32_t hits;         /**< readings that incremented OM */
    uint32_t far;          /**< readings with d >= rc */
    uint32_t near;         /**< readings with d < range_min */
    uint32_t outside;      /**< obstacle points outside the grid */
    uint32_t timeouts;     /**< readings without an echo */
    uint32_t cleared;      /**< OM_MODE_EVIDENCE: cells lowered by free-space evidence */
    mapper_outcome_t last; /**< outcome of the most recent reading */
    int32_t last_x_um;     /**< its obstacle point, when it had one (MAPPER_HIT, */
    int32_t last_y_um;     /**< MAPPER_OUTSIDE) */
    bool shadowed;         /**< mapper_free(): the hit lies just behind a wall OM holds */
} mapper_t;

/** Prepare the mapper for a checked configuration. */
void mapper_init(mapper_t *m, const slam_config_t *cfg);

/**
 * Algorithm C.1 for one control period. ISR-safe, O(1).
 * @param g     the grids to update
 * @param pose  the robot pose at this tick (after this tick's odometry step)
 * @param sw    what the sweep did this tick: a trigger records the pose; a completed
 *              reading is mapped with the pose recorded at its ping
 */
void mapper_tick(mapper_t *m, grid_t *g, const odom_pose_t *pose, const sweep_out_t *sw);

/**
 * Step 2 for one reading with an echo: map range d at servo angle θo seen from a pose.
 * mapper_tick() calls it; a log replay calls it directly. ISR-safe, O(1).
 * @return the outcome (also counted and kept in m->last)
 */
mapper_outcome_t mapper_reading(mapper_t *m, grid_t *g, const odom_pose_t *at_ping, bam32_t servo,
                                uint32_t range_um);

/**
 * mapper_reading() in its two halves, for a caller that holds hits back (localize.h).
 * mapper_free(): everything a reading does to OM but its hit (the free-space evidence in
 * OM_MODE_EVIDENCE) and the counts of far and near readings; MAPPER_HIT means a hit to
 * place, at (*hit_x_um, *hit_y_um), the reading's sonar_obstacle(). mapper_hit(): place it
 * (OM += 1 or the log-odds step), counted as a hit or as outside. ISR-safe, O(1).
 */
mapper_outcome_t mapper_free(mapper_t *m, grid_t *g, const odom_pose_t *at_ping, bam32_t servo,
                             uint32_t range_um, int32_t *hit_x_um, int32_t *hit_y_um);
mapper_outcome_t mapper_hit(mapper_t *m, grid_t *g, int32_t x_um, int32_t y_um);

/** mapper_hit() for a hit of which `placed` of the log-odds step is in OM already
 *  (grid_om_part(); at most om_hit, 0 in OM_MODE_COUNT): the rest, counted as one hit. */
mapper_outcome_t mapper_hit_rest(mapper_t *m, grid_t *g, int32_t x_um, int32_t y_um,
                                 uint8_t placed);

/** Whether a range is far (>= rc), near (< range_min) or a hit inside the sector. */
mapper_outcome_t mapper_classify(const mapper_t *m, uint32_t range_um);

/**
 * What a reading is, without mapping it: m->last and, for a hit inside the sector, its
 * obstacle point seen from @p at_ping (m->last_x_um, m->last_y_um). For a tick whose
 * readings are mapped later (localize.h): exploration still remembers every obstacle at
 * once. ISR-safe, O(1).
 */
void mapper_note(mapper_t *m, const odom_pose_t *at_ping, const sweep_reading_t *rd);

/**
 * A reading without an echo, seen from a pose: counted; in OM_MODE_EVIDENCE the robot's
 * cell gets free-space evidence. mapper_tick() calls it; a log replay calls it directly.
 * ISR-safe, O(1).
 */
void mapper_timeout(mapper_t *m, grid_t *g, const odom_pose_t *at_ping);

#endif /* SLAM_MAPPER_H */
