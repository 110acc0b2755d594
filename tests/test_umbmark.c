/* SPDX-License-Identifier: MIT */
/* Tests of the UMBmark test: runs, directions, corners, pauses and the stop at the start. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "slam/config.h"
#include "slam/odometry.h"
#include "slam/umbmark.h"

#define PI 3.14159265358979323846

/* A robot whose wheels follow their targets within the acceleration limit and whose
 * odometry is the truth: what the test drives is what odometry sees. */
typedef struct {
    slam_config_t cfg;
    umbmark_t u;
    odom_t odom;
    double speed_mm_s[2];
    double counts[2];
    uint32_t restarts;       /* runs begun (umbmark_step() said so) */
    int32_t max_target_mm_s; /* the fastest wheel target asked for */
} bot_t;

static void bot_init(bot_t *b, int32_t start_x_um, int32_t start_y_um, int32_t start_mdeg)
{
    memset(b, 0, sizeof *b);
    slam_config_default(&b->cfg);
    b->cfg.explore_mode = EXPLORE_UMBMARK;
    b->cfg.square_side_um = 1500000u;
    b->cfg.umbmark_runs = 2u;
    b->cfg.umbmark_pause_s = 2u;
    b->cfg.start_x_um = start_x_um;
    b->cfg.start_y_um = start_y_um;
    b->cfg.start_heading_mdeg = start_mdeg;
    assert_int_equal(slam_config_check(&b->cfg, NULL), 0);
    umbmark_init(&b->u, &b->cfg);
    odom_init(&b->odom, &b->cfg, 0u, 0u);
}

static void bot_tick(bot_t *b)
{
    int32_t target[2];
    odom_pose_t p = odom_pose(&b->odom);
    if (umbmark_step(&b->u, &p, target)) {
        b->restarts++;
        odom_set_pose(&b->odom, &b->u.start);
    }
    double counts_per_mm =
        b->cfg.encoder_counts_per_rev / (PI * b->cfg.wheel_diameter_left_um * 1e-3);
    double dv = b->cfg.accel_mm_s2 * 0.01;
    for (int w = 0; w < 2; w++) {
        int32_t t = target[w] < 0 ? -target[w] : target[w];
        b->max_target_mm_s = t > b->max_target_mm_s ? t : b->max_target_mm_s;
        double d = target[w] - b->speed_mm_s[w];
        b->speed_mm_s[w] += d > dv ? dv : (d < -dv ? -dv : d);
        b->counts[w] += b->speed_mm_s[w] * 0.01 * counts_per_mm;
    }
    odom_step(&b->odom, (uint16_t)(int64_t)floor(b->counts[0]),
              (uint16_t)(int64_t)floor(b->counts[1]));
}

static double heading_deg(const odom_pose_t *p)
{
    return (double)(int32_t)p->heading * (360.0 / 4294967296.0);
}

static void test_waits_then_starts_at_the_start_pose(void **state)
{
    (void)state;
    bot_t b;
    bot_init(&b, 0, 0, 0);
    assert_true(b.u.on);
    for (unsigned i = 0; i < 199u; i++) {
        bot_tick(&b);
        assert_int_equal(b.restarts, 0u);
        assert_true(b.speed_mm_s[0] == 0.0 && b.speed_mm_s[1] == 0.0);
    }
    bot_tick(&b); /* the 200th tick: the pause of 2 s is over */
    assert_int_equal(b.restarts, 1u);
    assert_int_equal(b.u.run, 1u);
    assert_int_equal(b.u.state, UMB_LEG);

    slam_config_t c;
    slam_config_default(&c);
    umbmark_t off;
    umbmark_init(&off, &c);
    assert_false(off.on); /* random exploration is not the test */
}

/* Drive every run; at each pause the robot stands where odometry began the run. */
static void drive_all(bot_t *b, double x0_mm, double y0_mm, double th0_deg)
{
    uint32_t last_run = 0u;
    double turned = 0.0, prev = 0.0;       /* heading turned since the run began */
    double min_turn = 0.0, max_turn = 0.0; /* its extremes in this run */
    unsigned pauses = 0u;
    unsigned paused_ticks = 0u;
    for (unsigned i = 0; i < 200000u && b->u.state != UMB_DONE; i++) {
        uint8_t before = b->u.state;
        bot_tick(b);
        odom_pose_t p = odom_pose(&b->odom);
        double rel = heading_deg(&p) - th0_deg;
        rel = rel > 180.0 ? rel - 360.0 : (rel < -180.0 ? rel + 360.0 : rel);
        if (b->u.run != last_run) {
            last_run = b->u.run;
            min_turn = max_turn = turned = prev = 0.0;
        }
        double step = rel - prev;
        turned += step > 180.0 ? step - 360.0 : (step < -180.0 ? step + 360.0 : step);
        prev = rel;
        min_turn = turned < min_turn ? turned : min_turn;
        max_turn = turned > max_turn ? turned : max_turn;
        if (b->u.state == UMB_PAUSE) {
            paused_ticks++;
        }
        if (before == UMB_STOP && b->u.state == UMB_PAUSE) {
            pauses++;
            /* The run is over: back where it began, facing the same way. */
            assert_true(fabs(p.x_um * 1e-3 - x0_mm) < 3.0);
            assert_true(fabs(p.y_um * 1e-3 - y0_mm) < 3.0);
            assert_true(fabs(rel) < 1.0);
            /* Clockwise runs turn right, to -90° and beyond; the others left. */
            if (umbmark_run_cw(&b->u, b->u.run)) {
                assert_true(min_turn < -260.0 && max_turn < 1.0);
            } else {
                assert_true(max_turn > 260.0 && min_turn > -1.0);
            }
        }
    }
    assert_int_equal(b->u.state, UMB_DONE);
    assert_int_equal(pauses, 4u);
    assert_int_equal(b->restarts, 4u);
    assert_int_equal(b->u.run, 4u);
    /* Five pauses of 2 s: before each of the four runs and after the last. */
    assert_true(paused_ticks >= 5u * 199u && paused_ticks <= 5u * 200u + 10u);
    /* At most the cruise speed, and the little more that holds the heading. */
    assert_true(b->max_target_mm_s <= (int32_t)b->cfg.cruise_mm_s + 5);
}

static void test_runs_both_ways_and_returns(void **state)
{
    (void)state;
    bot_t b;
    bot_init(&b, 0, 0, 0);
    drive_all(&b, 0.0, 0.0, 0.0);
}

static void test_square_turns_with_the_start_pose(void **state)
{
    (void)state;
    bot_t b;
    bot_init(&b, -700000, 2500000, 30000);
    /* The far corner of the first (clockwise) square: 1.5 m ahead and 1.5 m to the right
     * of a robot at (-0.7, 2.5) m facing 30°. */
    double c = cos(30.0 * PI / 180.0), s = sin(30.0 * PI / 180.0);
    double fx = -700.0 + 1500.0 * c + 1500.0 * s, fy = 2500.0 + 1500.0 * s - 1500.0 * c;
    double nearest = 1e9;
    for (unsigned i = 0; i < 20000u && b.u.run < 2u; i++) {
        bot_tick(&b);
        odom_pose_t p = odom_pose(&b.odom);
        double d = hypot(p.x_um * 1e-3 - fx, p.y_um * 1e-3 - fy);
        nearest = d < nearest ? d : nearest;
    }
    assert_true(nearest < 5.0);
    bot_init(&b, -700000, 2500000, 30000);
    drive_all(&b, -700.0, 2500.0, 30.0);
}

/* A run begins from the start pose whatever odometry said before: the robot was carried. */
static void test_a_run_begins_at_the_start_pose(void **state)
{
    (void)state;
    bot_t b;
    bot_init(&b, 0, 0, 0);
    const odom_pose_t elsewhere = {123456, -654321, 0x12345678u};
    odom_set_pose(&b.odom, &elsewhere);
    for (unsigned i = 0; i < 200u; i++) {
        bot_tick(&b);
    }
    assert_int_equal(b.restarts, 1u);
    odom_pose_t p = odom_pose(&b.odom);
    assert_true(p.x_um >= 0 && p.x_um < 100 && p.y_um == 0 && p.heading == 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_waits_then_starts_at_the_start_pose),
        cmocka_unit_test(test_runs_both_ways_and_returns),
        cmocka_unit_test(test_square_turns_with_the_start_pose),
        cmocka_unit_test(test_a_run_begins_at_the_start_pose),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
