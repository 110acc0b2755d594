/* SPDX-License-Identifier: MIT */
/* Tests of the sonar geometry: Eq. 3 bearings, Eq. 4-5 points against double, ranges. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "slam/config.h"
#include "slam/mapper.h"
#include "slam/sonar.h"
#include "test_rng.h"

static const double PI = 3.14159265358979323846;

static sonar_t sonar;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    slam_config_default(&cfg);
    slam_config_paper(&cfg); /* these tests hold the paper's Eq. 6 */
    sonar_init(&sonar, &cfg);
    return 0;
}

static void test_bearing_of_the_six_stops(void **state)
{
    (void)state;
    /* Eq. 3 with the robot facing +x: servo 90° is straight ahead, 65° is 25° to the left,
     * 155° is 65° to the right. */
    static const int32_t servo_deg[6] = {65, 83, 101, 119, 137, 155};
    static const int32_t bearing_deg[6] = {25, 7, -11, -29, -47, -65};
    for (int i = 0; i < 6; i++) {
        bam32_t servo = fix_bam_from_mdeg(servo_deg[i] * 1000);
        assert_int_equal(fix_bam_to_mdeg(sonar_bearing(&sonar, 0u, servo)), bearing_deg[i] * 1000);
        /* Facing 90° (+y) and 350° (across the wrap). */
        bam32_t h90 = fix_bam_from_mdeg(90000);
        assert_int_equal(fix_bam_to_mdeg(sonar_bearing(&sonar, h90, servo)),
                         90000 + bearing_deg[i] * 1000);
        bam32_t h350 = fix_bam_from_mdeg(350000);
        int32_t expect = -10000 + bearing_deg[i] * 1000;
        assert_true(abs(fix_bam_to_mdeg(sonar_bearing(&sonar, h350, servo)) - expect) <= 1);
    }
    /* A mount yaw turns every bearing. */
    cfg.mount_yaw_mdeg = -20000;
    sonar_init(&sonar, &cfg);
    assert_int_equal(fix_bam_to_mdeg(sonar_bearing(&sonar, 0u, fix_bam_from_mdeg(110000))), -40000);
}

/* Eq. 3-5 with the mount offset, in double. */
static void ref_obstacle(const slam_config_t *c, double x, double y, double th, double servo_deg,
                         double d, double *xo, double *yo)
{
    double xs = x + c->mount_x_um * cos(th) - c->mount_y_um * sin(th);
    double ys = y + c->mount_x_um * sin(th) + c->mount_y_um * cos(th);
    double theta = th + (PI / 2.0 - servo_deg * PI / 180.0) + c->mount_yaw_mdeg * PI / 180000.0;
    *xo = xs + d * cos(theta);
    *yo = ys + d * sin(theta);
}

static void test_obstacle_point_against_double(void **state)
{
    (void)state;
    test_rng_t rng = {17u};
    double worst = 0.0;
    for (int i = 0; i < 200000; i++) {
        cfg.mount_x_um = test_rng_range(&rng, -100000, 100000);
        cfg.mount_y_um = test_rng_range(&rng, -100000, 100000);
        cfg.mount_yaw_mdeg = test_rng_range(&rng, -30000, 30000);
        sonar_init(&sonar, &cfg);
        odom_pose_t p = {
            .x_um = test_rng_range(&rng, -20000000, 20000000),
            .y_um = test_rng_range(&rng, -20000000, 20000000),
            .heading = (bam32_t)test_rng_u64(&rng),
        };
        int32_t servo_mdeg = test_rng_range(&rng, 0, 180000);
        uint32_t d = (uint32_t)test_rng_range(&rng, 0, 4000000);
        int32_t xo;
        int32_t yo;
        sonar_obstacle(&sonar, &p, fix_bam_from_mdeg(servo_mdeg), d, &xo, &yo);
        double rx;
        double ry;
        double th = p.heading * (2.0 * PI / 4294967296.0);
        ref_obstacle(&cfg, p.x_um, p.y_um, th, servo_mdeg / 1000.0, d, &rx, &ry);
        double err = hypot(xo - rx, yo - ry);
        /* Table error 5e-6 on every rotated length, plus rounding. */
        double bound =
            2.0 + 1e-5 * (d + fabs((double)cfg.mount_x_um) + fabs((double)cfg.mount_y_um));
        assert_true(err <= bound);
        worst = err > worst ? err : worst;
    }
    printf("obstacle point: worst error %.2f um over 200000 random readings\n", worst);
}

static void test_paper_equations_without_offset(void **state)
{
    (void)state;
    cfg.mount_x_um = 0;
    sonar_init(&sonar, &cfg);
    /* Robot at (1 m, 2 m) facing +y; servo 90° looks along +y: 0.5 m ahead is (1, 2.5). */
    odom_pose_t p = {1000000, 2000000, FIX_BAM_QUARTER};
    int32_t x;
    int32_t y;
    sonar_obstacle(&sonar, &p, fix_bam_from_mdeg(90000), 500000u, &x, &y);
    assert_int_equal(x, 1000000);
    assert_int_equal(y, 2500000);
    /* Servo 180° looks 90° to the right of the heading: along +x. */
    sonar_obstacle(&sonar, &p, fix_bam_from_mdeg(180000), 500000u, &x, &y);
    assert_int_equal(x, 1500000);
    assert_int_equal(y, 2000000);
}

static void test_echo_width_to_range(void **state)
{
    (void)state;
    /* 343 m/s: 171.5 µm of range per µs of echo; 5831 µs is about a metre. */
    assert_int_equal(sonar_range_um(&sonar, 0u), 0u);
    assert_int_equal(sonar_range_um(&sonar, 2u), 343u);
    assert_int_equal(sonar_range_um(&sonar, 5831u), 1000017u); /* 1000016.5 rounds up */
    assert_int_equal(sonar_range_um(&sonar, 38000u), 6517000u);
    assert_int_equal(sonar_range_um(&sonar, UINT32_MAX), UINT32_MAX); /* saturates */
    test_rng_t rng = {23u};
    for (int i = 0; i < 100000; i++) {
        cfg.sound_speed_mm_per_s = (uint32_t)test_rng_range(&rng, 300000, 400000);
        sonar_init(&sonar, &cfg);
        uint32_t w = (uint32_t)test_rng_range(&rng, 0, 40000);
        double exact = w * (cfg.sound_speed_mm_per_s / 2000.0);
        assert_true(fabs(sonar_range_um(&sonar, w) - exact) <= 1.0);
    }
}

static void test_confidence_sector_bounds(void **state)
{
    (void)state;
    assert_false(sonar_in_confidence(&sonar, 19999u));
    assert_true(sonar_in_confidence(&sonar, 20000u));
    assert_true(sonar_in_confidence(&sonar, 999999u));
    assert_false(sonar_in_confidence(&sonar, 1000000u));
    assert_false(sonar_in_confidence(&sonar, UINT32_MAX));
}

static grid_t grid;

/* Readings at or beyond rc, at every stop and heading, never touch OM. */
static void test_far_readings_never_touch_om(void **state)
{
    (void)state;
    mapper_t m;
    mapper_init(&m, &cfg);
    grid_init(&grid, &cfg);
    static const uint32_t ranges[] = {1000000u, 1000001u, 1500000u, 3999999u, 6517000u, UINT32_MAX};
    unsigned n = 0;
    for (int h = 0; h < 360; h += 15) {
        odom_pose_t p = {0, 0, fix_bam_from_mdeg(h * 1000)};
        for (int s = 65; s <= 155; s += 18) {
            for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; r++) {
                assert_int_equal(
                    mapper_reading(&m, &grid, &p, fix_bam_from_mdeg(s * 1000), ranges[r]),
                    MAPPER_FAR);
                n++;
            }
        }
    }
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(grid.om[i], 0);
    }
    assert_int_equal(m.far, n);
    assert_int_equal(m.hits, 0u);
    /* One µm inside the sector does. */
    odom_pose_t p = {0, 0, 0u};
    assert_int_equal(mapper_reading(&m, &grid, &p, fix_bam_from_mdeg(90000), 999999u), MAPPER_HIT);
    assert_int_equal(m.hits, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_bearing_of_the_six_stops, setup),
        cmocka_unit_test_setup(test_obstacle_point_against_double, setup),
        cmocka_unit_test_setup(test_paper_equations_without_offset, setup),
        cmocka_unit_test_setup(test_echo_width_to_range, setup),
        cmocka_unit_test_setup(test_confidence_sector_bounds, setup),
        cmocka_unit_test_setup(test_far_readings_never_touch_om, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
