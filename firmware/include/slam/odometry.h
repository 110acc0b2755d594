/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Pose tracking by wheel odometry (paper §III, Eq. 8-12).
 *
 * Each control period the two encoder counters are read; their differences give the
 * distances dU_g (left) and dU_d (right) the wheels rolled, and
 *
 *     dΨ = (dU_d − dU_g) / 2h          (Eq. 8, 2h = wheel base)
 *     dU = (dU_d + dU_g) / 2           (Eq. 9)
 *     X += dU · cos(Ψ + dΨ/2)          (Eq. 10, midpoint heading)
 *     Y += dU · sin(Ψ + dΨ/2)          (Eq. 11, the paper's typo fixed)
 *     Ψ += dΨ                          (Eq. 12)
 *
 * Encoder counters are the raw 16-bit hardware counters; a step takes the wrapped
 * difference, so a counter may roll over freely as long as a wheel turns fewer than
 * 32768 counts in one period. Each wheel's distance per count includes its UMBmark
 * correction (c_L, c_R), and the wheel base its correction E_b (Borenstein & Feng).
 *
 * Positions are accumulated in Q48.16 µm and the heading as a binary angle with 16 more
 * fraction bits, so 10 ms steps of a slow robot never truncate; the pose seen by the rest
 * of the core is whole micrometres (odom_pose()). The gains per encoder count are exact
 * rationals of the configuration, computed once at odom_init().
 *
 * Positions wrap as the heading does: modulo 2^64 inside and modulo 2^32 µm (±2147 m) in
 * the pose, so differences of nearby poses stay exact and no encoder glitch, however
 * large or long, leads to undefined behaviour; a pose beyond ±2147 m reappears on the
 * other side, far outside any grid.
 */
#ifndef SLAM_ODOMETRY_H
#define SLAM_ODOMETRY_H

#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"

/** A pose in the world frame, as the mapper uses it. */
typedef struct {
    int32_t x_um;    /**< wheel-axle centre, µm */
    int32_t y_um;    /**< wheel-axle centre, µm */
    bam32_t heading; /**< Ψ, counter-clockwise from +x */
} odom_pose_t;

/** Odometry state. */
typedef struct {
    q48_16_t x_um;             /**< X, Q48.16 µm */
    q48_16_t y_um;             /**< Y, Q48.16 µm */
    uint64_t heading_q16;      /**< Ψ: a binary angle in bits 16..47, fraction below */
    uint16_t last_count[2];    /**< encoder counters at the previous step (left, right) */
    int32_t step_um[2];        /**< how far each wheel rolled in the last step, µm */
    q48_16_t um_per_count[2];  /**< calibrated wheel travel per count, Q48.16 µm */
    q48_16_t bam_per_count[2]; /**< heading change per count of one wheel, Q48.16 */
} odom_t;

/** Wheel indices, shared with the HAL's encoder and motor numbering. */
enum { ODOM_LEFT = 0, ODOM_RIGHT = 1 };

/**
 * Start tracking at the configured start pose.
 * @param cfg           a configuration that passed slam_config_check()
 * @param left, right   the encoder counters now (the reference for the first step)
 */
void odom_init(odom_t *o, const slam_config_t *cfg, uint16_t left, uint16_t right);

/**
 * Put the pose somewhere (the start pose, when the robot has been put back there); the
 * gains and the counters' reference stay: the next step counts from the last. ISR-safe.
 */
void odom_set_pose(odom_t *o, const odom_pose_t *p);

/**
 * One odometry step from the encoder counters now (Eq. 8-12). ISR-safe, O(1).
 * @param left, right  raw 16-bit counters, increasing when the wheel rolls forward
 */
void odom_step(odom_t *o, uint16_t left, uint16_t right);

/** The current pose, rounded to whole micrometres. */
odom_pose_t odom_pose(const odom_t *o);

/**
 * UMBmark correction factors from measured systematic errors (Borenstein & Feng 1996).
 * @param e_d     E_d = D_R / D_L, the ratio of the actual wheel diameters, Q1.30
 * @param c_left  out: c_L = 2 / (E_d + 1), Q1.30
 * @param c_right out: c_R = 2 / (1/E_d + 1), Q1.30
 * Put c_L and c_R in cal_left/cal_right and the measured E_b in cal_base.
 */
void odom_umbmark_factors(q1_30_t e_d, q1_30_t *c_left, q1_30_t *c_right);

#endif /* SLAM_ODOMETRY_H */
