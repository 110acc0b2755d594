/* SPDX-License-Identifier: MIT */
/* The paper's default configuration and the range check of every field. */
#include "slam/config.h"

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "slam/error.h"
#include "slam/grid.h"

/* Static storage: the padding bytes are zero too, so equal configurations compare equal
 * byte for byte. */
static const slam_config_t slam_config_defaults = {
    .wheel_diameter_left_um = 65000u,
    .wheel_diameter_right_um = 65000u,
    .wheel_base_um = 130000u,
    .encoder_counts_per_rev = 700u,
    .cal_left = FIX_Q30_ONE,
    .cal_right = FIX_Q30_ONE,
    .cal_base = FIX_Q30_ONE,
    .start_x_um = 0,
    .start_y_um = 0,
    .start_heading_mdeg = 0,
    .cell_um = 50000u,
    .start_cell_a = (uint16_t)(SLAM_GRID_A / 2u),
    .start_cell_b = (uint16_t)(SLAM_GRID_B / 2u),
    .om_max = 9u,
    .tm_max = 30u,
    .om_mode = OM_MODE_EVIDENCE,
    .om_hit = 4u,
    .om_miss = 1u,
    .confidence_radius_um = 1000000u,
    .range_min_um = 20000u,
    .sound_speed_mm_per_s = 343000u,
    .mount_x_um = 50000,
    .mount_y_um = 0,
    .mount_yaw_mdeg = 0,
    .sweep_first_mdeg = 65000,
    .sweep_last_mdeg = 155000,
    .sweep_stops = 6u,
    .settle_ticks = 3u,
    .echo_timeout_ticks = 4u,
    .ping_interval_ticks = 6u,
    .servo_pulse_0deg_us = 500u,
    .servo_pulse_180deg_us = 2500u,
    .post_threshold = 0u,
    .post_template_k = 0u,
    .post_insert = 0u,
    .top_speed_mm_s = 300u,
    .accel_mm_s2 = 500u,
    .motion_kp_q8 = 64u,
    .motion_ki_q8 = 8u,
    .explore_mode = EXPLORE_WALLS,
    .cruise_mm_s = 200u,
    .turn_mm_s = 100u,
    .avoid_um = 300000u,
    .clearance_um = 130000u,
    .follow_um = 300000u,
    .square_side_um = 1000000u,
    .square_laps = 1u,
    .explore_seed = 1u,
    .save_period_s = 60u,
    .localize = 1u,
    .umbmark_runs = 5u,
    .umbmark_pause_s = 90u,
};

void slam_config_default(slam_config_t *cfg)
{
    memcpy(cfg, &slam_config_defaults, sizeof *cfg);
}

void slam_config_paper(slam_config_t *cfg)
{
    cfg->om_mode = OM_MODE_COUNT;
    cfg->localize = 0u;
    cfg->post_threshold = 3u;
    cfg->post_template_k = 1u;
    cfg->post_insert = 1u;
}

/* Position limits: a pose must stay far from the int32_t µm limits (±2147 m). */
#define CFG_WORLD_LIMIT_UM 1000000000 /* 1 km */
#define CFG_MOUNT_LIMIT_UM 1000000    /* 1 m */
#define CFG_Q30_HALF (FIX_Q30_ONE / 2)
#define CFG_Q30_ONE_AND_HALF (FIX_Q30_ONE + FIX_Q30_ONE / 2)

static bool in_range_u(uint32_t v, uint32_t lo, uint32_t hi)
{
    return v >= lo && v <= hi;
}

static bool in_range_i(int32_t v, int32_t lo, int32_t hi)
{
    return v >= lo && v <= hi;
}

/* The first failing condition names its field; the order follows the struct. */
static const char *first_bad_field(const slam_config_t *c)
{
    if (!in_range_u(c->wheel_diameter_left_um, 10000u, 300000u)) {
        return "wheel_diameter_left_um";
    }
    if (!in_range_u(c->wheel_diameter_right_um, 10000u, 300000u)) {
        return "wheel_diameter_right_um";
    }
    if (!in_range_u(c->wheel_base_um, 50000u, 1000000u)) {
        return "wheel_base_um";
    }
    if (!in_range_u(c->encoder_counts_per_rev, 16u, 65535u)) {
        return "encoder_counts_per_rev";
    }
    if (!in_range_i(c->cal_left, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF)) {
        return "cal_left";
    }
    if (!in_range_i(c->cal_right, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF)) {
        return "cal_right";
    }
    if (!in_range_i(c->cal_base, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF)) {
        return "cal_base";
    }
    if (!in_range_i(c->start_x_um, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM)) {
        return "start_x_um";
    }
    if (!in_range_i(c->start_y_um, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM)) {
        return "start_y_um";
    }
    if (!in_range_i(c->start_heading_mdeg, -360000, 360000)) {
        return "start_heading_mdeg";
    }
    /* A·L and B·L stay below 1 km, so every grid coordinate fits in int32_t µm. */
    uint32_t max_side = SLAM_GRID_A > SLAM_GRID_B ? SLAM_GRID_A : SLAM_GRID_B;
    if (!in_range_u(c->cell_um, 5000u, 1000000u) ||
        (uint64_t)c->cell_um * max_side > (uint64_t)CFG_WORLD_LIMIT_UM) {
        return "cell_um";
    }
    if (c->start_cell_a >= SLAM_GRID_A) {
        return "start_cell_a";
    }
    if (c->start_cell_b >= SLAM_GRID_B) {
        return "start_cell_b";
    }
    if (c->om_max == 0u) {
        return "om_max";
    }
    if (c->tm_max == 0u) {
        return "tm_max";
    }
    if (c->om_mode >= OM_MODES) {
        return "om_mode";
    }
    if (!in_range_u(c->om_hit, 1u, GRID_EVIDENCE_MAX)) {
        return "om_hit";
    }
    if (!in_range_u(c->om_miss, 1u, GRID_EVIDENCE_MAX)) {
        return "om_miss";
    }
    if (!in_range_u(c->confidence_radius_um, 1u, 10000000u) ||
        c->confidence_radius_um <= c->range_min_um) {
        return "confidence_radius_um";
    }
    if (c->range_min_um > 1000000u) {
        return "range_min_um";
    }
    if (!in_range_u(c->sound_speed_mm_per_s, 300000u, 400000u)) {
        return "sound_speed_mm_per_s";
    }
    if (!in_range_i(c->mount_x_um, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM)) {
        return "mount_x_um";
    }
    if (!in_range_i(c->mount_y_um, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM)) {
        return "mount_y_um";
    }
    if (!in_range_i(c->mount_yaw_mdeg, -180000, 180000)) {
        return "mount_yaw_mdeg";
    }
    if (!in_range_i(c->sweep_first_mdeg, 0, 180000)) {
        return "sweep_first_mdeg";
    }
    if (!in_range_i(c->sweep_last_mdeg, 0, 180000)) {
        return "sweep_last_mdeg";
    }
    if (!in_range_u(c->sweep_stops, 1u, SLAM_SWEEP_STOPS_MAX) ||
        (c->sweep_stops == 1u && c->sweep_first_mdeg != c->sweep_last_mdeg)) {
        return "sweep_stops";
    }
    if (c->settle_ticks == 0u) {
        return "settle_ticks";
    }
    if (c->echo_timeout_ticks == 0u) {
        return "echo_timeout_ticks";
    }
    if (!in_range_u(c->servo_pulse_0deg_us, 400u, 2600u)) {
        return "servo_pulse_0deg_us";
    }
    if (!in_range_u(c->servo_pulse_180deg_us, 400u, 2600u) ||
        c->servo_pulse_180deg_us == c->servo_pulse_0deg_us) {
        return "servo_pulse_180deg_us";
    }
    if (c->post_threshold >= (c->om_mode == OM_MODE_COUNT ? c->om_max : GRID_EVIDENCE_MAX)) {
        return "post_threshold";
    }
    if (c->post_template_k > 8u) {
        return "post_template_k";
    }
    if (c->post_insert > 1u) {
        return "post_insert";
    }
    if (!in_range_u(c->top_speed_mm_s, 50u, 5000u)) {
        return "top_speed_mm_s";
    }
    if (!in_range_u(c->accel_mm_s2, 10u, 50000u)) {
        return "accel_mm_s2";
    }
    if (c->motion_kp_q8 > 2048u) {
        return "motion_kp_q8";
    }
    if (c->motion_ki_q8 > 2048u) {
        return "motion_ki_q8";
    }
    if (c->explore_mode >= EXPLORE_MODES) {
        return "explore_mode";
    }
    if (c->cruise_mm_s == 0u || c->cruise_mm_s > c->top_speed_mm_s) {
        return "cruise_mm_s";
    }
    if (c->turn_mm_s == 0u || c->turn_mm_s > c->top_speed_mm_s) {
        return "turn_mm_s";
    }
    if (!in_range_u(c->avoid_um, 50000u, 4000000u)) {
        return "avoid_um";
    }
    if (!in_range_u(c->clearance_um, 10000u, 2000000u)) {
        return "clearance_um";
    }
    if (!in_range_u(c->square_side_um, 100000u, 100000000u)) {
        return "square_side_um";
    }
    if (c->explore_seed == 0u) {
        return "explore_seed";
    }
    if (c->localize > 1u) {
        return "localize";
    }
    if (c->ping_interval_ticks == 0u) {
        return "ping_interval_ticks";
    }
    if (!in_range_u(c->follow_um, 50000u, 2000000u) || c->follow_um <= c->clearance_um) {
        return "follow_um";
    }
    if (!in_range_u(c->umbmark_runs, 1u, 50u)) {
        return "umbmark_runs";
    }
    if (!in_range_u(c->umbmark_pause_s, 1u, 3600u)) {
        return "umbmark_pause_s";
    }
    return NULL;
}

int slam_config_check(const slam_config_t *cfg, const char **field)
{
    const char *bad = first_bad_field(cfg);
    if (field != NULL) {
        *field = bad;
    }
    return bad == NULL ? SLAM_OK : SLAM_EINVAL;
}
