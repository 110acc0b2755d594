/* SPDX-License-Identifier: MIT */
/* The pose correction's Kalman filter in fixed point (prediction, scalar updates), the
 * correction it estimates, and the systematic drift of odometry it learns. */
#include "loc_filter.h"

#include "slam/fixed.h"

#define LKF_K_SHIFT 20u /* Kalman gains in Q20 */

#define LOC_KAPPA_MAX 20000000     /* ±20 µrad/mm (1.1° a metre), ±2 % of a turn */
#define LOC_URAD_PER_BAM_Q26 98175 /* 0.00146292 µrad per bam, Q26 */

/* Odometry's random errors, measured in the simulator per metre driven and per radian
 * turned: µm² per mm; µrad² per mm and per mrad. */
#ifndef LKF_Q_XY_PER_MM
#define LKF_Q_XY_PER_MM 1000 /* (1 mm)² per metre */
#endif
#ifndef LKF_Q_TH_PER_MM
#define LKF_Q_TH_PER_MM 26000 /* (0.29°)² per metre */
#endif
#ifndef LKF_Q_TH_PER_MRAD
#define LKF_Q_TH_PER_MRAD 2200 /* (0.085°)² per radian */
#endif
/* What the systematic errors may be at the start (E_d and E_b after a calibration, one
 * standard deviation) and how fast they may change (per metre driven). */
#ifndef LKF_KD0
#define LKF_KD0 500000LL /* 0.5 µrad/mm: 0.03° per metre, E_d within ±0.0065 % */
#endif
#ifndef LKF_KT0
#define LKF_KT0 1000000LL /* 0.1 % of each turn: E_b within ±0.1 % */
#endif
#ifndef LKF_Q_K_PER_MM
#define LKF_Q_K_PER_MM 1000LL /* (1 nrad/mm)² or (1 ppm)² per km: E_d and E_b barely change */
#endif

uint32_t lkf_isqrt(uint64_t v)
{
    /* Digit by digit, from the highest power of four within v: the steps above it would
     * leave the root at 0, so starting there changes nothing but their cost (the
     * covariance's diagonal is 20 to 43 bits long, a wall normal's sums under 24). */
    if (v == 0u) {
        return 0u;
    }
    if ((v >> 32) == 0u) { /* in 32-bit words: half the instructions on the MCU */
        uint32_t v32 = (uint32_t)v;
        uint32_t r32 = 0;
        for (uint32_t bit = 1u << ((31u - (uint32_t)__builtin_clz(v32)) & ~1u); bit != 0u;
             bit >>= 2) {
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
    for (uint64_t bit = 1ull << ((63u - (uint32_t)__builtin_clzll(v)) & ~1u); bit != 0u;
         bit >>= 2) {
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
    static const int64_t lo[LKF_N] = {LKF_VAR_XY_MIN, LKF_VAR_XY_MIN, LKF_VAR_TH_MIN, LKF_VAR_K_MIN,
                                      LKF_VAR_K_MIN};
    static const int64_t hi[LKF_N] = {LKF_VAR_XY_MAX, LKF_VAR_XY_MAX, LKF_VAR_TH_MAX, LKF_VAR_K_MAX,
                                      LKF_VAR_K_MAX};
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

void lkf_update(lkf_state_t *d, lkf_cov_t *c, const lkf_state_t *lin, int64_t h, const int32_t j[3],
                int64_t r)
{
    /* P Jᵀ, in the state's units × µm Q12. The bounds of lkf_sane(), |j0|, |j1| <= 2^12
     * and |j2| <= 2^15 (an 8 m lever, loc_match.c) keep |P Jᵀ| below 2^55, and so its
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

/* ---- the correction ------------------------------------------------------------------------ */

static loc_corr_t corr_of(int32_t tx_um, int32_t ty_um, bam32_t th)
{
    return (loc_corr_t){tx_um, ty_um, th, fix_cos(th), fix_sin(th)};
}

odom_pose_t loc_apply(const loc_corr_t *c, const odom_pose_t *odom)
{
    odom_pose_t p;
    loc_corr_point(c, odom->x_um, odom->y_um, &p.x_um, &p.y_um);
    p.heading = odom->heading + c->th;
    return p;
}

void loc_move_point(int32_t x, int32_t y, int32_t cx, int32_t cy, int64_t dx, int64_t dy, q1_30_t c,
                    q1_30_t s, int32_t *ox, int32_t *oy)
{
    int64_t rx = (int64_t)x - cx;
    int64_t ry = (int64_t)y - cy;
    *ox = fix_sat_i32(cx + fix_round_shift(rx * c - ry * s, 30u) + dx);
    *oy = fix_sat_i32(cy + fix_round_shift(rx * s + ry * c, 30u) + dy);
}

/* The correction turned by dth about a map point, then shifted: the robot standing there
 * keeps its place and changes its heading. */
static void correct_about(loc_filter_t *f, int32_t cx, int32_t cy, bam32_t dth, int64_t dx,
                          int64_t dy)
{
    int32_t tx;
    int32_t ty;
    loc_move_point(f->corr.tx_um, f->corr.ty_um, cx, cy, dx, dy, fix_cos(dth), fix_sin(dth), &tx,
                   &ty);
    f->corr = corr_of(tx, ty, f->corr.th + dth);
}

void loc_filter_init(loc_filter_t *f)
{
    *f = (loc_filter_t){0};
    f->corr.c = FIX_Q30_ONE; /* no correction: cos 0 is one, the rest is zero */
    lkf_init(&f->cov);
}

/* ---- the drift ----------------------------------------------------------------------------- */

void loc_filter_move(loc_filter_t *f, const odom_pose_t *odom)
{
    if (!f->have_last) {
        f->have_last = true;
        f->last_odom = *odom;
        return;
    }
    int32_t dxo = (int32_t)((uint32_t)odom->x_um - (uint32_t)f->last_odom.x_um);
    int32_t dyo = (int32_t)((uint32_t)odom->y_um - (uint32_t)f->last_odom.y_um);
    int32_t turned = fix_bam_diff(odom->heading, f->last_odom.heading);
    /* Driven: the move along the heading it began with (backwards is negative). */
    int64_t ds_um = fix_round_shift((int64_t)dxo * fix_cos(f->last_odom.heading) +
                                        (int64_t)dyo * fix_sin(f->last_odom.heading),
                                    30u);
    f->last_odom = *odom;
    /* The move in the map frame is odometry's turned by the correction. */
    int64_t dx = fix_round_shift((int64_t)dxo * f->corr.c - (int64_t)dyo * f->corr.s, 30u);
    int64_t dy = fix_round_shift((int64_t)dxo * f->corr.s + (int64_t)dyo * f->corr.c, 30u);
    int64_t turn_urad = ((int64_t)turned * LOC_URAD_PER_BAM_Q26) >> 26;
    lkf_predict(&f->cov, fix_div_s64(dx, 1000), fix_div_s64(dy, 1000), fix_div_s64(ds_um, 1000),
                turn_urad);
    /* The learned drift, whole µrad at a time (the rest waits for the next move). */
    lkf_state_t k = {{0, 0, 0, f->kappa_prad_per_mm, f->kappa_ppb}};
    f->drift_nrad += lkf_drift_nrad(&k, ds_um, turn_urad);
    int64_t urad = fix_div_s64(f->drift_nrad, 1000);
    if (urad != 0) {
        f->drift_nrad -= urad * 1000;
        odom_pose_t at = loc_apply(&f->corr, odom);
        correct_about(f, at.x_um, at.y_um, loc_bam_of_urad(urad), 0, 0);
    }
}

static int32_t clamp_kappa(int64_t v)
{
    return (int32_t)(v < -LOC_KAPPA_MAX ? -LOC_KAPPA_MAX : v > LOC_KAPPA_MAX ? LOC_KAPPA_MAX : v);
}

void loc_filter_correct(loc_filter_t *f, int32_t cx, int32_t cy, const lkf_state_t *d, lkf_cov_t *p)
{
    correct_about(f, cx, cy, loc_bam_of_urad(d->v[LKF_T]), d->v[LKF_X], d->v[LKF_Y]);
    f->kappa_prad_per_mm = clamp_kappa(f->kappa_prad_per_mm + d->v[LKF_KD]);
    f->kappa_ppb = clamp_kappa(f->kappa_ppb + d->v[LKF_KT]);
    lkf_sane(p);
    f->cov = *p;
}
