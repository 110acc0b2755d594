/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The one table of configuration fields: every fact about a field of `slam_config_t` but
 * its C declaration, from which the defaults, the checks, the text names, the telemetry
 * keys and the tools' tables are all generated.
 *
 * X(name, type, default, lo, hi, rule, id, live, words), one row per field:
 * - name: the member of slam_config_t (config.h, where its doc comment says what it is);
 *   the key of the text configuration and of the tools' `get`/`set`.
 * - type: how it is stored: U8, U16, U32, I32, or Q30 (an int32_t holding a Q1.30 factor,
 *   written in text as a decimal such as 0.9901, sent on the wire as its raw I32).
 * - default: slam_config_default()'s value (a Q30 field's raw value).
 * - lo, hi: the valid range, both included (signed for I32 and Q30).
 * - rule: what the field must hold besides its range, comparing it with other fields
 *   (config.c's RULE_*: NONE, CELL, ABOVE_MIN, STOPS, PULSES, THRESHOLD, TOP_SPEED,
 *   ABOVE_CLEARANCE, CORRIDOR, GRID, IN_GRID_A, IN_GRID_B); the field named when the
 *   rule fails is this one.
 * - id: its telemetry key for GET and SET (telemetry.h), 1..255. The ids are the
 *   protocol: never renumber one; a new field takes a new id, whatever its place.
 * - live: LIVE when SET may change it while the robot runs, FIXED when it takes effect
 *   only at robot_init() (SET answers TELEM_ERR_FIXED).
 * - words: the valid range in words for messages ("lo..hi", then any rule), or
 *   SLAM_CONFIG_WORDS_MODES for "0..N (the mode names of explore_modes.h)".
 *
 * Rows follow the order of the members in slam_config_t: slam_config_check() and the
 * text configuration go through them in this order (config.c asserts it, with the types).
 * A new field is a member with its doc in config.h and a row here; tests/config_view.c
 * and tests/test_config_tables.py prove that C, the text configuration and the Python
 * tools (tools/slamtools/link.py reads this file) agree on every row.
 */
#ifndef SLAM_CONFIG_FIELDS_H
#define SLAM_CONFIG_FIELDS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"
#include "slam/grid.h"

/** A position stays within 1 km of the origin, far from the int32_t µm limits (±2147 m). */
#define SLAM_CONFIG_WORLD_LIMIT_UM 1000000000
/** The default start pose's x and y: half the default cell, so that the start cell's centre
 *  lies there and the grid's lines on whole multiples of L from the world's origin: an
 *  exported map's origin is then a whole number of cells, which every map reader takes
 *  exactly (MRPT's rounds it to one). With another cell_um, start_x_um and start_y_um of
 *  half of it keep that. */
#define SLAM_START_UM 25000
/** The sonar's servo axis sits on the robot: at most 100 mm behind the wheel axle, 200 mm
 *  ahead of it and 100 mm to a side (farther, in 18 simulated minutes over the shipped
 *  rooms, the robot ran into walls it had not seen: 1 m behind or beside, every run). */
#define SLAM_CONFIG_MOUNT_BACK_UM 100000
#define SLAM_CONFIG_MOUNT_AHEAD_UM 200000
#define SLAM_CONFIG_MOUNT_SIDE_UM 100000

/** The words of explore_mode: its range and the names of explore_modes.h's rows. */
#define SLAM_CONFIG_WORDS_MODES NULL

#define SLAM_CONFIG_FIELDS(X)                                                                      \
    /* Odometry. */                                                                                \
    X(wheel_diameter_left_um, U32, 65000, 10000, 300000, NONE, 1, LIVE, "10000..300000")           \
    X(wheel_diameter_right_um, U32, 65000, 10000, 300000, NONE, 2, LIVE, "10000..300000")          \
    X(wheel_base_um, U32, 130000, 50000, 1000000, NONE, 3, LIVE, "50000..1000000")                 \
    X(encoder_counts_per_rev, U32, 700, 16, 65535, NONE, 4, LIVE, "16..65535")                     \
    X(cal_left, Q30, FIX_Q30_ONE, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2, NONE, 5, LIVE,   \
      "0.5..1.5")                                                                                  \
    X(cal_right, Q30, FIX_Q30_ONE, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2, NONE, 6, LIVE,  \
      "0.5..1.5")                                                                                  \
    X(cal_base, Q30, FIX_Q30_ONE, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2, NONE, 7, LIVE,   \
      "0.5..1.5")                                                                                  \
    /* Start pose. */                                                                              \
    X(start_x_um, I32, SLAM_START_UM, -SLAM_CONFIG_WORLD_LIMIT_UM, SLAM_CONFIG_WORLD_LIMIT_UM,     \
      NONE, 8, FIXED, "-1000000000..1000000000")                                                   \
    X(start_y_um, I32, SLAM_START_UM, -SLAM_CONFIG_WORLD_LIMIT_UM, SLAM_CONFIG_WORLD_LIMIT_UM,     \
      NONE, 9, FIXED, "-1000000000..1000000000")                                                   \
    X(start_heading_mdeg, I32, 0, -360000, 360000, NONE, 10, FIXED, "-360000..360000")             \
    /* Grids. */                                                                                   \
    X(cell_um, U32, 50000, 20000, 1000000, CELL, 11, FIXED,                                        \
      "20000..1000000, and at most 1 km over the grid's longer side")                              \
    X(grid_a, U16, 0, 0, SLAM_GRID_A, GRID, 53, FIXED,                                             \
      "0..65535: 3 up to the build's grid capacity along x, or 0 for all of it")                   \
    X(grid_b, U16, 0, 0, SLAM_GRID_B, GRID, 54, FIXED,                                             \
      "0..65535: 3 up to the build's grid capacity along y, or 0 for all of it")                   \
    X(start_cell_a, U16, SLAM_GRID_A / 2, 0, SLAM_GRID_A - 1, IN_GRID_A, 12, FIXED,                \
      "0..65535, below the grid's cells along x")                                                  \
    X(start_cell_b, U16, SLAM_GRID_B / 2, 0, SLAM_GRID_B - 1, IN_GRID_B, 13, FIXED,                \
      "0..65535, below the grid's cells along y")                                                  \
    X(om_max, U8, 9, 1, UINT8_MAX, NONE, 14, FIXED,                                                \
      "1..255, and above post_threshold when om_mode is 0")                                        \
    X(tm_max, U8, 30, 1, UINT8_MAX, NONE, 15, FIXED, "1..255")                                     \
    X(om_mode, U8, OM_MODE_EVIDENCE, 0, OM_MODES - 1, NONE, 16, FIXED,                             \
      "0..1 (0 the paper's hit counts, 1 log-odds evidence)")                                      \
    X(om_hit, U8, 4, 1, GRID_EVIDENCE_MAX, NONE, 17, FIXED, "1..127")                              \
    X(om_miss, U8, 1, 1, GRID_EVIDENCE_MAX, NONE, 18, FIXED, "1..127")                             \
    /* Sonar. */                                                                                   \
    X(confidence_radius_um, U32, 1000000, 1, 10000000, ABOVE_MIN, 19, LIVE,                        \
      "1..10000000, above range_min_um")                                                           \
    X(range_min_um, U32, 20000, 0, 1000000, NONE, 20, LIVE,                                        \
      "0..1000000, below confidence_radius_um")                                                    \
    X(sound_speed_mm_per_s, U32, 343000, 300000, 400000, NONE, 21, LIVE, "300000..400000")         \
    X(mount_x_um, I32, 50000, -SLAM_CONFIG_MOUNT_BACK_UM, SLAM_CONFIG_MOUNT_AHEAD_UM, NONE, 22,    \
      LIVE, "-100000..200000 (on the robot: behind or ahead of the wheel axle)")                   \
    X(mount_y_um, I32, 0, -SLAM_CONFIG_MOUNT_SIDE_UM, SLAM_CONFIG_MOUNT_SIDE_UM, NONE, 23, LIVE,   \
      "-100000..100000 (on the robot: beside its middle)")                                         \
    X(mount_yaw_mdeg, I32, 0, -20000, 20000, NONE, 24, LIVE,                                       \
      "-20000..20000 (a mounting error: the sonar faces forward)")                                 \
    /* Sweep: it always takes in straight ahead, the servo's 90 degrees. */                        \
    X(sweep_first_mdeg, I32, 40000, 0, 90000, NONE, 25, FIXED,                                     \
      "0..90000 (the sweep takes in straight ahead, 90 degrees)")                                  \
    X(sweep_last_mdeg, I32, 180000, 90000, 180000, NONE, 26, FIXED,                                \
      "90000..180000 (the sweep takes in straight ahead, 90 degrees)")                             \
    X(sweep_stops, U8, 8, 1, SLAM_SWEEP_STOPS_MAX, STOPS, 27, FIXED,                               \
      "1..16, and 1 only when sweep_first_mdeg equals sweep_last_mdeg")                            \
    X(settle_ticks, U8, 3, 1, UINT8_MAX, NONE, 28, FIXED, "1..255")                                \
    X(echo_timeout_ticks, U8, 4, 1, UINT8_MAX, NONE, 29, FIXED, "1..255")                          \
    X(servo_pulse_0deg_us, U16, 500, 400, 2600, NONE, 30, FIXED, "400..2600")                      \
    X(servo_pulse_180deg_us, U16, 2500, 400, 2600, PULSES, 31, FIXED,                              \
      "400..2600, and not equal to servo_pulse_0deg_us")                                           \
    /* Post-processing. */                                                                         \
    X(post_threshold, U8, 0, 0, UINT8_MAX, THRESHOLD, 32, LIVE,                                    \
      "0..254, below om_max when om_mode is 0, below 127 when it is 1")                            \
    X(post_template_k, U8, 0, 0, 8, NONE, 33, LIVE, "0..8")                                        \
    X(post_insert, U8, 0, 0, 1, NONE, 34, LIVE, "0..1")                                            \
    /* Motion. */                                                                                  \
    X(top_speed_mm_s, U16, 300, 50, 5000, NONE, 35, LIVE,                                          \
      "50..5000, at least cruise_mm_s and turn_mm_s")                                              \
    X(accel_mm_s2, U16, 500, 100, 50000, NONE, 36, LIVE,                                           \
      "100..50000 (gentler, the robot runs into a wall before it stops)")                          \
    X(motion_kp_q8, U16, 64, 0, 2048, NONE, 37, LIVE, "0..2048")                                   \
    X(motion_ki_q8, U16, 8, 0, 2048, NONE, 38, LIVE, "0..2048")                                    \
    /* Exploration. */                                                                             \
    X(explore_mode, U8, EXPLORE_WALLS, 0, EXPLORE_MODES - 1, NONE, 39, LIVE,                       \
      SLAM_CONFIG_WORDS_MODES)                                                                     \
    X(cruise_mm_s, U16, 200, 1, UINT16_MAX, TOP_SPEED, 40, LIVE,                                   \
      "1..5000, at most top_speed_mm_s")                                                           \
    X(turn_mm_s, U16, 100, 1, UINT16_MAX, TOP_SPEED, 41, LIVE, "1..5000, at most top_speed_mm_s")  \
    X(avoid_um, U32, 300000, 50000, 4000000, NONE, 42, LIVE, "50000..4000000")                     \
    X(clearance_um, U32, 130000, 10000, 2000000, CORRIDOR, 43, LIVE,                               \
      "10000..2000000, below follow_um; the corridor ahead at most 240 cells")                     \
    X(square_side_um, U32, 1500000, 100000, 100000000, NONE, 44, LIVE, "100000..100000000")        \
    X(square_laps, U8, 1, 0, UINT8_MAX, NONE, 45, LIVE, "0..255 (0: for ever)")                    \
    X(explore_seed, U32, 1, 1, UINT32_MAX, NONE, 46, LIVE, "1..4294967295 (not 0)")                \
    /* Persistence. */                                                                             \
    X(save_period_s, U16, 60, 0, UINT16_MAX, NONE, 47, LIVE, "0..65535 (0: never)")                \
    /* Localization. */                                                                            \
    X(localize, U8, 1, 0, 1, NONE, 48, FIXED, "0..1 (1: the pose corrected against OM)")           \
    /* Sonar timing and the walls mode. */                                                         \
    X(ping_interval_ticks, U8, 6, 1, UINT8_MAX, NONE, 49, FIXED, "1..255")                         \
    X(follow_um, U32, 300000, 50000, 2000000, ABOVE_CLEARANCE, 50, LIVE,                           \
      "50000..2000000, above clearance_um")                                                        \
    /* Calibration. */                                                                             \
    X(umbmark_runs, U8, 5, 1, 50, NONE, 51, LIVE, "1..50 (runs each way)")                         \
    X(umbmark_pause_s, U16, 90, 1, 3600, NONE, 52, LIVE,                                           \
      "1..3600 (standing still before and after each run)")                                        \
    /* The second sonar. */                                                                        \
    X(sonar1_map, U8, 0, 0, 1, NONE, 55, FIXED, "0..1 (1: HAL sonar 1 pinged and mapped)")         \
    X(sonar1_mdeg, I32, 0, 0, 180000, NONE, 56, FIXED,                                             \
      "0..180000 (its beam as a servo angle: 0 looks left, 180000 right)")

/** Each field's row number (SLAM_CONFIG_ROW_<name>) and how many rows there are. The
 *  names are the members' own, so these constants are not upper case. */
enum slam_config_row {
#define SLAM_CONFIG_ROW_OF(name, type, dflt, lo, hi, rule, id, live, words) SLAM_CONFIG_ROW_##name,
    SLAM_CONFIG_FIELDS(SLAM_CONFIG_ROW_OF)
#undef SLAM_CONFIG_ROW_OF
        SLAM_CONFIG_ROWS
};

/** Each field's telemetry key (SLAM_CONFIG_ID_<name>). */
enum slam_config_id {
#define SLAM_CONFIG_ID_OF(name, type, dflt, lo, hi, rule, id, live, words)                         \
    SLAM_CONFIG_ID_##name = id,
    SLAM_CONFIG_FIELDS(SLAM_CONFIG_ID_OF)
#undef SLAM_CONFIG_ID_OF
};

/** The highest telemetry key: the size of a union of one char[id] per row. */
#define SLAM_CONFIG_ID_MAX ((unsigned)sizeof(union {SLAM_CONFIG_FIELDS(SLAM_CONFIG_ID_SPAN)}))
#define SLAM_CONFIG_ID_SPAN(name, type, dflt, lo, hi, rule, id, live, words) char name[id];

/**
 * A field's value by its row, widened to 32 bits: zero-extended from U8 and U16, an I32's
 * or a Q30's two's complement bits.
 * @param row  a slam_config_row (below SLAM_CONFIG_ROWS)
 */
uint32_t slam_config_field_get(const slam_config_t *cfg, unsigned row);

/**
 * Store a value into a field by its row (an I32 or Q30 takes the value's bits), unchecked
 * against the field's range: slam_config_check() judges the whole configuration.
 * @param row  a slam_config_row (below SLAM_CONFIG_ROWS)
 * @return false, and @p cfg unchanged, when the value does not fit a U8 or U16 field
 */
bool slam_config_field_set(slam_config_t *cfg, unsigned row, uint32_t value);

#endif /* SLAM_CONFIG_FIELDS_H */
