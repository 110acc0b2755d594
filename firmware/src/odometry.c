/* SPDX-License-Identifier: MIT */
/* Wheel odometry, Eq. 8-12 with the midpoint heading, in fixed point. */
#include "slam/odometry.h"

/* π in Q29, for the wheel circumference; the rounding error is 4e-11 relative. */
#define ODOM_PI_Q29 1686629713u

SLAM_START_UP void odom_init(odom_t *o, const slam_config_t *cfg, uint16_t left, uint16_t right)
{
    const uint32_t diameter[2] = {cfg->wheel_diameter_left_um, cfg->wheel_diameter_right_um};
    const q1_30_t cal[2] = {cfg->cal_left, cfg->cal_right};
    uint64_t counts = cfg->encoder_counts_per_rev;

    for (unsigned w = 0; w < 2u; w++) {
        /* D·c_w in Q30 µm: at most 2^49 for the checked ranges. */
        uint64_t dc = (uint64_t)diameter[w] * (uint64_t)cal[w];
        /* Travel per count π·D·c_w / N, in Q16 µm. */
        o->um_per_count[w] = (q48_16_t)fix_muldiv_u64(dc, ODOM_PI_Q29, counts << 43);
        /* Heading per count of this wheel alone: (π·D·c_w/N) / (E_b·2h) rad, which is
         * D·c_w·2^31 / (N·2h·E_b) binary angle units: π cancels, so the gain is exact. */
        uint64_t dc_per_eb = fix_muldiv_u64(dc, FIX_Q30_ONE, (uint64_t)cfg->cal_base);
        o->bam_per_count[w] =
            (q48_16_t)fix_muldiv_u64(dc_per_eb, 1u << 17, counts * cfg->wheel_base_um);
    }

    const odom_pose_t start = {cfg->start_x_um, cfg->start_y_um,
                               fix_bam_from_mdeg(cfg->start_heading_mdeg)};
    odom_set_pose(o, &start);
    o->last_count[ODOM_LEFT] = left;
    o->last_count[ODOM_RIGHT] = right;
    o->step_um[ODOM_LEFT] = 0;
    o->step_um[ODOM_RIGHT] = 0;
}

void odom_set_pose(odom_t *o, const odom_pose_t *p)
{
    o->x_um = (q48_16_t)p->x_um * FIX_Q16_ONE;
    o->y_um = (q48_16_t)p->y_um * FIX_Q16_ONE;
    o->heading_q16 = (uint64_t)p->heading << 16;
}

/* Counts moved since the last reading of a wrapping 16-bit counter, in [-32768, 32767]. */
static int32_t count_delta(uint16_t now, uint16_t before)
{
    uint16_t d = (uint16_t)(now - before);
    return d >= 0x8000u ? (int32_t)d - 0x10000 : (int32_t)d;
}

void odom_step(odom_t *o, uint16_t left, uint16_t right)
{
    int32_t dl = count_delta(left, o->last_count[ODOM_LEFT]);
    int32_t dr = count_delta(right, o->last_count[ODOM_RIGHT]);
    o->last_count[ODOM_LEFT] = left;
    o->last_count[ODOM_RIGHT] = right;

    /* Each wheel's travel dU_g, dU_d in Q16 µm. */
    int64_t ul = dl * o->um_per_count[ODOM_LEFT];
    int64_t ur = dr * o->um_per_count[ODOM_RIGHT];
    o->step_um[ODOM_LEFT] = (int32_t)fix_round_shift(ul, 16u);
    o->step_um[ODOM_RIGHT] = (int32_t)fix_round_shift(ur, 16u);
    /* Eq. 8: dΨ = (dU_d - dU_g) / 2h, in Q16 binary angle units. Each product fits 63
     * bits (|d| <= 2^15, a checked configuration's gain < 2^47.2); their difference is
     * taken modulo 2^64 like the heading it turns: opposite runaway counts on the coarsest
     * encoders exceed 63 bits, and are then as meaningless as harmless. */
    int64_t dpsi = (int64_t)((uint64_t)(dr * o->bam_per_count[ODOM_RIGHT]) -
                             (uint64_t)(dl * o->bam_per_count[ODOM_LEFT]));
    /* Eq. 9: dU = (dU_d + dU_g) / 2, in Q16 µm. */
    int64_t du = (ur + ul) / 2;

    /* Eq. 10-11 along the midpoint heading Ψ + dΨ/2; unsigned arithmetic wraps the turn,
     * and the positions too: they are added as the unsigned type of the same width (which
     * C lets alias them), so a runaway encoder wraps them instead of overflowing. */
    bam32_t mid = (bam32_t)((o->heading_q16 + (uint64_t)(dpsi / 2)) >> 16);
    *(uint64_t *)&o->x_um += (uint64_t)fix_mul_q30_i64(du, fix_cos(mid));
    *(uint64_t *)&o->y_um += (uint64_t)fix_mul_q30_i64(du, fix_sin(mid));
    /* Eq. 12. */
    o->heading_q16 += (uint64_t)dpsi;
}

/* A Q48.16 position rounded to whole µm, modulo 2^32 (the wrap of fix_bam_diff()). */
static int32_t pose_um(q48_16_t v)
{
    uint32_t u = (uint32_t)(((uint64_t)v + 0x8000u) >> 16);
    return (u & 0x80000000u) ? -(int32_t)(~u) - 1 : (int32_t)u;
}

odom_pose_t odom_pose(const odom_t *o)
{
    odom_pose_t p = {
        .x_um = pose_um(o->x_um),
        .y_um = pose_um(o->y_um),
        .heading = (bam32_t)(fix_round_shift((int64_t)(o->heading_q16 & 0xFFFFFFFFFFFFull), 16u)),
    };
    return p;
}

void odom_umbmark_factors(q1_30_t e_d, q1_30_t *c_left, q1_30_t *c_right)
{
    /* c_L = 2/(E_d + 1) and c_R = 2·E_d/(E_d + 1), both in Q30. */
    uint64_t sum = (uint64_t)e_d + FIX_Q30_ONE;
    *c_left = (q1_30_t)fix_muldiv_u64(2u * (uint64_t)FIX_Q30_ONE, FIX_Q30_ONE, sum);
    *c_right = (q1_30_t)fix_muldiv_u64(2u * (uint64_t)e_d, FIX_Q30_ONE, sum);
}
