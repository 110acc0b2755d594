/* SPDX-License-Identifier: MIT */
/* Tests of the escape from a place without progress (moves.c): the places where the robot
 * made progress, and backing out along them after turning about too long. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "explore_world.h"
#include "modes.h"
#include "moves.h"

/* The place of progress k places older than the newest: its x. */
static int32_t place_x(uint32_t k)
{
    return ex.moves.prog_x_um[(ex.moves.prog_head - k) & (EXPLORE_PROGRESS_KEPT - 1u)];
}

static int32_t place_y(uint32_t k)
{
    return ex.moves.prog_y_um[(ex.moves.prog_head - k) & (EXPLORE_PROGRESS_KEPT - 1u)];
}

/* Progress checked at a place dx_um east of the start, at `now`. */
static void progress_at(int32_t dx_um, uint32_t now)
{
    odom_pose_t p = {cfg.start_x_um + dx_um, cfg.start_y_um, 0};
    ex.machine.now = now;
    explore_progress(&ex, &p);
}

/* Progress is coming 0.25 m from the last place of progress and from the one before it:
 * going to and fro between two places is none. */
static void test_places_of_progress(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    const int32_t x0 = cfg.start_x_um;
    progress_at(249000, 100u);
    assert_int_equal(place_x(0u), x0);
    assert_int_equal(ex.moves.prog_at, 0u);
    progress_at(250000, 200u);
    assert_int_equal(place_x(0u), x0 + 250000);
    assert_int_equal(place_x(1u), x0);
    assert_int_equal(ex.moves.prog_at, 200u);
    progress_at(0, 300u); /* back where it was: 0.25 m from the last, not from the one before */
    assert_int_equal(place_x(0u), x0 + 250000);
    assert_int_equal(ex.moves.prog_at, 200u);
    progress_at(500000, 400u);
    assert_int_equal(place_x(0u), x0 + 500000);
    assert_int_equal(place_x(1u), x0 + 250000);
    assert_int_equal(place_x(2u), x0);
    assert_int_equal(ex.moves.prog_at, 400u);
    assert_int_equal(ex.moves.prog_n, 3u);
    for (uint32_t k = 0u; k < 2u * EXPLORE_PROGRESS_KEPT; k++) {
        progress_at((int32_t)(750000u + 250000u * k), 500u + k);
    }
    assert_int_equal(ex.moves.prog_n, EXPLORE_PROGRESS_KEPT); /* the oldest are forgotten */
    assert_int_equal(place_x(0u), x0 + 750000 + 250000 * (2 * (int32_t)EXPLORE_PROGRESS_KEPT - 1));
}

/* An escape that gets nowhere (it stalls as it begins to back out) is no progress where it
 * began, though the places it would have backed out along have left the list; 0.25 m on
 * from there is. */
static void test_an_escape_that_got_nowhere_is_no_progress(void **state)
{
    (void)state;
    setup_mode(EXPLORE_TM);
    for (uint32_t k = 1u; k <= 4u; k++) {
        progress_at((int32_t)(250000u * k), 100u * k);
    }
    assert_int_equal(ex.moves.prog_n, 5u);
    odom_pose_t p = {cfg.start_x_um + 1000000, cfg.start_y_um, 0};
    ex.machine.now = 400u + EXPLORE_STUCK_TICKS;
    explore_turn_by(&ex, &p, (int32_t)EXPLORE_DEG(45), EXPLORE_FORWARD);
    assert_int_equal(ex.count.escapes, 1u);
    assert_int_equal(ex.machine.state, EXPLORE_BACK);
    int32_t target_mm_s[2] = {0, 0};
    (void)explore_back_step(&ex, &p, target_mm_s); /* takes the places */
    assert_int_equal(ex.moves.prog_n, 3u);
    assert_int_equal(place_x(0u), cfg.start_x_um + 500000); /* 0.5 m behind */
    progress_at(1000000 - 10000, 3000u);
    assert_int_equal(ex.moves.prog_n, 3u);
    assert_int_equal(ex.moves.prog_at, 400u + EXPLORE_STUCK_TICKS);
    progress_at(1000000 + 250000, 3100u);
    assert_int_equal(ex.moves.prog_n, 4u);
    assert_int_equal(ex.moves.prog_at, 3100u);
}

/* Walls round a point, `half_m` from it on every side. */
static void box(double x_m, double y_m, double half_m)
{
    add_wall(x_m - half_m, y_m - half_m, x_m + half_m, y_m - half_m);
    add_wall(x_m + half_m, y_m - half_m, x_m + half_m, y_m + half_m);
    add_wall(x_m + half_m, y_m + half_m, x_m - half_m, y_m + half_m);
    add_wall(x_m - half_m, y_m + half_m, x_m - half_m, y_m - half_m);
}

/*
 * The robot drives 0.6 m east in the open; then every way round it closes within avoid_um
 * (walls 0.25 m off on every side, as among a chair's legs once the robot has turned), and
 * it turns about. The TM mode checks progress at each turn it begins (the walls mode at each
 * trail position as well): the first turn finds it 0.6 m from the start. The first turn it
 * begins EXPLORE_STUCK_TICKS after that is an escape instead: it backs out along the places
 * of progress, the newest first, to the start (the test's world has no contact: the way
 * back is through the box's west wall), then goes on as after backing off (the TM mode
 * looks and weighs every way). The place it left is off the list: the start is the newest
 * again.
 */
static void test_turning_about_escapes_the_way_it_came(void **state)
{
    (void)state;
    setup_mode(EXPLORE_TM);
    box(0.0, 0.0, 3.0); /* far walls: echoes beyond the confidence radius */
    unsigned n = 0u;
    while (px < 600000.0 && n++ < 2000u) {
        world_tick();
    }
    assert_true(px >= 600000.0);
    double bx = px;
    double by = py;
    box(bx / 1e6, by / 1e6, 0.25);
    unsigned turns = ex.count.turns;
    while (ex.count.turns == turns && n++ < 2000u) {
        world_tick();
    }
    /* The start and, 0.6 m on, where the first turn began. */
    assert_int_equal(ex.moves.prog_n, 2u);
    assert_true(place_x(0u) - place_x(1u) >= 550000);
    double start_x = place_x(1u);
    double start_y = place_y(1u);
    uint32_t last = ex.moves.prog_at;
    double moved = 0.0;
    double closest = HUGE_VAL;
    while (ex.count.escapes == 0u && n++ < 10000u) {
        world_tick();
        /* It stops and turns about in place, clear of the box's walls. */
        moved = fmax(moved, hypot(px - bx, py - by));
        closest = fmin(closest, clearance());
    }
    uint32_t waited = ex.machine.now - last;
    printf("%u turns about, then an escape %u ticks after the last progress\n",
           ex.count.turns - turns, waited);
    printf("moved %.0f µm from where it was boxed in, at least %.0f µm from a wall\n", moved,
           closest);
    assert_true(moved < 60000.0 && closest > 150000.0);
    assert_true(ex.count.turns - turns >= 5u);
    assert_true(waited >= EXPLORE_STUCK_TICKS && waited < EXPLORE_STUCK_TICKS + 400u);
    assert_int_equal(ex.machine.state, EXPLORE_BACK);
    double wide = 0.0;
    while (ex.machine.state == EXPLORE_BACK && n++ < 20000u) {
        world_tick();
        wide = fmax(wide, fabs(py));
    }
    printf(
        "backed out to (%.0f, %.0f) µm, the start (%.0f, %.0f), at most %.0f µm off the way in\n",
        px, py, start_x, start_y, wide);
    /* (The firmware's start is its start cell's centre, 25 mm from the world's origin in x
     * and in y: the way in runs along y = 0, the way out to y = 25 mm.) */
    assert_true(hypot(px - start_x, py - start_y) < 30000.0 && wide < 40000.0);
    assert_int_equal(ex.machine.state, EXPLORE_LOOK); /* as after any backing off */
    assert_int_equal(ex.count.escapes, 1u);
    assert_int_equal(ex.moves.prog_n, 1u);
    assert_true(place_x(0u) == start_x && place_y(0u) == start_y);
}

/* A wheel that stalled alone (its count stopped) puts the places of progress where the
 * odometry says: no escape for a minute after it, however long the robot turns about. */
static void test_no_escape_after_a_count_stopped(void **state)
{
    (void)state;
    setup_mode(EXPLORE_TM);
    box(0.0, 0.0, 3.0);
    while (px < 600000.0 && ex.machine.now < 2000u) {
        world_tick();
    }
    box(px / 1e6, py / 1e6, 0.25);
    /* Turning about, one wheel stalls alone as a turn begins. */
    unsigned turns = ex.count.turns;
    while (ex.count.turns == turns && ex.machine.now < 4000u) {
        world_tick();
    }
    ex.moves.one_wheel = true;
    stalled = true;
    world_tick();
    stalled = false;
    ex.moves.one_wheel = false;
    assert_int_equal(ex.count.stalls, 1u);
    uint32_t stood = ex.machine.now;
    while (ex.machine.now - stood < EXPLORE_DOUBT_TICKS - 200u) {
        world_tick();
    }
    assert_int_equal(ex.count.escapes, 0u);
    while (ex.count.escapes == 0u && ex.machine.now - stood < EXPLORE_DOUBT_TICKS + 3000u) {
        world_tick();
    }
    printf("the first escape %u ticks after the stall\n", ex.machine.now - stood);
    assert_int_equal(ex.count.escapes, 1u);
}

/* No way in known (boxed in where it started, so one place of progress only): the escape
 * squeezes instead of backing out, the body's own corridor ahead (memory.narrow) until the
 * robot makes progress; then the usual corridor again. */
static void test_no_way_in_squeezes(void **state)
{
    (void)state;
    setup_mode(EXPLORE_TM);
    box(0.0, 0.0, 3.0);
    box(0.0, 0.0, 0.25);
    while (ex.count.escapes == 0u && ex.machine.now < 4000u) {
        world_tick();
    }
    assert_int_equal(ex.count.escapes, 1u);
    assert_int_equal(ex.moves.prog_n, 1u);
    assert_true(ex.memory.narrow && ex.moves.squeezing);
    assert_int_not_equal(ex.machine.state, EXPLORE_BACK);
    nwalls -= 4u; /* the box round the start opens */
    uint32_t squeezed = ex.machine.now;
    while (ex.moves.prog_n == 1u && ex.machine.now < 10000u) {
        world_tick();
    }
    printf("progress %u ticks after the box opened\n", ex.machine.now - squeezed);
    assert_int_equal(ex.moves.prog_n, 2u);
    assert_false(ex.memory.narrow || ex.moves.squeezing);
}

/* Boxed in, in the walls mode: a full circle of 45° looks, every one blocked, backs out
 * the way it came at once, however lately the robot made progress; a robot that knows no
 * way in squeezes and weighs the ways instead. */
static void test_a_circle_of_blocked_looks_backs_out_at_once(void **state)
{
    (void)state;
    static const uint32_t known[] = {4u, 1u}; /* places of progress, the start's included */
    for (size_t i = 0u; i < sizeof known / sizeof known[0]; i++) {
        uint32_t places = known[i];
        setup_mode(EXPLORE_WALLS);
        for (uint32_t k = 1u; k < places; k++) {
            progress_at((int32_t)(250000u * k), 100u * k);
        }
        odom_pose_t p = {cfg.start_x_um + 250000 * ((int32_t)places - 1), cfg.start_y_um, 0};
        ex.machine.now = 100u * places + 1u; /* just after its last progress */
        ex.moves.after_turn = EXPLORE_FOLLOW;
        for (uint32_t k = 0u; k < EXPLORE_LEFTS_MAX; k++) {
            explore_walls_next(&ex, &p, EXPLORE_WHY_BLOCKED);
            assert_int_equal(ex.machine.state, EXPLORE_TURN); /* on to the left, 45° */
        }
        assert_int_equal(ex.count.escapes, 0u);
        explore_walls_next(&ex, &p, EXPLORE_WHY_BLOCKED); /* the circle is closed */
        assert_int_equal(ex.count.escapes, 1u);
        if (places > 1u) {
            assert_int_equal(ex.machine.state, EXPLORE_BACK);
            assert_true(ex.moves.escaping);
        } else {
            assert_true(ex.moves.squeezing && ex.memory.narrow);
            assert_int_equal(ex.machine.state, EXPLORE_DECIDE);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_places_of_progress),
        cmocka_unit_test(test_an_escape_that_got_nowhere_is_no_progress),
        cmocka_unit_test(test_turning_about_escapes_the_way_it_came),
        cmocka_unit_test(test_no_escape_after_a_count_stopped),
        cmocka_unit_test(test_no_way_in_squeezes),
        cmocka_unit_test(test_a_circle_of_blocked_looks_backs_out_at_once),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
