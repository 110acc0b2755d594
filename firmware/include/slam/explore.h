/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Exploration (paper §II.E): where to drive next, from the sonar and the maps.
 *
 * All modes share one obstacle memory: the latest obstacle point seen at each sweep stop,
 * kept in world coordinates (so it stays right while the robot turns) and forgotten after
 * EXPLORE_MEMORY_TICKS. Something is *ahead* when one of those points lies in the corridor
 * the robot would sweep: less than avoid ahead of the sonar and less than clearance to
 * either side of the centre line.
 *
 * - EXPLORE_RANDOM, the paper's: drive straight; when something is ahead, stop and turn in
 *   place by a random 90°..180° away from it; now and then (and after driving straight
 *   too long) turn by a random angle anyway. After each turn, stand still for one sweep
 *   and look before driving on.
 * - EXPLORE_TM: the same avoidance, but each new heading (at the start, when something is
 *   ahead, and every EXPLORE_TM_REDECIDE_TICKS of driving) is the one of
 *   EXPLORE_CANDIDATES directions whose ray through TM (1 m, stopped by occupied OM cells)
 *   crosses the fewest visits, the smallest turn among equals: the trajectory map used
 *   for online path planning, as the paper says it can be. A candidate is weighed over a
 *   few ticks (about half a second for all, standing still), so every tick stays small.
 * - EXPLORE_SQUARE: square_laps counter-clockwise squares of square_side by odometry
 *   (UMBmark's path), turning in place at the corners, then stop.
 * - EXPLORE_OFF: stand still.
 *
 * In every mode but the square, wheels that stall while driving (the robot pushes
 * against something the sonar did not see: a wall at grazing incidence, or on the left
 * beyond the sweep) make the robot back off EXPLORE_BACK_UM and turn away; the point it
 * pushed against joins the obstacle memory for EXPLORE_BUMP_TICKS, so neither mode heads
 * straight back into it.
 *
 * The output is a target speed for each wheel; motion.h follows it.
 */
#ifndef SLAM_EXPLORE_H
#define SLAM_EXPLORE_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/odometry.h"
#include "slam/sweep.h"

#define EXPLORE_CANDIDATES 12u          /**< headings weighed in TM mode, 30° apart */
#define EXPLORE_MEMORY_TICKS 300u       /**< obstacle points are forgotten after 3 s */
#define EXPLORE_BUMP_TICKS 1000u        /**< a stall's point is remembered for 10 s */
#define EXPLORE_BUMP SLAM_SWEEP_STOPS_MAX /**< the memory slot of the last stall */
#define EXPLORE_FORWARD_MAX_TICKS 2000u /**< turn anyway after 20 s straight */
#define EXPLORE_RAY_CELLS 8u            /**< TM cells a DECIDE tick walks at most */
#define EXPLORE_BACK_UM 100000          /**< how far to back off after a stall */

/** States of the exploration. */
typedef enum {
    EXPLORE_STOP = 0, /**< stand still (EXPLORE_OFF, or the square is done) */
    EXPLORE_LOOK,     /**< stand still for a sweep, then decide */
    EXPLORE_DECIDE,   /**< TM mode: weigh candidate headings, one a tick */
    EXPLORE_TURN,     /**< turn in place to target_heading */
    EXPLORE_FORWARD,  /**< drive straight */
    EXPLORE_BACK,     /**< back away from what the wheels stalled against */
} explore_state_t;

/** Exploration state. */
typedef struct {
    uint8_t mode;        /**< an explore_mode_t */
    uint8_t state;       /**< an explore_state_t */
    uint8_t stops;       /**< sweep stops */
    uint8_t candidate;   /**< DECIDE: the candidate being weighed */
    uint8_t weighed;     /**< DECIDE: candidates weighed */
    uint8_t best;        /**< DECIDE: the best candidate so far */
    uint8_t ray_phase;   /**< DECIDE: 0 start the candidate's ray, 1 walk and judge it */
    uint8_t laps;        /**< SQUARE: laps to drive; 0 = forever */
    uint32_t leg;        /**< SQUARE: legs done */
    uint32_t best_cost;  /**< DECIDE: its cost */
    uint32_t ray_left;   /**< DECIDE: cells of the ray still to walk */
    uint32_t ray_cost;   /**< DECIDE: visits counted along it so far */
    int32_t ray_fx, ray_fy; /**< DECIDE: where the walk is, Q16 cells */
    int32_t ray_dx, ray_dy; /**< DECIDE: one cell along the candidate, Q16 cells */
    uint32_t rng;        /**< xorshift32 state */
    uint32_t ticks;      /**< ticks in the current state */
    uint32_t now;        /**< ticks since init */
    bam32_t target_heading;    /**< TURN: where to */
    int32_t leg_x_um, leg_y_um; /**< SQUARE: where the current leg began; BACK: the stall */
    int32_t obst_x_um[SLAM_SWEEP_STOPS_MAX + 1]; /**< obstacle memory, world µm: a slot a
                                                       stop, then EXPLORE_BUMP */
    int32_t obst_y_um[SLAM_SWEEP_STOPS_MAX + 1];
    uint32_t obst_seen[SLAM_SWEEP_STOPS_MAX + 1]; /**< `now` when seen; 0 = nothing */
    uint32_t look_readings;    /**< LOOK: readings since it began */
    bool decide;               /**< TM: the next LOOK decides a new heading */
    /* From the configuration. */
    int32_t cruise_mm_s;
    int32_t turn_mm_s;
    int32_t avoid_um;
    int32_t clearance_um;
    int32_t mount_x_um;
    int32_t mount_y_um;
    int32_t square_side_um;
    uint32_t cell_um;
    uint8_t tm_max;
    /* Counters. */
    uint32_t turns;            /**< turns begun */
    uint32_t avoidances;       /**< of which because something was ahead */
    uint32_t stalls;           /**< times the wheels stalled against something */
} explore_t;

/** Start exploring with a checked configuration; the first act is to look. */
void explore_init(explore_t *e, const slam_config_t *cfg);

/**
 * One tick of exploration. ISR-safe, O(1).
 * @param pose    the pose after this tick's odometry step
 * @param sw      what the sweep did this tick (a completed reading feeds the memory)
 * @param m       the mapper, for the sensor geometry and the pose of the reading's ping
 * @param g       the maps (TM mode reads them, at most EXPLORE_RAY_CELLS cells a tick)
 * @param stalled the wheels have stalled (motion_stalled())
 * @param target_mm_s  out: target speed of each wheel (ODOM_LEFT, ODOM_RIGHT), mm/s
 */
void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw,
                  const mapper_t *m, const grid_t *g, bool stalled, int32_t target_mm_s[2]);

/** Whether a remembered obstacle lies in the corridor ahead of a pose. */
bool explore_blocked(const explore_t *e, const odom_pose_t *pose);

#endif /* SLAM_EXPLORE_H */
