/* SPDX-License-Identifier: MIT */
/* Sonar reading to world point: echo width to distance, Eq. 3-5 with the mount offset. */
#include "slam/sonar.h"

void sonar_init(sonar_t *s, const slam_config_t *cfg)
{
    s->mount_x_um = cfg->mount_x_um;
    s->mount_y_um = cfg->mount_y_um;
    s->mount_yaw = fix_bam_from_mdeg(cfg->mount_yaw_mdeg);
    /* c/2 in µm per µs is c[mm/s] / 2000; kept in Q16.16 (171.5 at 343 m/s is exact). */
    s->um_per_echo_us_q16 = (uint32_t)fix_muldiv_u64(cfg->sound_speed_mm_per_s, FIX_Q16_ONE, 2000u);
    s->range_min_um = cfg->range_min_um;
    s->confidence_um = cfg->confidence_radius_um;
}

uint32_t sonar_range_um(const sonar_t *s, uint32_t echo_us)
{
    uint64_t d = ((uint64_t)echo_us * s->um_per_echo_us_q16 + (FIX_Q16_ONE / 2)) >> 16;
    return d > UINT32_MAX ? UINT32_MAX : (uint32_t)d;
}

bool sonar_in_confidence(const sonar_t *s, uint32_t range_um)
{
    return range_um >= s->range_min_um && range_um < s->confidence_um;
}

bam32_t sonar_bearing(const sonar_t *s, bam32_t heading, bam32_t servo)
{
    /* Eq. 3: θ = Ψ + (π/2 − θo), turned by the mount yaw. */
    return heading + FIX_BAM_QUARTER - servo + s->mount_yaw;
}

void sonar_origin(const sonar_t *s, const odom_pose_t *pose, int32_t *x_um, int32_t *y_um)
{
    q1_30_t c = fix_cos(pose->heading);
    q1_30_t sn = fix_sin(pose->heading);
    /* The offset is within 1 m (slam_config_check), so the 32 x 32-bit products cannot
     * overflow. */
    int64_t mx = s->mount_x_um;
    int64_t my = s->mount_y_um;
    *x_um = fix_sat_i32((int64_t)pose->x_um + fix_round_shift(mx * c - my * sn, 30u));
    *y_um = fix_sat_i32((int64_t)pose->y_um + fix_round_shift(mx * sn + my * c, 30u));
}

void sonar_beam(const sonar_t *s, const odom_pose_t *pose, bam32_t servo, sonar_beam_t *b)
{
    sonar_origin(s, pose, &b->x_um, &b->y_um);
    bam32_t theta = sonar_bearing(s, pose->heading, servo);
    b->c = fix_cos(theta);
    b->s = fix_sin(theta);
}

void sonar_beam_point(const sonar_beam_t *b, uint32_t range_um, int32_t *x_um, int32_t *y_um)
{
    /* d < 2^32 and |cos| <= 1, so the products fit; a point of the world (within 1 km,
     * slam_config_check()) plus a sonar's range stays far inside int32_t. */
    int64_t d = range_um;
    *x_um = (int32_t)(b->x_um + fix_round_shift(d * b->c, 30u));
    *y_um = (int32_t)(b->y_um + fix_round_shift(d * b->s, 30u));
}

void sonar_obstacle(const sonar_t *s, const odom_pose_t *pose, bam32_t servo, uint32_t range_um,
                    int32_t *x_um, int32_t *y_um)
{
    sonar_beam_t b;
    sonar_beam(s, pose, servo, &b);
    sonar_beam_point(&b, range_um, x_um, y_um);
}
