/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The lowest layer of the pose correction (localize.h): its Kalman filter in fixed point,
 * the correction's arithmetic, and the drift the filter learns, turned into the correction
 * as the robot moves.
 *
 * The state: an increment of the correction about the robot, (dx, dy) in µm and dθ in
 * µrad, and two systematic errors of odometry the filter learns as it goes (what UMBmark
 * leaves, or what a tyre's wear brings): the heading odometry gains per millimetre driven,
 * κd in prad/mm (10⁻¹² rad; unequal wheels, E_d), and per radian turned, κt in ppb (a
 * wrong wheel base, E_b). Their units are that fine so that their Kalman gains, tiny in
 * any coarser unit, keep their precision in Q20. Between matches the correction turns by
 * κd·distance + κt·turn, so the pose follows the drift it has learned; each match corrects
 * dθ, and through their correlation with it, κd and κt (Martinelli's simultaneous
 * localization and odometry calibration).
 *
 * The covariance is a full symmetric 5×5 matrix of int64 in the state's units. A
 * measurement's Jacobian is in Q12 (a unit normal is 4096, the θ entry in µm per µrad) and
 * never involves κ directly.
 *
 * Internal to the core; the tests check the filter against a double-precision one. Calls
 * nothing else of the module.
 */
#ifndef SLAM_LOC_FILTER_H
#define SLAM_LOC_FILTER_H

#include <stdint.h>

#include "slam/localize.h"

/** The state's entries. */
enum { LKF_X = 0, LKF_Y, LKF_T, LKF_KD, LKF_KT, LKF_N };
_Static_assert(LKF_N == LOC_STATES, "the filter's state and loc_t's covariance differ");

#define LKF_J_SHIFT 12u /**< Jacobians in Q12 */
#define LKF_J_ONE (1 << LKF_J_SHIFT)

/* Bounds that keep every product in 64 bits and the matrix a covariance. */
#define LKF_VAR_XY_MIN 1000000LL      /**< (1 mm)² */
#define LKF_VAR_XY_MAX 250000000000LL /**< (0.5 m)² */
#define LKF_VAR_TH_MIN 100LL          /**< (10 µrad)² */
#define LKF_VAR_TH_MAX 30000000000LL  /**< (10°)² */
#define LKF_VAR_K_MIN 100000000LL     /**< (10 nrad/mm)², (10 ppm)² */
#define LKF_VAR_K_MAX                                                                              \
    8000000000000LL /**< (2.8 µrad/mm = 0.16°/m)², (0.28 %)²: every                            \
                         gain × covariance product stays below 2^63 */

/** A state: µm, µm, µrad, prad/mm, ppb. */
typedef struct {
    int64_t v[LKF_N];
} lkf_state_t;

/* lkf_cov_t, the filter's covariance, is in slam/localize.h: loc_filter_t holds the
 * filter's, loc_match_t a match's while it runs. */

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
void lkf_update(lkf_state_t *d, lkf_cov_t *c, const lkf_state_t *lin, int64_t h, const int32_t j[3],
                int64_t r);

/* ---- the correction and the drift (loc_filter_t) ---------------------------------------- */

/** One more in a counter that stops at UINT32_MAX. */
static inline void loc_count(uint32_t *c)
{
    if (*c != UINT32_MAX) {
        (*c)++;
    }
}

/** The covariance's units: 2π·10⁶ µrad is 2^32 binary angle units (683.565 bam per µrad,
 *  Q16). */
#define LOC_BAM_PER_URAD_Q16 44797728

/** An angle in µrad as a binary angle. */
static inline bam32_t loc_bam_of_urad(int64_t urad)
{
    return (bam32_t)(uint32_t)(int32_t)((urad * LOC_BAM_PER_URAD_Q16) >> 16);
}

/** A point (µm) through a correction. Inline: the held-back hits go through it by the
 *  hundred for each reading. Positions stay far inside ±2^31 µm (slam_config_check keeps
 *  the world within 1 km), so the 32 × 30-bit products fit. */
static inline void loc_corr_point(const loc_corr_t *c, int32_t x, int32_t y, int32_t *ox,
                                  int32_t *oy)
{
    *ox = fix_sat_i32(fix_round_shift((int64_t)x * c->c - (int64_t)y * c->s, 30u) + c->tx_um);
    *oy = fix_sat_i32(fix_round_shift((int64_t)x * c->s + (int64_t)y * c->c, 30u) + c->ty_um);
}

/** A map point moved by an increment about a centre: turned by c, s, then shifted by
 *  (dx, dy). µm. */
void loc_move_point(int32_t x, int32_t y, int32_t cx, int32_t cy, int64_t dx, int64_t dy, q1_30_t c,
                    q1_30_t s, int32_t *ox, int32_t *oy);

/** No correction yet, the starting covariance, no drift learned. */
void loc_filter_init(loc_filter_t *f);

/** A reading's ping at odometry pose @p odom: since the last one the covariance grows with
 *  the move, and the correction turns by the drift learned so far, about the robot. */
void loc_filter_move(loc_filter_t *f, const odom_pose_t *odom);

/** A match's increment @p d about the map point (cx, cy), with its covariance @p p: the
 *  correction turned by dθ about that point, then shifted; the drift estimates moved on. */
void loc_filter_correct(loc_filter_t *f, int32_t cx, int32_t cy, const lkf_state_t *d,
                        lkf_cov_t *p);

#endif /* SLAM_LOC_FILTER_H */
