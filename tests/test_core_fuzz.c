/* SPDX-License-Identifier: MIT */
/* The whole core under random valid configurations, noisy wheels, encoder glitches and a
 * sonar that answers anything: it must never reach undefined behaviour (the sanitizer
 * build aborts on any) and its outputs must stay in range.
 *
 *   test_core_fuzz [RUNS [FIRST_SEED]]
 *
 * Without arguments it runs FUZZ_RUNS configurations of FUZZ_TICKS ticks each, a few
 * seconds in the sanitizer build (make test); `make fuzz-core` runs many more. A failure
 * names the seed, and `test_core_fuzz 1 SEED` runs that configuration alone. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "fake_hal.h"
#include "slam/config_fields.h"
#include "slam/error.h"
#include "slam/explore.h"
#include "slam/grid.h"
#include "slam/odometry.h"
#include "slam/robot.h"

#define FUZZ_RUNS 500u
#define FUZZ_TICKS 3000u

static uint32_t fuzz_runs = FUZZ_RUNS;
static uint32_t fuzz_first_seed = 1u;

/* splitmix32: the fuzz's own random stream, one per run. */
static uint32_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (uint32_t)((z ^ (z >> 31)) >> 32);
}

/* A value in [lo, hi]; the ends themselves come up often, as a fuzz should make them. */
static int64_t pick(uint64_t *s, int64_t lo, int64_t hi)
{
    uint32_t r = next(s);
    if ((r & 7u) == 0u) {
        return (r & 8u) != 0u ? lo : hi;
    }
    return lo + (int64_t)((uint64_t)next(s) % (uint64_t)(hi - lo + 1));
}

/* A configuration slam_config_check() accepts: each field anywhere in its range, often at
 * an end of it; the few fields that depend on others are drawn after them. */
static void random_config(uint64_t *s, slam_config_t *c)
{
    test_config_default(c);
    if ((next(s) & 3u) == 0u) {
        return; /* the defaults too, with random inputs */
    }
    c->wheel_diameter_left_um = (uint32_t)pick(s, 10000, 300000);
    c->wheel_diameter_right_um =
        (next(s) & 1u) != 0u ? c->wheel_diameter_left_um : (uint32_t)pick(s, 10000, 300000);
    c->wheel_base_um = (uint32_t)pick(s, 50000, 1000000);
    c->encoder_counts_per_rev = (uint32_t)pick(s, 16, 65535);
    c->cal_left = (q1_30_t)pick(s, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2);
    c->cal_right = (q1_30_t)pick(s, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2);
    c->cal_base = (q1_30_t)pick(s, FIX_Q30_ONE / 2, FIX_Q30_ONE + FIX_Q30_ONE / 2);
    c->start_x_um = (int32_t)pick(s, -1000000000, 1000000000);
    c->start_y_um = (int32_t)pick(s, -1000000000, 1000000000);
    c->start_heading_mdeg = (int32_t)pick(s, -360000, 360000);
    uint32_t side = SLAM_GRID_A > SLAM_GRID_B ? SLAM_GRID_A : SLAM_GRID_B;
    c->cell_um =
        (uint32_t)pick(s, 20000, 1000000000 / side < 1000000 ? 1000000000 / side : 1000000);
    c->start_cell_a = (uint16_t)pick(s, 0, SLAM_GRID_A - 1);
    c->start_cell_b = (uint16_t)pick(s, 0, SLAM_GRID_B - 1);
    c->om_max = (uint8_t)pick(s, 1, 255);
    c->tm_max = (uint8_t)pick(s, 1, 255);
    c->om_mode = (uint8_t)pick(s, 0, OM_MODES - 1);
    c->om_hit = (uint8_t)pick(s, 1, GRID_EVIDENCE_MAX);
    c->om_miss = (uint8_t)pick(s, 1, GRID_EVIDENCE_MAX);
    c->range_min_um = (uint32_t)pick(s, 0, 1000000);
    c->confidence_radius_um = (uint32_t)pick(s, c->range_min_um + 1, 10000000);
    c->sound_speed_mm_per_s = (uint32_t)pick(s, 300000, 400000);
    c->mount_x_um = (int32_t)pick(s, -SLAM_CONFIG_MOUNT_BACK_UM, SLAM_CONFIG_MOUNT_AHEAD_UM);
    c->mount_y_um = (int32_t)pick(s, -SLAM_CONFIG_MOUNT_SIDE_UM, SLAM_CONFIG_MOUNT_SIDE_UM);
    c->mount_yaw_mdeg = (int32_t)pick(s, -20000, 20000);
    c->sweep_stops = (uint8_t)pick(s, 1, SLAM_SWEEP_STOPS_MAX);
    c->sweep_first_mdeg = c->sweep_stops == 1u ? 90000 : (int32_t)pick(s, 0, 89999);
    c->sweep_last_mdeg = c->sweep_stops == 1u ? 90000 : (int32_t)pick(s, 90000, 180000);
    c->settle_ticks = (uint8_t)pick(s, 1, 255);
    c->echo_timeout_ticks = (uint8_t)pick(s, 1, 255);
    c->ping_interval_ticks = (uint8_t)pick(s, 1, 255);
    c->servo_pulse_0deg_us = (uint16_t)pick(s, 400, 2600);
    do {
        c->servo_pulse_180deg_us = (uint16_t)pick(s, 400, 2600);
    } while (c->servo_pulse_180deg_us == c->servo_pulse_0deg_us);
    c->post_threshold =
        (uint8_t)pick(s, 0, (c->om_mode == OM_MODE_COUNT ? c->om_max : GRID_EVIDENCE_MAX) - 1);
    c->post_template_k = (uint8_t)pick(s, 0, 8);
    c->post_insert = (uint8_t)pick(s, 0, 1);
    c->top_speed_mm_s = (uint16_t)pick(s, 50, 5000);
    c->accel_mm_s2 = (uint16_t)pick(s, 100, 50000);
    c->motion_kp_q8 = (uint16_t)pick(s, 0, 2048);
    c->motion_ki_q8 = (uint16_t)pick(s, 0, 2048);
    c->explore_mode = (uint8_t)pick(s, 0, EXPLORE_MODES - 1);
    c->cruise_mm_s = (uint16_t)pick(s, 1, c->top_speed_mm_s);
    c->turn_mm_s = (uint16_t)pick(s, 1, c->top_speed_mm_s);
    c->avoid_um = (uint32_t)pick(s, 50000, 4000000);
    /* The widest clearance whose corridor ahead the cell size takes (config.h). */
    uint32_t columns = SLAM_CORRIDOR_CELLS_MAX / slam_corridor_rows(c->cell_um);
    uint32_t widest = (columns - 1u) * c->cell_um / 2u + c->cell_um / 2u - 1u;
    c->clearance_um = (uint32_t)pick(s, 10000, widest < 1999999u ? widest : 1999999);
    c->follow_um =
        (uint32_t)pick(s, c->clearance_um < 50000u ? 50000 : c->clearance_um + 1u, 2000000);
    c->square_side_um = (uint32_t)pick(s, 100000, 100000000);
    c->square_laps = (uint8_t)pick(s, 0, 255);
    c->explore_seed = (uint32_t)pick(s, 1, UINT32_MAX);
    c->save_period_s = (uint16_t)pick(s, 0, 3);
    c->umbmark_runs = (uint8_t)pick(s, 1, 50);
    c->umbmark_pause_s = (uint16_t)pick(s, 1, 3); /* so UMBmark's runs begin within a run */
}

/* The wheels roll about as the duty says, with noise; now and then an encoder jumps by up
 * to half its counter range (a glitch), sometimes tick after tick, and a runaway encoder
 * jumps the most it can, always forward. */
static void move_wheels(uint64_t *s, uint32_t glitchy, bool runaway)
{
    for (unsigned w = 0; w < 2u; w++) {
        int32_t counts = fake_hal.motor[w] / 50 + (int32_t)(next(s) % 5u) - 2;
        uint32_t r = next(s);
        if (r % 1000u < glitchy) {
            counts = runaway ? 32767 : (int32_t)(next(s) % 65535u) - 32767;
        }
        fake_hal.encoder[w] = (uint16_t)(fake_hal.encoder[w] + (uint16_t)counts);
    }
}

/* The sonar answers a ping with anything: an echo of any width, a timeout, or nothing. */
static void answer_sonar(uint64_t *s)
{
    if (fake_hal.sonar_next == HAL_SONAR_ECHO || fake_hal.sonar_next == HAL_SONAR_TIMEOUT) {
        return; /* not yet polled */
    }
    uint32_t r = next(s) % 8u;
    if (r < 4u) {
        fake_hal.sonar_next = HAL_SONAR_ECHO;
        fake_hal.sonar_echo_us = r == 0u ? next(s) : next(s) % 40000u;
    } else if (r == 4u) {
        fake_hal.sonar_next = HAL_SONAR_TIMEOUT;
    } else {
        fake_hal.sonar_next = HAL_SONAR_BUSY;
    }
}

static void check_outputs(const robot_t *r, uint64_t seed, uint32_t tick)
{
    for (unsigned w = 0; w < 2u; w++) {
        if (fake_hal.motor[w] < -HAL_DUTY_MAX || fake_hal.motor[w] > HAL_DUTY_MAX) {
            fail_msg("seed %llu tick %u: duty %d out of range", (unsigned long long)seed,
                     (unsigned)tick, fake_hal.motor[w]);
        }
    }
    if (r->ticks != tick + 1u) {
        fail_msg("seed %llu tick %u: robot counts %u ticks", (unsigned long long)seed,
                 (unsigned)tick, (unsigned)r->ticks);
    }
}

static void check_grid(const robot_t *r, uint64_t seed)
{
    uint8_t om_max = r->cfg.om_mode == OM_MODE_COUNT ? r->cfg.om_max : 255u;
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        if (r->grid.om[i] > om_max || r->grid.tm[i] > r->cfg.tm_max) {
            fail_msg("seed %llu: cell %u holds OM %u, TM %u beyond OMmax %u, TMmax %u",
                     (unsigned long long)seed, (unsigned)i, r->grid.om[i], r->grid.tm[i], om_max,
                     r->cfg.tm_max);
        }
    }
}

static robot_t robot;

static void fuzz_one(uint64_t seed)
{
    uint64_t s = seed;
    slam_config_t cfg;
    random_config(&s, &cfg);
    const char *bad = NULL;
    if (slam_config_check(&cfg, &bad) != SLAM_OK) {
        fail_msg("seed %llu: the fuzz drew an invalid configuration (%s)", (unsigned long long)seed,
                 bad);
    }
    fake_hal_reset();
    fake_hal.encoder[0] = (uint16_t)next(&s);
    fake_hal.encoder[1] = (uint16_t)next(&s);
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    /* Per mille of wheel readings that glitch: none, a few, or most. */
    static const uint32_t glitch_rates[] = {0u, 2u, 20u, 900u};
    uint32_t glitchy = glitch_rates[next(&s) % 4u];
    bool runaway = glitchy != 0u && next(&s) % 4u == 0u;
    for (uint32_t t = 0; t < FUZZ_TICKS; t++) {
        move_wheels(&s, glitchy, runaway);
        answer_sonar(&s);
        if (next(&s) % 500u == 0u) {
            robot_request_save(&robot);
        }
        robot_tick(&robot);
        check_outputs(&robot, seed, t);
        if (next(&s) % 4u == 0u) {
            robot_idle(&robot);
        }
    }
    check_grid(&robot, seed);
}

static void test_random_configurations_and_glitches(void **state)
{
    (void)state;
    for (uint32_t i = 0; i < fuzz_runs; i++) {
        fuzz_one((uint64_t)fuzz_first_seed + i);
    }
}

/* The largest wheels the configuration allows, on the coarsest encoders, each reading a
 * runaway count (the most a 16-bit counter can move in one tick, the wheels opposite ways
 * or together): kilometres a tick, a heading change of thousands of turns. Odometry wraps
 * (positions like the heading: modulo their range) and never overflows a signed integer;
 * the pose moves by exactly the wheels' travel, modulo 2^32 µm. */
static void test_runaway_encoders_on_the_largest_wheels(void **state)
{
    (void)state;
    slam_config_t cfg;
    test_config_default(&cfg);
    cfg.wheel_diameter_left_um = cfg.wheel_diameter_right_um = 300000u;
    cfg.encoder_counts_per_rev = 16u;
    cfg.wheel_base_um = 50000u;
    cfg.cal_left = cfg.cal_right = FIX_Q30_ONE + FIX_Q30_ONE / 2;
    cfg.cal_base = FIX_Q30_ONE / 2;
    assert_int_equal(slam_config_check(&cfg, NULL), SLAM_OK);

    odom_t o;
    uint16_t left = 0u;
    uint16_t right = 0u;
    odom_init(&o, &cfg, left, right);
    /* Opposite ways: the heading spins as fast as the counters allow. */
    for (int t = 0; t < 1000; t++) {
        left = (uint16_t)(left - 32768u);
        right = (uint16_t)(right + 32767u);
        odom_step(&o, left, right);
    }
    /* Straight ahead along x, 100 000 ticks at 2.9 km a tick: the pose moves by the step
     * modulo 2^32 µm, every tick, through every wrap of the 32-bit pose and the Q48.16
     * accumulator. */
    odom_init(&o, &cfg, left, right);
    int64_t step_um = fix_round_shift(32767 * o.um_per_count[ODOM_LEFT], 16u);
    odom_pose_t before = odom_pose(&o);
    for (int t = 0; t < 100000; t++) {
        left = (uint16_t)(left + 32767u);
        right = (uint16_t)(right + 32767u);
        odom_step(&o, left, right);
        odom_pose_t now = odom_pose(&o);
        uint32_t moved = (uint32_t)now.x_um - (uint32_t)before.x_um;
        uint32_t off = moved - (uint32_t)step_um;
        if (off + 1u > 2u) { /* within ±1 µm of rounding */
            fail_msg("tick %d: the pose moved %u µm (mod 2^32), not %lld", t, (unsigned)moved,
                     (long long)step_um);
        }
        assert_int_equal(now.y_um, 0);
        assert_int_equal(now.heading, 0u);
        before = now;
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        fuzz_runs = (uint32_t)strtoul(argv[1], NULL, 10);
    }
    if (argc > 2) {
        fuzz_first_seed = (uint32_t)strtoul(argv[2], NULL, 10);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_runaway_encoders_on_the_largest_wheels),
        cmocka_unit_test(test_random_configurations_and_glitches),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
