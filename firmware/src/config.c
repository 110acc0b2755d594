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

/* How a field is stored. */
enum { CFG_U8, CFG_U16, CFG_U32, CFG_I32 };

/* What a field must hold besides its range: each names the fields it is compared with. */
enum {
    RULE_NONE,
    RULE_CELL,          /* cell_um · the longer grid side stays within CFG_WORLD_LIMIT_UM */
    RULE_ABOVE_MIN,     /* confidence_radius_um > range_min_um */
    RULE_STOPS,         /* one stop only where sweep_first_mdeg == sweep_last_mdeg */
    RULE_PULSES,        /* servo_pulse_180deg_us != servo_pulse_0deg_us */
    RULE_THRESHOLD,     /* post_threshold below OMmax (counting) or the evidence limit */
    RULE_TOP_SPEED,     /* no faster than top_speed_mm_s */
    RULE_ABOVE_CLEARANCE /* follow_um > clearance_um */
};

/* A field's valid range; a signed field's bounds are int32_t values stored as uint32_t. */
typedef struct {
    const char *name;
    uint32_t lo;
    uint32_t hi;
    uint8_t offset;
    uint8_t type;
    uint8_t rule;
} cfg_range_t;

_Static_assert(sizeof(slam_config_t) <= 255u, "field offsets are bytes");

#define CFG_GRID_SIDE (SLAM_GRID_A > SLAM_GRID_B ? SLAM_GRID_A : SLAM_GRID_B)
#define R(field, type, lo, hi, rule)                                                          \
    {#field, (uint32_t)(lo), (uint32_t)(hi), (uint8_t)offsetof(slam_config_t, field), CFG_##type, \
     RULE_##rule}

/* In the order of the fields (and of the telemetry keys): the first that fails is named. */
static const cfg_range_t cfg_ranges[] = {
    R(wheel_diameter_left_um, U32, 10000, 300000, NONE),
    R(wheel_diameter_right_um, U32, 10000, 300000, NONE),
    R(wheel_base_um, U32, 50000, 1000000, NONE),
    R(encoder_counts_per_rev, U32, 16, 65535, NONE),
    R(cal_left, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE),
    R(cal_right, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE),
    R(cal_base, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE),
    R(start_x_um, I32, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM, NONE),
    R(start_y_um, I32, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM, NONE),
    R(start_heading_mdeg, I32, -360000, 360000, NONE),
    /* A·L and B·L stay below 1 km, so every grid coordinate fits in int32_t µm. */
    R(cell_um, U32, 5000, 1000000, CELL),
    R(start_cell_a, U16, 0, SLAM_GRID_A - 1u, NONE),
    R(start_cell_b, U16, 0, SLAM_GRID_B - 1u, NONE),
    R(om_max, U8, 1, UINT8_MAX, NONE),
    R(tm_max, U8, 1, UINT8_MAX, NONE),
    R(om_mode, U8, 0, OM_MODES - 1, NONE),
    R(om_hit, U8, 1, GRID_EVIDENCE_MAX, NONE),
    R(om_miss, U8, 1, GRID_EVIDENCE_MAX, NONE),
    R(confidence_radius_um, U32, 1, 10000000, ABOVE_MIN),
    R(range_min_um, U32, 0, 1000000, NONE),
    R(sound_speed_mm_per_s, U32, 300000, 400000, NONE),
    R(mount_x_um, I32, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM, NONE),
    R(mount_y_um, I32, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM, NONE),
    R(mount_yaw_mdeg, I32, -180000, 180000, NONE),
    R(sweep_first_mdeg, I32, 0, 180000, NONE),
    R(sweep_last_mdeg, I32, 0, 180000, NONE),
    R(sweep_stops, U8, 1, SLAM_SWEEP_STOPS_MAX, STOPS),
    R(settle_ticks, U8, 1, UINT8_MAX, NONE),
    R(echo_timeout_ticks, U8, 1, UINT8_MAX, NONE),
    R(servo_pulse_0deg_us, U16, 400, 2600, NONE),
    R(servo_pulse_180deg_us, U16, 400, 2600, PULSES),
    R(post_threshold, U8, 0, UINT8_MAX, THRESHOLD),
    R(post_template_k, U8, 0, 8, NONE),
    R(post_insert, U8, 0, 1, NONE),
    R(top_speed_mm_s, U16, 50, 5000, NONE),
    R(accel_mm_s2, U16, 10, 50000, NONE),
    R(motion_kp_q8, U16, 0, 2048, NONE),
    R(motion_ki_q8, U16, 0, 2048, NONE),
    R(explore_mode, U8, 0, EXPLORE_MODES - 1, NONE),
    R(cruise_mm_s, U16, 1, UINT16_MAX, TOP_SPEED),
    R(turn_mm_s, U16, 1, UINT16_MAX, TOP_SPEED),
    R(avoid_um, U32, 50000, 4000000, NONE),
    R(clearance_um, U32, 10000, 2000000, NONE),
    R(square_side_um, U32, 100000, 100000000, NONE),
    R(explore_seed, U32, 1, UINT32_MAX, NONE),
    R(localize, U8, 0, 1, NONE),
    R(ping_interval_ticks, U8, 1, UINT8_MAX, NONE),
    R(follow_um, U32, 50000, 2000000, ABOVE_CLEARANCE),
    R(umbmark_runs, U8, 1, 50, NONE),
    R(umbmark_pause_s, U16, 1, 3600, NONE),
};
#undef R

static uint32_t field_value(const slam_config_t *c, const cfg_range_t *r)
{
    const uint8_t *field = (const uint8_t *)c + r->offset;
    if (r->type == CFG_U8) {
        return *field;
    }
    if (r->type == CFG_U16) {
        uint16_t v;
        memcpy(&v, field, sizeof v);
        return v;
    }
    uint32_t v;
    memcpy(&v, field, sizeof v); /* an int32_t's bits are its two's complement */
    return v;
}

static bool rule_holds(const slam_config_t *c, unsigned rule, uint32_t v)
{
    switch (rule) {
    case RULE_CELL:
        return v <= (uint32_t)CFG_WORLD_LIMIT_UM / CFG_GRID_SIDE;
    case RULE_ABOVE_MIN:
        return v > c->range_min_um;
    case RULE_STOPS:
        return v != 1u || c->sweep_first_mdeg == c->sweep_last_mdeg;
    case RULE_PULSES:
        return v != c->servo_pulse_0deg_us;
    case RULE_THRESHOLD:
        return v < (c->om_mode == OM_MODE_COUNT ? c->om_max : GRID_EVIDENCE_MAX);
    case RULE_TOP_SPEED:
        return v <= c->top_speed_mm_s;
    case RULE_ABOVE_CLEARANCE:
        return v > c->clearance_um;
    default:
        return true;
    }
}

static const char *first_bad_field(const slam_config_t *c)
{
    for (size_t i = 0; i < sizeof cfg_ranges / sizeof cfg_ranges[0]; i++) {
        const cfg_range_t *r = &cfg_ranges[i];
        uint32_t v = field_value(c, r);
        bool in_range = r->type == CFG_I32
                            ? (int32_t)v >= (int32_t)r->lo && (int32_t)v <= (int32_t)r->hi
                            : v >= r->lo && v <= r->hi;
        if (!in_range || !rule_holds(c, r->rule, v)) {
            return r->name;
        }
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
