/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The Kalman filter of the pose correction (localize.c), in fixed point.
 *
 * The state: an increment of the correction about the robot, (dx, dy) in µm and dθ in
 * µrad, and two systematic errors of odometry the filter learns as it goes (what UMBmark
 * leaves, or what a tyre's wear brings): the heading odometry gains per millimetre driven,
 * κd in prad/mm (10⁻¹² rad; unequal wheels, E_d), and per radian turned, κt in ppb (a
 * wrong wheel base, E_b). Their units are that fine so that their Kalman gains, tiny in
 * any coarser unit, keep their precision in Q20. Between matches the correction turns by κd·distance + κt·turn, so the pose
 * follows the drift it has learned; each match corrects dθ, and through their correlation
 * with it, κd and κt (Martinelli's simultaneous localization and odometry calibration).
 *
 * The covariance is a full symmetric 5×5 matrix of int64 in the state's units. A
 * measurement's Jacobian is in Q12 (a unit normal is 4096, the θ entry in µm per µrad) and
 * never involves κ directly.
 *
 * Internal to the core; the tests check it against a double-precision filter.
 */
#ifndef SLAM_LOC_KF_H
#define SLAM_LOC_KF_H

#include <stdint.h>

#include "slam/localize.h"

/** The state's entries. */
enum { LKF_X = 0, LKF_Y, LKF_T, LKF_KD, LKF_KT, LKF_N };
_Static_assert(LKF_N == LOC_STATES, "the filter's state and loc_t's covariance differ");

#define LKF_J_SHIFT 12u               /**< Jacobians in Q12 */
#define LKF_J_ONE (1 << LKF_J_SHIFT)

/* Bounds that keep every product in 64 bits and the matrix a covariance. */
#define LKF_VAR_XY_MIN 1000000LL      /**< (1 mm)² */
#define LKF_VAR_XY_MAX 250000000000LL /**< (0.5 m)² */
#define LKF_VAR_TH_MIN 100LL          /**< (10 µrad)² */
#define LKF_VAR_TH_MAX 30000000000LL  /**< (10°)² */
#define LKF_VAR_K_MIN 100000000LL     /**< (10 nrad/mm)², (10 ppm)² */
#define LKF_VAR_K_MAX 8000000000000LL /**< (2.8 µrad/mm = 0.16°/m)², (0.28 %)²: every
                                           gain × covariance product stays below 2^63 */

/** A state: µm, µm, µrad, prad/mm, ppb. */
typedef struct {
    int64_t v[LKF_N];
} lkf_state_t;

/* lkf_cov_t, the filter's covariance, is in slam/localize.h: loc_t holds two. */

/** floor(sqrt(v)). */
uint32_t lkf_isqrt(uint64_t v);

/** A starting covariance: position and heading known, κd and κt not. */
void lkf_init(lkf_cov_t *c);

/** The matrix symmetric, its diagonal within bounds, every correlation within ±1. */
void lkf_sane(lkf_cov_t *c);

/**
 * The covariance after a move of the robot by (dx, dy) mm in the map frame, driving ds_mm
 * (forward positive) and turning by turn_urad (counter-clockwise positive): the heading
 * gains κd·ds + κt·turn, the position takes up the heading's uncertainty across the path,
 * and odometry's random errors over that distance and turn are added.
 */
void lkf_predict(lkf_cov_t *c, int64_t dx_mm, int64_t dy_mm, int64_t ds_mm, int64_t turn_urad);

/** The heading a move of ds_um driven and turn_urad turned adds under the learned κd and
 *  κt, in nrad. */
int64_t lkf_drift_nrad(const lkf_state_t *k, int64_t ds_um, int64_t turn_urad);

/**
 * One scalar measurement whose value should be 0: h at the linearisation point lin, with
 * Jacobian j (over x, y, θ) and variance r (µm²). Updates the state d and its covariance.
 */
void lkf_update(lkf_state_t *d, lkf_cov_t *c, const lkf_state_t *lin, int64_t h,
                const int32_t j[3], int64_t r);

#endif /* SLAM_LOC_KF_H */
