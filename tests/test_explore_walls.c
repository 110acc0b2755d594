/* SPDX-License-Identifier: MIT */
/* Tests of the walls mode: following what is on the right, corners, openings passed at
 * their middle, leaving a wall driven before, the frontier of blocks. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "explore_world.h"
#include "slam/error.h"

/* Runs the world until cond() holds or n ticks pass; the closest the body came to a wall
 * (centre distance less the 90 mm radius) in *closest. Returns the ticks run. */
static unsigned run_until(bool (*cond)(void), unsigned n, double *closest)
{
    unsigned t = 0;
    while (t < n && (cond == NULL || !cond())) {
        world_tick();
        double c = clearance() - 90000.0;
        if (closest != NULL && c < *closest) {
            *closest = c;
        }
        t++;
    }
    return t;
}

static bool following(void)
{
    return ex.machine.state == EXPLORE_FOLLOW;
}

/* A long wall 0.25 m to the right: the robot follows it at follow_um, never nearer than
 * the body allows. */
static void test_follows_a_wall_on_the_right(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 12.0, -0.25);
    double closest = HUGE_VAL;
    run_until(following, 3000u, &closest);
    assert_int_equal(ex.machine.state, EXPLORE_FOLLOW);
    double lo = HUGE_VAL;
    double hi = 0.0;
    run_until(NULL, 1000u, &closest); /* settle */
    while (px < 8e6 && ex.machine.state == EXPLORE_FOLLOW) {
        world_tick();
        double d = py + 250000.0; /* the axle above the wall */
        lo = d < lo ? d : lo;
        hi = d > hi ? d : hi;
    }
    printf("followed at %.0f .. %.0f mm, closest %.0f mm\n", lo / 1000.0, hi / 1000.0,
           closest / 1000.0);
    assert_true(px >= 8e6); /* all the way along */
    assert_true(lo > cfg.follow_um - 60000.0 && hi < cfg.follow_um + 60000.0);
    assert_true(closest > 100000.0);
}

static bool heading_north(void)
{
    return ex.machine.state == EXPLORE_FOLLOW &&
           fabs(remainder(pth - EW_PI / 2.0, 2.0 * EW_PI)) < 0.1 && py > 0.0;
}

/* A concave corner: the wall ahead makes the robot turn left and follow it too. */
static void test_concave_corner_turns_left(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 2.0, -0.25);
    add_wall(2.0, -0.25, 2.0, 5.0);
    double closest = HUGE_VAL;
    unsigned t = run_until(heading_north, 20000u, &closest);
    printf("round the corner in %u ticks, closest %.0f mm, at x %.0f mm\n", t, closest / 1000.0,
           px / 1000.0);
    assert_true(heading_north());
    run_until(NULL, 1500u, &closest);
    assert_true(fabs(px - (2e6 - cfg.follow_um)) < 60000.0);
    assert_true(closest > 100000.0);
}

/* Round the end of a wall (a convex corner) the robot arcs right at the follow distance
 * and follows the wall's other side back. */
static void test_convex_corner_arcs_right(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 2.0, -0.25); /* a free-standing wall, ending at x = 2 m */
    double closest = HUGE_VAL;
    run_until(following, 3000u, &closest);
    bool back = false;
    for (unsigned t = 0; t < 12000u && !back; t++) {
        world_tick();
        double c = clearance() - 90000.0;
        closest = c < closest ? c : closest;
        back = py < -0.25e6 && fabs(remainder(pth - EW_PI, 2.0 * EW_PI)) < 0.3;
    }
    printf("round the end: (%.0f, %.0f) mm, closest %.0f mm\n", px / 1000.0, py / 1000.0,
           closest / 1000.0);
    assert_true(back); /* heading west on the wall's far side */
    assert_true(closest > 100000.0);
}

static bool passed(void)
{
    return py < -350000.0; /* the body wholly beyond the wall's line (-0.25 m) */
}

/* A wall to the right with a 0.36 m opening (twice the body's width): the robot
 * finds it, measures it on the map, backs up to its middle, turns and passes it, never
 * nearer to its edges than 40 mm; then it turns right, to follow the wall's far side. */
static void test_opening_is_passed_at_its_middle(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 1.5, -0.25);
    add_wall(1.86, -0.25, 6.0, -0.25);
    double closest = HUGE_VAL;
    unsigned t = run_until(passed, 20000u, &closest);
    printf("through at x %.0f mm after %u ticks, closest %.0f mm, doors %u\n", px / 1000.0, t,
           closest / 1000.0, ex.count.doors);
    assert_true(passed());
    assert_true(px > 1.5e6 && px < 1.86e6);
    assert_true(closest > 40000.0);
    assert_true(ex.count.doors >= 1u);
    run_until(following, 1000u, &closest);
    run_until(NULL, 1000u, &closest);
    printf("then at (%.0f, %.0f) mm heading %.0f°\n", px / 1000.0, py / 1000.0,
           pth * 180.0 / EW_PI);
    assert_int_equal(ex.machine.state, EXPLORE_FOLLOW);
    assert_true(py < -0.25e6 && px < 1.5e6); /* west, along the far side */
    assert_true(closest > 40000.0);
}

/* The same wall without the opening: no opening is passed. */
static void test_a_whole_wall_has_no_opening(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 12.0, -0.25);
    double closest = HUGE_VAL;
    run_until(NULL, 6000u, &closest);
    assert_true(py > -0.25e6);
    assert_int_equal(ex.count.doors, 0u);
}

/* Along a wall driven before (TM ahead), the robot leaves it and seeks the frontier. */
static void test_leaves_a_wall_driven_before(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    add_wall(-1.0, -0.25, 12.0, -0.25);
    for (int32_t x = 0; x < 5000000; x += 10000) {
        grid_cell_t c;
        if (grid_cell_of(&grid, x, 50000, &c) == SLAM_OK) {
            grid.tm[grid_index(&grid, c)] = 5u;
        }
    }
    run_until(following, 3000u, NULL);
    bool left = false;
    for (unsigned t = 0; t < 4000u && !left; t++) {
        world_tick();
        left = ex.machine.state == EXPLORE_SEEK || ex.machine.state == EXPLORE_DECIDE;
    }
    printf("left the wall at x %.0f mm\n", px / 1000.0);
    assert_true(left);
    assert_true(px < 2e6);
}

/* Marks a block explored. */
static void explored(uint32_t ba, uint32_t bb)
{
    uint32_t k = bb * EXPLORE_BLOCKS_A + ba;
    ex.seek.explored[k >> 3] = (uint8_t)(ex.seek.explored[k >> 3] | (1u << (k & 7u)));
}

static bool is_dead(uint32_t ba, uint32_t bb)
{
    uint32_t k = bb * EXPLORE_BLOCKS_A + ba;
    return (ex.seek.dead[k >> 3] & (1u << (k & 7u))) != 0u;
}

/* SEEK: the nearest block next to an explored one, in sight; one hidden behind an
 * occupied wall on the map is given up; FACE then turns toward the one found. */
static void test_seeks_the_nearest_frontier_in_sight(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    grid_cell_t here;
    assert_int_equal(grid_cell_of(&grid, 0, 0, &here), SLAM_OK);
    uint32_t ba = here.a >> EXPLORE_BLOCK_SHIFT;
    uint32_t bb = here.b >> EXPLORE_BLOCK_SHIFT;
    /* Five by five blocks explored about the robot's; the nearest frontier blocks are the
     * ones south and west of it, equally far. A wall 1.2 m south hides the south one. */
    for (uint32_t j = bb - 2u; j <= bb + 2u; j++) {
        for (uint32_t i = ba - 2u; i <= ba + 2u; i++) {
            explored(i, j);
        }
    }
    for (int32_t x = -3000000; x <= 3000000; x += 20000) {
        grid_cell_t c;
        if (grid_cell_of(&grid, x, -1200000, &c) == SLAM_OK) {
            grid.om[grid_index(&grid, c)] = ew_om_occupied();
        }
    }
    /* Following, with the way ahead driven before: the robot leaves the wall and seeks. */
    ex.machine.state = EXPLORE_FOLLOW;
    ex.walls.retrace = 100u;
    unsigned t = 0;
    while (ex.machine.state != EXPLORE_FACE && t++ < 2000u) {
        quiet_tick();
        px = py = pth = 0.0; /* stand still */
    }
    uint32_t ta = ex.seek.target % EXPLORE_BLOCKS_A;
    uint32_t tb = ex.seek.target / EXPLORE_BLOCKS_A;
    printf("sought in %u ticks: block (%u, %u), from (%u, %u)\n", t, ta, tb, ba, bb);
    assert_int_equal(ex.machine.state, EXPLORE_FACE);
    assert_true(is_dead(ba, bb - 3u));
    assert_int_equal(ta, ba - 3u); /* west, beside the robot's row */
    assert_true(tb + 1u >= bb && tb <= bb + 1u);
    /* FACE turns toward it, then the robot looks. */
    t = 0;
    while (ex.machine.state == EXPLORE_FACE && t++ < 2000u) {
        quiet_tick();
    }
    assert_int_equal(ex.machine.state, EXPLORE_LOOK);
    double bx = (double)grid.origin_x_um + ((ta << EXPLORE_BLOCK_SHIFT) + 8u) * 50000.0;
    double by = (double)grid.origin_y_um + ((tb << EXPLORE_BLOCK_SHIFT) + 8u) * 50000.0;
    double want = atan2(by - py, bx - px);
    printf("facing %.1f°, the target at %.1f°\n", pth * 180.0 / EW_PI, want * 180.0 / EW_PI);
    assert_true(fabs(remainder(pth - want, 2.0 * EW_PI)) < 3.0 * EW_PI / 180.0);
}

/* The rolling scan marks a block explored once it holds a known free cell. */
static void test_free_cells_explore_their_block(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    grid_cell_t c = {200u % SLAM_GRID_A, 10u};
    grid.tm[grid_index(&grid, c)] = 1u;
    grid.om[grid_index(&grid, c)] = ew_om_free();
    assert_int_equal(grid_state(&grid, grid_index(&grid, c)), GRID_FREE);
    uint32_t k = (c.b >> EXPLORE_BLOCK_SHIFT) * EXPLORE_BLOCKS_A + (c.a >> EXPLORE_BLOCK_SHIFT);
    assert_true((ex.seek.explored[k >> 3] & (1u << (k & 7u))) == 0u);
    for (unsigned t = 0;
         t < 20u * SLAM_GRID_CELLS / 8u && (ex.seek.explored[k >> 3] & (1u << (k & 7u))) == 0u;
         t++) {
        quiet_tick();
        px = py = pth = 0.0;
    }
    assert_true((ex.seek.explored[k >> 3] & (1u << (k & 7u))) != 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_follows_a_wall_on_the_right),
        cmocka_unit_test(test_concave_corner_turns_left),
        cmocka_unit_test(test_convex_corner_arcs_right),
        cmocka_unit_test(test_opening_is_passed_at_its_middle),
        cmocka_unit_test(test_a_whole_wall_has_no_opening),
        cmocka_unit_test(test_leaves_a_wall_driven_before),
        cmocka_unit_test(test_seeks_the_nearest_frontier_in_sight),
        cmocka_unit_test(test_free_cells_explore_their_block),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
