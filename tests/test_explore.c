/* SPDX-License-Identifier: MIT */
/* Tests of exploration: look, avoid, turn, TM-guided headings, the square, determinism. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "slam/error.h"
#include "slam/explore.h"

static const double PI = 3.14159265358979323846;

static slam_config_t cfg;
static explore_t ex;
static bool stalled; /* what motion_stalled() says in the next tick */
static mapper_t mapper;
static grid_t grid;

/* An ideal robot: the wheels do exactly what the exploration asks. */
static double px, py, pth; /* µm, µm, rad */
static int32_t target[2];

static odom_pose_t pose(void)
{
    double th = fmod(pth, 2.0 * PI);
    th = th < 0 ? th + 2.0 * PI : th;
    return (odom_pose_t){(int32_t)lround(px), (int32_t)lround(py),
                         (bam32_t)(uint64_t)llround(th / (2.0 * PI) * 4294967296.0)};
}

static void move(void)
{
    double vl = target[0] * 10.0; /* µm per tick */
    double vr = target[1] * 10.0;
    double dth = (vr - vl) / cfg.wheel_base_um;
    double du = (vl + vr) / 2.0;
    px += du * cos(pth + dth / 2.0);
    py += du * sin(pth + dth / 2.0);
    pth += dth;
}

static void setup_mode(uint8_t mode)
{
    slam_config_default(&cfg);
    cfg.explore_mode = mode;
    explore_init(&ex, &cfg);
    mapper_init(&mapper, &cfg);
    grid_init(&grid, &cfg);
    px = py = pth = 0.0;
    target[0] = target[1] = 0;
    stalled = false;
}

/* One tick; a reading at a stop (servo 65 + 18·stop degrees) when range_mm >= 0, a
 * timeout when range_mm == -1, none when -2. */
static void tick(int stop, double range_mm)
{
    sweep_out_t sw = {0};
    odom_pose_t p = pose();
    if (range_mm > -1.5) {
        sw.reading_ready = true;
        sw.reading.stop = (uint8_t)stop;
        sw.reading.servo_mdeg = 65000 + 18000 * stop;
        sw.reading.servo = fix_bam_from_mdeg(sw.reading.servo_mdeg);
        sw.reading.echo = range_mm >= 0.0;
        sw.reading.echo_us = sw.reading.echo ? (uint32_t)lround(range_mm * 1000.0 / 171.5) : 0u;
        mapper.ping_pose = p;
    }
    mapper_tick(&mapper, &grid, &p, &sw); /* places the reading's point, as in robot_tick() */
    explore_step(&ex, &p, &sw, &mapper, &grid, stalled, target);
    move();
}

/* How far apart two binary angles are, either way round. */
static uint32_t angle_off(bam32_t a, bam32_t b)
{
    int64_t d = fix_bam_diff(a, b);
    return (uint32_t)(d < 0 ? -d : d);
}

static void full_clear_sweep(void)
{
    for (int s = 0; s < 6; s++) {
        tick(s, -1.0);
    }
}

static void test_off_stands_still(void **state)
{
    (void)state;
    setup_mode(EXPLORE_OFF);
    for (int t = 0; t < 1000; t++) {
        tick(t % 6, 100.0);
        assert_int_equal(target[0], 0);
        assert_int_equal(target[1], 0);
    }
}

static void test_look_then_forward(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    for (int t = 0; t < 50; t++) {
        tick(0, -2.0); /* no readings yet: stand and look */
        assert_int_equal(target[0], 0);
        assert_int_equal(ex.state, EXPLORE_LOOK);
    }
    full_clear_sweep();
    tick(0, -2.0); /* decisions wait for a tick without a reading */
    assert_int_equal(ex.state, EXPLORE_FORWARD);
    tick(0, -2.0);
    assert_int_equal(target[0], 200);
    assert_int_equal(target[1], 200);
}

static void test_obstacle_ahead_turns_away(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    full_clear_sweep();
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_FORWARD);
    /* Servo 101°: 11° to the right; 0.2 m from the sonar. The corridor is checked in the
     * tick after the reading. */
    tick(2, 200.0);
    assert_int_equal(ex.state, EXPLORE_FORWARD);
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_TURN);
    assert_int_equal(ex.avoidances, 1u);
    int32_t turn = fix_bam_diff(ex.target_heading, pose().heading);
    /* Away from the right: to the left, by 90..180°. */
    assert_true(turn >= (int32_t)fix_bam_from_mdeg(89000) && turn <= INT32_MAX);
    tick(0, -2.0);
    assert_true(target[0] < 0 && target[1] > 0); /* counter-clockwise */
    /* The turn ends at the target heading, and the robot looks again. */
    int t = 0;
    while (ex.state == EXPLORE_TURN && t++ < 2000) {
        tick(0, -2.0);
    }
    assert_int_equal(ex.state, EXPLORE_LOOK);
    assert_true(angle_off(ex.target_heading, pose().heading) < fix_bam_from_mdeg(3000));
    /* The obstacle is behind now: looking finds the way clear. */
    full_clear_sweep();
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_FORWARD);
}

/* Wheels that stall while driving (something the sonar missed): back off 0.1 m, then
 * turn away; the square, an odometry experiment, ignores stalls. */
static void test_stall_backs_off_then_turns(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    full_clear_sweep();
    tick(0, -2.0);
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_FORWARD);
    stalled = true;
    tick(0, -2.0);
    stalled = false;
    assert_int_equal(ex.state, EXPLORE_BACK);
    assert_int_equal(ex.stalls, 1u);
    double x0 = px;
    tick(0, -2.0);
    assert_int_equal(target[0], -100);
    assert_int_equal(target[1], -100);
    int t = 0;
    while (ex.state == EXPLORE_BACK && t++ < 500) {
        tick(0, -2.0);
    }
    assert_int_equal(ex.state, EXPLORE_TURN);
    assert_true(x0 - px >= 99000.0 && x0 - px < 102000.0); /* backed off 0.1 m */

    setup_mode(EXPLORE_SQUARE);
    stalled = true;
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_FORWARD);
    assert_int_equal(ex.stalls, 0u);
}

static void test_corridor_and_memory(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    odom_pose_t p = pose();
    /* Servo 155°: 65° to the right; 0.3 m away the point is 0.13 m ahead of the sonar
     * but 0.27 m to the side: outside the 0.13 m corridor. */
    tick(5, 300.0);
    assert_false(explore_blocked(&ex, &p));
    /* Servo 83°: 7° to the left, 0.25 m: ahead and inside. */
    tick(1, 250.0);
    assert_true(explore_blocked(&ex, &p));
    /* Seen from a pose facing the other way, it is behind: no block. */
    odom_pose_t back = {p.x_um, p.y_um, p.heading + FIX_BAM_HALF};
    assert_false(explore_blocked(&ex, &back));
    /* A later timeout at that stop clears it. */
    tick(1, -1.0);
    assert_false(explore_blocked(&ex, &p));
    /* And a point is forgotten after three seconds. */
    tick(1, 250.0);
    for (unsigned t = 0; t < EXPLORE_MEMORY_TICKS - 1u; t++) {
        ex.now++;
    }
    assert_true(explore_blocked(&ex, &p));
    ex.now += 2u;
    assert_false(explore_blocked(&ex, &p));
}

/* Marks the cells along a heading from the origin, 0.05 .. 1 m. */
static void paint_ray(double deg, uint8_t *map, uint8_t value, double from_m, double to_m)
{
    for (double r = from_m; r <= to_m; r += 0.01) {
        grid_cell_t c;
        int32_t x = (int32_t)lround(r * 1e6 * cos(deg * PI / 180.0));
        int32_t y = (int32_t)lround(r * 1e6 * sin(deg * PI / 180.0));
        if (grid_cell_of(&grid, x, y, &c) == SLAM_OK) {
            map[grid_index(c)] = value;
        }
    }
}

static void test_tm_mode_heads_for_the_least_visited(void **state)
{
    (void)state;
    setup_mode(EXPLORE_TM);
    memset(grid.tm, 30, sizeof grid.tm);
    paint_ray(90.0, grid.tm, 0u, 0.03, 1.2);
    paint_ray(180.0, grid.tm, 5u, 0.03, 1.2);
    full_clear_sweep();
    assert_int_equal(ex.state, EXPLORE_LOOK);
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_DECIDE);
    unsigned t = 0;
    while (ex.state == EXPLORE_DECIDE && t++ < 200u) {
        tick(0, -2.0);
    }
    printf("TM decision: %u ticks\n", t);
    assert_true(t <= 64u); /* standing still well under a second */
    assert_int_equal(ex.state, EXPLORE_TURN);
    assert_true(angle_off(ex.target_heading, FIX_BAM_QUARTER) < fix_bam_from_mdeg(1000));

    /* An obstacle in OM 0.3 m along 90° makes that way the worst; 180° wins. */
    setup_mode(EXPLORE_TM);
    memset(grid.tm, 30, sizeof grid.tm);
    paint_ray(90.0, grid.tm, 0u, 0.03, 1.2);
    paint_ray(180.0, grid.tm, 5u, 0.03, 1.2);
    paint_ray(90.0, grid.om, 200u, 0.28, 0.32); /* log-odds +72: occupied */
    full_clear_sweep();
    tick(0, -2.0);
    assert_int_equal(ex.state, EXPLORE_DECIDE);
    t = 0;
    while (ex.state == EXPLORE_DECIDE && t++ < 200u) {
        tick(0, -2.0);
    }
    assert_int_equal(ex.state, EXPLORE_TURN);
    assert_true(angle_off(ex.target_heading, FIX_BAM_HALF) < fix_bam_from_mdeg(1000));
}

static void test_square_returns_to_the_start(void **state)
{
    (void)state;
    setup_mode(EXPLORE_SQUARE);
    int t = 0;
    while (ex.state != EXPLORE_STOP && t++ < 20000) {
        tick(t % 6, 100.0); /* readings do not matter to the square */
    }
    assert_int_equal(ex.state, EXPLORE_STOP);
    assert_int_equal(ex.turns, 3u);
    /* An ideal robot ends near where it began: each turn stops within 1° of its corner
     * (17 mm off over a 1 m leg), each leg within a tick's travel (2 mm). */
    printf("square: ends %.1f mm from the start\n", hypot(px, py) / 1000.0);
    assert_true(hypot(px, py) < 3.0 * 17500.0 + 4.0 * 2000.0);
    assert_true(fabs(remainder(pth - 1.5 * PI, 2.0 * PI)) < PI / 180.0); /* facing -y */
    tick(0, -2.0);
    assert_int_equal(target[0], 0);
    assert_int_equal(target[1], 0);
}

/* The random exploration in a test arena: an obstacle ahead whenever the robot has driven
 * more than 0.5 m from its last turn. Returns a fingerprint of its turns. */
static uint64_t random_run(uint32_t seed)
{
    setup_mode(EXPLORE_RANDOM);
    cfg.explore_seed = seed;
    explore_init(&ex, &cfg);
    uint64_t h = 1469598103934665603ull;
    double x0 = 0.0;
    double y0 = 0.0;
    for (int t = 0; t < 20000; t++) {
        /* A reading every fifth tick, as the sweep delivers them. */
        int stop = (t / 5) % 6;
        double r = hypot(px - x0, py - y0) > 500000.0 ? 150.0 : -1.0;
        uint8_t before = ex.state;
        tick(stop, t % 5 != 0 ? -2.0 : stop == 2 ? r : -1.0);
        if (ex.state == EXPLORE_TURN && before != EXPLORE_TURN) {
            h = (h ^ ex.target_heading) * 1099511628211ull;
            x0 = px;
            y0 = py;
        }
    }
    assert_true(ex.turns > 10u);
    return h;
}

static void test_random_is_deterministic_for_a_seed(void **state)
{
    (void)state;
    uint64_t a = random_run(7u);
    uint64_t b = random_run(7u);
    uint64_t c = random_run(8u);
    assert_true(a == b);
    assert_true(a != c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_off_stands_still),
        cmocka_unit_test(test_look_then_forward),
        cmocka_unit_test(test_obstacle_ahead_turns_away),
        cmocka_unit_test(test_stall_backs_off_then_turns),
        cmocka_unit_test(test_corridor_and_memory),
        cmocka_unit_test(test_tm_mode_heads_for_the_least_visited),
        cmocka_unit_test(test_square_returns_to_the_start),
        cmocka_unit_test(test_random_is_deterministic_for_a_seed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
