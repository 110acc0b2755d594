/* SPDX-License-Identifier: MIT */
/**
 * @file
 * UMBmark (Borenstein & Feng 1996, §IV): the bidirectional square test that measures a
 * differential-drive robot's systematic odometry errors, driven by odometry alone.
 *
 * The robot drives umbmark_runs squares clockwise, then umbmark_runs counter-clockwise,
 * each of side square_side_um, from the configured start pose: a leg straight ahead, a
 * 90° turn in place (to the right clockwise, to the left counter-clockwise), four times,
 * so it ends facing the start heading where odometry believes the start pose is. Every run
 * starts with odometry put back at the start pose (umbmark_step() says when: the caller
 * owns odometry), because the person who measured the last run's return error has put the
 * robot back there by hand.
 *
 * Before the first run and after each one the robot stands still for umbmark_pause_s:
 * time to measure, with a tape, where it stopped, and to carry it back to the start. After
 * the last run and its pause it stays where it is (UMB_DONE).
 *
 * Legs and turns slow down over their end at the configured acceleration, to a crawl of
 * UMB_CRAWL_MM_S, and the robot comes to rest between them, so it stops within a
 * millimetre or two of where odometry meant it to: the return error a person measures is
 * then the error of odometry, not of the stop. A leg holds the odometry heading of its
 * side. Work per tick is O(1): a few multiplications, no table look-up but at a corner.
 *
 * Frames and units: the world frame of config.h; positions µm, headings binary angles.
 */
#ifndef SLAM_UMBMARK_H
#define SLAM_UMBMARK_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"
#include "slam/odometry.h"

#define UMB_CRAWL_MM_S 20   /**< the slowest wheel speed of a leg's or a turn's end */
#define UMB_STILL_TICKS 10u /**< odometry unchanged this long: the robot is at rest */

/** States of the test. */
typedef enum {
    UMB_PAUSE = 0, /**< stand still: before the first run, and after each */
    UMB_LEG,       /**< drive a side of the square */
    UMB_TURN,      /**< turn in place at a corner */
    UMB_STOP,      /**< come to rest after a leg or a turn (then u->next) */
    UMB_DONE,      /**< every run driven: stand still */
} umb_state_t;

/** The test's state. */
typedef struct {
    bool on;        /**< the configuration asks for the test (EXPLORE_UMBMARK) */
    uint8_t state;  /**< an umb_state_t */
    uint8_t run;    /**< runs begun: 0 before the first; 1..runs clockwise, then
                         counter-clockwise up to 2·runs */
    uint8_t runs;   /**< runs in each direction (umbmark_runs) */
    uint8_t legs;   /**< legs of this run driven (0..4) */
    uint8_t next;   /**< STOP: the state that follows */
    uint32_t ticks; /**< ticks in the current state (STOP: since odometry moved) */
    uint32_t pause_ticks;
    int32_t side_um;
    int32_t cruise_mm_s;
    int32_t turn_mm_s;
    uint32_t brake_q16;         /**< mm/s of wheel speed per µm left to go, Q16: the speed from
                                     which the acceleration limit stops a wheel there */
    uint32_t arc_um;            /**< a wheel's travel in a full turn in place, π·wheel base */
    int32_t stop_um;            /**< how far a wheel rolls on from a crawl: a leg or a turn
                                     ends this much early */
    odom_pose_t start;          /**< the configured start pose */
    odom_pose_t last;           /**< odometry at the last tick */
    bam32_t heading;            /**< the odometry heading of this leg, or the turn's target */
    int32_t leg_x_um, leg_y_um; /**< where this leg began (odometry) */
    q1_30_t leg_c, leg_s;       /**< cos, sin of its heading */
} umbmark_t;

/** Set up from a checked configuration: on when explore_mode is EXPLORE_UMBMARK, first
 *  the pause before the first run. */
void umbmark_init(umbmark_t *u, const slam_config_t *cfg);

/**
 * One tick of the test. ISR-safe, O(1).
 * @param odom         the odometry pose after this tick's step (what is being measured,
 *                     never a corrected pose)
 * @param target_mm_s  out: target speed of each wheel (ODOM_LEFT, ODOM_RIGHT), mm/s
 * @retval true   a run begins now: put odometry at the start pose (u->start)
 * @retval false  otherwise
 */
bool umbmark_step(umbmark_t *u, const odom_pose_t *odom, int32_t target_mm_s[2]);

/** Whether run number @p run (1..2·runs) goes clockwise. */
static inline bool umbmark_run_cw(const umbmark_t *u, uint8_t run)
{
    return run <= u->runs;
}

#endif /* SLAM_UMBMARK_H */
