/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Wheel speed control (paper §III.B): each wheel follows a target speed through an
 * acceleration limit, with a feed-forward duty plus a PI correction from its encoder.
 *
 * Speeds are in µm per control tick (10 ms): 1 mm/s is 10 µm/tick. Each tick the set
 * speed of a wheel moves toward its target by at most the acceleration limit, and the
 * duty is
 *
 *     duty = v_set · 1000 / v_top  +  (kp · ē + ki · Σe) / 256
 *
 * clamped to ±HAL's full scale (1000), where e = v_set − v_measured this tick and ē is its
 * mean over the last MOTION_SPEED_TICKS ticks: one encoder count is 0.3 mm, a large step
 * of a 2 mm-per-tick speed, so the proportional part works on a smoothed speed while the
 * integral part (a position error, which counts do not blur) takes every count. The acceleration
 * limit is what the paper's Fig. 6 is about: a robot that accelerates hard slips, and its odometry
 * drifts more.
 */
#ifndef SLAM_MOTION_H
#define SLAM_MOTION_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/odometry.h"

/** Full-scale duty (the HAL's HAL_DUTY_MAX). */
#define MOTION_DUTY_MAX 1000

/** A wheel stalls when it turns at under a quarter of its set speed, set at least this
 *  fast (µm/tick), for MOTION_STALL_TICKS ticks in a row: pushing against something. So
 *  does the body, both wheels asked one way, going under a quarter of their mean. */
#define MOTION_STALL_MIN_UM_TICK 300
#define MOTION_STALL_TICKS 25u
/** After this many of those ticks the wheel is driven by its feed-forward alone. */
#define MOTION_DEAD_TICKS 5u

/** Ticks the proportional part averages the speed error over (a power of two). */
#define MOTION_SPEED_TICKS 4u

/** Speed control state, per wheel (ODOM_LEFT, ODOM_RIGHT). */
typedef struct {
    int32_t target_um_tick[2];                  /**< where each wheel speed is going */
    int32_t set_um_tick[2];                     /**< the ramped set speed */
    int32_t integral_um[2];                     /**< Σ(set − measured), clamped */
    int32_t err_um_tick[2][MOTION_SPEED_TICKS]; /**< the last speed errors */
    int32_t err_sum[2];                         /**< their sum */
    uint8_t err_pos;                            /**< where the next error goes */
    int32_t accel_um_tick2;                     /**< the most the set speed changes in one tick */
    int32_t top_um_tick;                        /**< wheel speed at full duty */
    int32_t kp_q8;                              /**< duty per µm/tick of error, Q8 */
    int32_t ki_q8;                              /**< duty per µm of accumulated error, Q8 */
    int32_t integral_max_um; /**< |Σe| limit: the integral term alone stays in range */
    uint16_t slow_ticks[2];  /**< ticks in a row below a quarter of the set speed */
    uint16_t body_slow;      /**< the same for the body, both wheels asked one way */
} motion_t;

/** Start at rest with the gains and limits of a checked configuration. */
void motion_init(motion_t *m, const slam_config_t *cfg);

/**
 * Set the target speed of both wheels (the ramp and the control follow).
 * @param left_mm_s, right_mm_s  target wheel speeds in mm/s, forward positive; clamped
 *                               to the top speed
 */
void motion_set_target(motion_t *m, int32_t left_mm_s, int32_t right_mm_s);

/**
 * One control step. ISR-safe, O(1).
 * @param odom     the odometry after this tick's step: its last wheel travel is the measure
 * @param periods  control periods that travel took, 1 unless ticks were lost (at least 1)
 * @param duty     out: the duty for each motor, -1000 .. 1000
 */
void motion_step(motion_t *m, const odom_t *odom, uint32_t periods, int16_t duty[2]);

/** Whether a wheel or the body has stalled (see MOTION_STALL_TICKS); cleared when it
 *  moves again. */
bool motion_stalled(const motion_t *m);

/** Whether one wheel has stalled while the other turns as asked: not a body held against
 *  something (that stops both), but a wheel or an encoder that stopped on its own. */
bool motion_one_wheel(const motion_t *m);

/**
 * Whether both ramps are at rest: set speeds zero, so motion_step() returns zero duties
 * from now until a target changes. A zero duty alone is not rest (the PI part can cancel
 * the feed-forward for a tick while the ramp still asks for speed). ISR-safe, O(1).
 */
static inline bool motion_at_rest(const motion_t *m)
{
    return (m->set_um_tick[0] | m->set_um_tick[1]) == 0;
}

#endif /* SLAM_MOTION_H */
