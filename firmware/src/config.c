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

/* How a field is stored (two bits). */
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
_Static_assert(RULE_ABOVE_CLEARANCE < 64, "a rule fits the six bits above a field's storage");

/* Every field's valid range and rule, in the order of the fields (and of the telemetry
 * keys): the first that fails is named. X(field, type, lo, hi, rule); a signed field's
 * bounds are int32_t values. */
#define CFG_FIELDS(X) \
    X(wheel_diameter_left_um, U32, 10000, 300000, NONE)                             \
    X(wheel_diameter_right_um, U32, 10000, 300000, NONE)                            \
    X(wheel_base_um, U32, 50000, 1000000, NONE)                                     \
    X(encoder_counts_per_rev, U32, 16, 65535, NONE)                                 \
    X(cal_left, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE)                      \
    X(cal_right, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE)                     \
    X(cal_base, I32, CFG_Q30_HALF, CFG_Q30_ONE_AND_HALF, NONE)                      \
    X(start_x_um, I32, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM, NONE)               \
    X(start_y_um, I32, -CFG_WORLD_LIMIT_UM, CFG_WORLD_LIMIT_UM, NONE)               \
    X(start_heading_mdeg, I32, -360000, 360000, NONE)                               \
    /* A·L and B·L stay below 1 km, so every grid coordinate fits in int32_t µm. */ \
    X(cell_um, U32, 5000, 1000000, CELL)                                            \
    X(start_cell_a, U16, 0, SLAM_GRID_A - 1u, NONE)                                 \
    X(start_cell_b, U16, 0, SLAM_GRID_B - 1u, NONE)                                 \
    X(om_max, U8, 1, UINT8_MAX, NONE)                                               \
    X(tm_max, U8, 1, UINT8_MAX, NONE)                                               \
    X(om_mode, U8, 0, OM_MODES - 1, NONE)                                           \
    X(om_hit, U8, 1, GRID_EVIDENCE_MAX, NONE)                                       \
    X(om_miss, U8, 1, GRID_EVIDENCE_MAX, NONE)                                      \
    X(confidence_radius_um, U32, 1, 10000000, ABOVE_MIN)                            \
    X(range_min_um, U32, 0, 1000000, NONE)                                          \
    X(sound_speed_mm_per_s, U32, 300000, 400000, NONE)                              \
    X(mount_x_um, I32, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM, NONE)               \
    X(mount_y_um, I32, -CFG_MOUNT_LIMIT_UM, CFG_MOUNT_LIMIT_UM, NONE)               \
    X(mount_yaw_mdeg, I32, -180000, 180000, NONE)                                   \
    X(sweep_first_mdeg, I32, 0, 180000, NONE)                                       \
    X(sweep_last_mdeg, I32, 0, 180000, NONE)                                        \
    X(sweep_stops, U8, 1, SLAM_SWEEP_STOPS_MAX, STOPS)                              \
    X(settle_ticks, U8, 1, UINT8_MAX, NONE)                                         \
    X(echo_timeout_ticks, U8, 1, UINT8_MAX, NONE)                                   \
    X(servo_pulse_0deg_us, U16, 400, 2600, NONE)                                    \
    X(servo_pulse_180deg_us, U16, 400, 2600, PULSES)                                \
    X(post_threshold, U8, 0, UINT8_MAX, THRESHOLD)                                  \
    X(post_template_k, U8, 0, 8, NONE)                                              \
    X(post_insert, U8, 0, 1, NONE)                                                  \
    X(top_speed_mm_s, U16, 50, 5000, NONE)                                          \
    X(accel_mm_s2, U16, 10, 50000, NONE)                                            \
    X(motion_kp_q8, U16, 0, 2048, NONE)                                             \
    X(motion_ki_q8, U16, 0, 2048, NONE)                                             \
    X(explore_mode, U8, 0, EXPLORE_MODES - 1, NONE)                                 \
    X(cruise_mm_s, U16, 1, UINT16_MAX, TOP_SPEED)                                   \
    X(turn_mm_s, U16, 1, UINT16_MAX, TOP_SPEED)                                     \
    X(avoid_um, U32, 50000, 4000000, NONE)                                          \
    X(clearance_um, U32, 10000, 2000000, NONE)                                      \
    X(square_side_um, U32, 100000, 100000000, NONE)                                 \
    X(explore_seed, U32, 1, UINT32_MAX, NONE)                                       \
    X(localize, U8, 0, 1, NONE)                                                     \
    X(ping_interval_ticks, U8, 1, UINT8_MAX, NONE)                                  \
    X(follow_um, U32, 50000, 2000000, ABOVE_CLEARANCE)                              \
    X(umbmark_runs, U8, 1, 50, NONE)                                                \
    X(umbmark_pause_s, U16, 1, 3600, NONE)

_Static_assert(sizeof(slam_config_t) <= 255u, "field offsets are bytes");

#define CFG_GRID_SIDE (SLAM_GRID_A > SLAM_GRID_B ? SLAM_GRID_A : SLAM_GRID_B)
/* The table as parallel arrays: the names one after another, each ended by its NUL, and a
 * field's storage and rule in one byte (no padding and no pointers in flash). */
#define CFG_LO(field, type, lo, hi, rule) (uint32_t)(lo),
#define CFG_HI(field, type, lo, hi, rule) (uint32_t)(hi),
#define CFG_OFFSET(field, type, lo, hi, rule) (uint8_t)offsetof(slam_config_t, field),
#define CFG_KIND(field, type, lo, hi, rule) (uint8_t)(CFG_##type | RULE_##rule << 2),
#define CFG_NAME(field, type, lo, hi, rule) #field "\0"
static const uint32_t cfg_lo[] = {CFG_FIELDS(CFG_LO)};
static const uint32_t cfg_hi[] = {CFG_FIELDS(CFG_HI)};
static const uint8_t cfg_offset[] = {CFG_FIELDS(CFG_OFFSET)};
static const uint8_t cfg_kind[] = {CFG_FIELDS(CFG_KIND)};
static const char cfg_names[] = CFG_FIELDS(CFG_NAME);

static uint32_t field_value(const slam_config_t *c, size_t i)
{
    const uint8_t *field = (const uint8_t *)c + cfg_offset[i];
    unsigned type = cfg_kind[i] & 3u;
    if (type == CFG_U8) {
        return *field;
    }
    if (type == CFG_U16) {
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
    const char *name = cfg_names;
    for (size_t i = 0; i < sizeof cfg_lo / sizeof cfg_lo[0]; i++) {
        uint32_t v = field_value(c, i);
        bool in_range = (cfg_kind[i] & 3u) == CFG_I32
                            ? (int32_t)v >= (int32_t)cfg_lo[i] && (int32_t)v <= (int32_t)cfg_hi[i]
                            : v >= cfg_lo[i] && v <= cfg_hi[i];
        if (!in_range || !rule_holds(c, cfg_kind[i] >> 2, v)) {
            return name;
        }
        while (*name++ != '\0') {
            /* past this name and its NUL */
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
