/* SPDX-License-Identifier: MIT */
/* The pose correction's Kalman filter in fixed point: prediction, scalar updates, and the
 * systematic drift of odometry it learns. */
#include "loc_kf.h"

#include "slam/fixed.h"

#define LKF_K_SHIFT 20u /* Kalman gains in Q20 */

/* Odometry's random errors, measured in the simulator per metre driven and per radian
 * turned: µm² per mm; µrad² per mm and per mrad. */
#ifndef LKF_Q_XY_PER_MM
#define LKF_Q_XY_PER_MM 1000      /* (1 mm)² per metre */
#endif
#ifndef LKF_Q_TH_PER_MM
#define LKF_Q_TH_PER_MM 26000     /* (0.29°)² per metre */
#endif
#ifndef LKF_Q_TH_PER_MRAD
#define LKF_Q_TH_PER_MRAD 2200    /* (0.085°)² per radian */
#endif
/* What the systematic errors may be at the start (E_d and E_b after a calibration, one
 * standard deviation) and how fast they may change (per metre driven). */
#ifndef LKF_KD0
#define LKF_KD0 500000LL          /* 0.5 µrad/mm: 0.03° per metre, E_d within ±0.0065 % */
#endif
#ifndef LKF_KT0
#define LKF_KT0 1000000LL         /* 0.1 % of each turn: E_b within ±0.1 % */
#endif
#ifndef LKF_Q_K_PER_MM
#define LKF_Q_K_PER_MM 1000LL     /* (1 nrad/mm)² or (1 ppm)² per km: E_d and E_b barely change */
#endif

uint32_t lkf_isqrt(uint64_t v)
{
    if ((v >> 32) == 0u) { /* the wall normals' sums: half the steps, in 32-bit words */
        uint32_t v32 = (uint32_t)v;
        uint32_t r32 = 0;
        for (uint32_t bit = 1u << 30; bit != 0u; bit >>= 2) {
            if (v32 >= r32 + bit) {
                v32 -= r32 + bit;
                r32 = (r32 >> 1) + bit;
            } else {
                r32 >>= 1;
            }
        }
        return r32;
    }
    uint64_t r = 0;
    for (uint64_t bit = 1ull << 62; bit != 0u; bit >>= 2) {
        if (v >= r + bit) {
            v -= r + bit;
            r = (r >> 1) + bit;
        } else {
            r >>= 1;
        }
    }
    return (uint32_t)r;
}

static int64_t clamp64(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

void lkf_init(lkf_cov_t *c)
{
    for (unsigned i = 0; i < LKF_N; i++) {
        for (unsigned k = 0; k < LKF_N; k++) {
            c->p[i][k] = 0;
        }
    }
    c->p[LKF_X][LKF_X] = LKF_VAR_XY_MIN;
    c->p[LKF_Y][LKF_Y] = LKF_VAR_XY_MIN;
    c->p[LKF_T][LKF_T] = LKF_VAR_TH_MIN;
    c->p[LKF_KD][LKF_KD] = LKF_KD0 * LKF_KD0;
    c->p[LKF_KT][LKF_KT] = LKF_KT0 * LKF_KT0;
}

void lkf_sane(lkf_cov_t *c)
{
    static const int64_t lo[LKF_N] = {LKF_VAR_XY_MIN, LKF_VAR_XY_MIN, LKF_VAR_TH_MIN,
                                      LKF_VAR_K_MIN, LKF_VAR_K_MIN};
    static const int64_t hi[LKF_N] = {LKF_VAR_XY_MAX, LKF_VAR_XY_MAX, LKF_VAR_TH_MAX,
                                      LKF_VAR_K_MAX, LKF_VAR_K_MAX};
    int64_t root[LKF_N];
    for (unsigned i = 0; i < LKF_N; i++) {
        c->p[i][i] = clamp64(c->p[i][i], lo[i], hi[i]);
        root[i] = (int64_t)lkf_isqrt((uint64_t)c->p[i][i]);
    }
    for (unsigned i = 0; i < LKF_N; i++) {
        for (unsigned k = i + 1u; k < LKF_N; k++) {
            /* Symmetric, and |P_ik| <= sqrt(P_ii)·sqrt(P_kk) (the roots floored). */
            int64_t v = (c->p[i][k] + c->p[k][i]) / 2;
            int64_t bound = root[i] * root[k];
            c->p[i][k] = c->p[k][i] = clamp64(v, -bound, bound);
        }
    }
}

/* State i += (num / den) · state j: P = E P Eᵀ with E = I + (num/den)·e_i e_jᵀ. */
static void shear(lkf_cov_t *c, unsigned i, unsigned j, int64_t num, int64_t den)
{
    if (num == 0) {
        return;
    }
    for (unsigned k = 0; k < LKF_N; k++) {
        c->p[i][k] += fix_div_s64(num * c->p[j][k], den); /* row i */
    }
    for (unsigned k = 0; k < LKF_N; k++) {
        c->p[k][i] += fix_div_s64(num * c->p[k][j], den); /* column i */
    }
}

void lkf_predict(lkf_cov_t *c, int64_t dx_mm, int64_t dy_mm, int64_t ds_mm, int64_t turn_urad)
{
    /* A reading's move is centimetres; more than a metre (a glitch) counts as a metre. */
    int64_t dx = clamp64(dx_mm, -1000, 1000);
    int64_t dy = clamp64(dy_mm, -1000, 1000);
    int64_t ds = clamp64(ds_mm, -1000, 1000);
    int64_t turn = clamp64(turn_urad, -7000000, 7000000);
    /* The heading gains κd·ds (prad/mm × mm) and κt·turn (ppb × µrad), in µrad... */
    shear(c, LKF_T, LKF_KD, ds, 1000000);
    shear(c, LKF_T, LKF_KT, turn, 1000000000);
    /* ... and the position follows the heading across the move (the lever in m). */
    shear(c, LKF_X, LKF_T, -dy, 1000);
    shear(c, LKF_Y, LKF_T, dx, 1000);
    /* Odometry's random errors over this move; κ may wander too. */
    int64_t dist = ds < 0 ? -ds : ds;
    int64_t turned = turn < 0 ? -turn : turn;
    c->p[LKF_X][LKF_X] += LKF_Q_XY_PER_MM * dist;
    c->p[LKF_Y][LKF_Y] += LKF_Q_XY_PER_MM * dist;
    c->p[LKF_T][LKF_T] += LKF_Q_TH_PER_MM * dist + LKF_Q_TH_PER_MRAD * fix_div_s64(turned, 1000);
    c->p[LKF_KD][LKF_KD] += LKF_Q_K_PER_MM * dist;
    c->p[LKF_KT][LKF_KT] += LKF_Q_K_PER_MM * dist;
    lkf_sane(c);
}

int64_t lkf_drift_nrad(const lkf_state_t *k, int64_t ds_um, int64_t turn_urad)
{
    return fix_div_s64(k->v[LKF_KD] * ds_um + k->v[LKF_KT] * turn_urad, 1000000);
}

static uint64_t magnitude(int64_t v)
{
    return v < 0 ? 0u - (uint64_t)v : (uint64_t)v;
}

void lkf_update(lkf_state_t *d, lkf_cov_t *c, const lkf_state_t *lin, int64_t h,
                const int32_t j[3], int64_t r)
{
    /* P Jᵀ, in the state's units × µm Q12. The bounds of lkf_sane(), |j0|, |j1| <= 2^12
     * and |j2| <= 2^15 (an 8 m lever, localize.c) keep |P Jᵀ| below 2^55, and so its
     * gain numerator below 2^63. */
    int64_t pj[LKF_N];
    for (unsigned i = 0; i < LKF_N; i++) {
        pj[i] = c->p[i][LKF_X] * j[0] + c->p[i][LKF_Y] * j[1] + c->p[i][LKF_T] * j[2];
    }
    int64_t q[LKF_N];
    for (unsigned i = 0; i < LKF_N; i++) {
        q[i] = fix_round_shift(pj[i], LKF_J_SHIFT);
    }
    int64_t s = ((q[LKF_X] * j[0] + q[LKF_Y] * j[1] + q[LKF_T] * j[2]) >> LKF_J_SHIFT) + r;
    if (s <= 0) {
        return;
    }
    /* The measurement is 0; its prediction is h moved on from the linearisation point. */
    int64_t pred = h + fix_round_shift(j[0] * (d->v[LKF_X] - lin->v[LKF_X]) +
                                           j[1] * (d->v[LKF_Y] - lin->v[LKF_Y]) +
                                           j[2] * (d->v[LKF_T] - lin->v[LKF_T]),
                                       LKF_J_SHIFT);
    int64_t k[LKF_N];
    for (unsigned i = 0; i < LKF_N; i++) {
        /* Q20, rounded to nearest: a truncated gain would shrink every update the same way. */
        int64_t num = pj[i] * (1 << (LKF_K_SHIFT - LKF_J_SHIFT));
        k[i] = fix_div_s64(num + (num < 0 ? -s / 2 : s / 2), s);
    }
    /* lkf_sane() bounds each correlation, not the matrix: where rounding has left P short
     * of a covariance along J, s can be small against P Jᵀ and a gain times it leave 64
     * bits. Such a hit tells nothing to trust: it is skipped. (With P a covariance,
     * |k_i · q_m| <= sqrt(P_ii · P_mm) · 2^20, within LKF_VAR_K_MAX's bound.) */
    uint64_t kmax = 0u;
    uint64_t qmax = magnitude(pred);
    for (unsigned i = 0; i < LKF_N; i++) {
        kmax = magnitude(k[i]) > kmax ? magnitude(k[i]) : kmax;
        qmax = magnitude(q[i]) > qmax ? magnitude(q[i]) : qmax;
    }
    const uint64_t room = (uint64_t)INT64_MAX - (1u << (LKF_K_SHIFT - 1u)); /* and the rounding */
    if (kmax != 0u && qmax > fix_div_u64(room, kmax)) {
        return;
    }
    /* Rounded, not floored: a hundred updates must not drift by a hundred half units. */
    for (unsigned i = 0; i < LKF_N; i++) {
        d->v[i] -= fix_round_shift(k[i] * pred, LKF_K_SHIFT);
    }
    /* P −= K (P Jᵀ)ᵀ, symmetric. */
    for (unsigned i = 0; i < LKF_N; i++) {
        for (unsigned m = i; m < LKF_N; m++) {
            int64_t v = c->p[i][m] - fix_round_shift(k[i] * q[m], LKF_K_SHIFT);
            c->p[i][m] = c->p[m][i] = v;
        }
    }
}
