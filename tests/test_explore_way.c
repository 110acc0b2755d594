/* SPDX-License-Identifier: MIT */
/* Tests of the walls mode's way to a frontier out of sight (way.c), worked out a slice a
 * call as robot_idle() does, and of the exploration saying it is done (seek.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "explore_world.h"
#include "slam/error.h"
#include "way.h"

/* Grid cells: the test's grid is 60 x 60 cells of 50 mm (3 m), 12 x 12 way cells. */
#define N 60u

static void set_cell(uint32_t a, uint32_t b, uint8_t om)
{
    grid.om[b * grid.a_cells + a] = om;
}

/* Known free: columns [a0, a1) of rows [b0, b1). */
static void free_box(uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1)
{
    for (uint32_t b = b0; b < b1; b++) {
        for (uint32_t a = a0; a < a1; a++) {
            set_cell(a, b, ew_om_free());
        }
    }
}

/* A wall of occupied cells along column a, rows [b0, b1). */
static void wall_column(uint32_t a, uint32_t b0, uint32_t b1)
{
    for (uint32_t b = b0; b < b1; b++) {
        set_cell(a, b, ew_om_occupied());
    }
}

static void setup_grid(void)
{
    setup_mode(EXPLORE_WALLS);
    cfg.grid_a = N;
    cfg.grid_b = N;
    cfg.start_cell_a = 10u;
    cfg.start_cell_b = 30u;
    explore_init(&ex, &cfg);
    grid_init(&grid, &cfg);
}

/* Room A (columns 0-29) known free, room B beyond a wall at column 30 unknown, but for an
 * opening in the wall at rows [b0, b1), known three cells deep. */
static void two_rooms(uint32_t b0, uint32_t b1)
{
    setup_grid();
    free_box(0u, 30u, 0u, N);
    wall_column(30u, 0u, b0);
    wall_column(30u, b1, N);
    free_box(30u, 33u, b0, b1);
}

/* The centre of a grid cell, in µm. */
static odom_pose_t at_cell(uint32_t a, uint32_t b)
{
    return (odom_pose_t){grid.origin_x_um + (int32_t)(a * grid.cell_um + grid.cell_um / 2u),
                         grid.origin_y_um + (int32_t)(b * grid.cell_um + grid.cell_um / 2u), 0u};
}

/* Ask from a cell and work until answered; the calls it took in *calls. */
static explore_way_result_t ask(uint32_t a, uint32_t b, uint32_t now, int32_t *x, int32_t *y,
                                unsigned *calls)
{
    odom_pose_t p = at_cell(a, b);
    explore_way_ask(&ex.way, &p, now);
    explore_way_result_t res = EXPLORE_WAY_NONE;
    unsigned n = 0u;
    while (!explore_way_answer(&ex.way, &res, x, y)) {
        explore_way_work(&ex.way, &grid);
        n++;
        assert_true(n < 10000u);
    }
    if (calls != NULL) {
        *calls = n;
    }
    return res;
}

/* The answer alone, from a cell. */
static explore_way_result_t result_at(uint32_t a, uint32_t b, uint32_t now)
{
    int32_t x;
    int32_t y;
    return ask(a, b, now, &x, &y, NULL);
}

/* Whether a straight line between two world points crosses an occupied cell. */
static bool clear_line(int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    for (int i = 0; i <= 200; i++) {
        grid_cell_t c;
        int32_t x = x0 + (int32_t)((int64_t)(x1 - x0) * i / 200);
        int32_t y = y0 + (int32_t)((int64_t)(y1 - y0) * i / 200);
        if (grid_cell_of(&grid, x, y, &c) != 0 ||
            grid_state(&grid, grid_index(&grid, c)) == GRID_OCCUPIED) {
            return false;
        }
    }
    return true;
}

/* Two rooms: with an opening in the wall between them the way leads toward it, to a point
 * the robot sees; with the wall whole there is no frontier to reach. */
static void test_way_through_an_opening(void **state)
{
    (void)state;
    setup_grid();
    free_box(0u, 30u, 0u, N);
    wall_column(30u, 0u, N);
    assert_int_equal(result_at(10u, 30u, 1u), EXPLORE_WAY_NONE);

    two_rooms(20u, 36u); /* an opening of 0.8 m */
    int32_t x;
    int32_t y;
    unsigned calls = 0u;
    assert_int_equal(ask(10u, 30u, 1u, &x, &y, &calls), EXPLORE_WAY_TO);
    odom_pose_t p = at_cell(10u, 30u);
    grid_cell_t c;
    assert_int_equal(grid_cell_of(&grid, x, y, &c), SLAM_OK);
    printf("the way's point: cell (%u, %u), after %u calls\n", c.a, c.b, calls);
    assert_true(c.a > 10u);                        /* toward the opening */
    assert_true(c.b >= 15u && c.b <= 40u);         /* abreast of it */
    assert_true(clear_line(p.x_um, p.y_um, x, y)); /* in sight */
}

/* A frontier round a corner: the point answered is one the robot sees, on the way. */
static void test_way_round_a_corner(void **state)
{
    (void)state;
    setup_grid();
    /* An L: the robot in the bottom arm (rows 0-19), the top-right arm (columns 40-59)
     * known up to row 50, unknown above; an inner wall hides it. */
    free_box(0u, N, 0u, 20u);
    free_box(40u, N, 20u, 50u);
    for (uint32_t a = 0u; a < 40u; a++) {
        set_cell(a, 20u, ew_om_occupied());
    }
    wall_column(39u, 20u, N);
    int32_t x;
    int32_t y;
    assert_int_equal(ask(5u, 10u, 1u, &x, &y, NULL), EXPLORE_WAY_TO);
    odom_pose_t p = at_cell(5u, 10u);
    grid_cell_t c;
    assert_int_equal(grid_cell_of(&grid, x, y, &c), SLAM_OK);
    printf("the way's point: cell (%u, %u)\n", c.a, c.b);
    assert_true(clear_line(p.x_um, p.y_um, x, y));
    assert_true(c.a >= 30u); /* along the arm, toward the corner */
}

/* A frontier answered twice in a row was not resolved by going there: put off (no way
 * now, but not done), then, struck again once its time is up, given up (none). The
 * opening is one way cell (rows 25-29), so that it is the only frontier. */
static void test_frontier_put_off_then_given_up(void **state)
{
    (void)state;
    two_rooms(25u, 30u);
    assert_int_equal(result_at(10u, 30u, 1u), EXPLORE_WAY_TO);
    assert_int_equal(result_at(10u, 30u, 2u), EXPLORE_WAY_PUT_OFF);
    assert_int_equal(result_at(10u, 30u, 3u), EXPLORE_WAY_PUT_OFF); /* still off */
    uint32_t later = 3u + 12000u;
    assert_int_equal(result_at(10u, 30u, later), EXPLORE_WAY_TO);
    assert_int_equal(result_at(10u, 30u, later + 1u), EXPLORE_WAY_NONE);
}

/* The robot standing at a frontier that stays unknown has looked at it: given up. */
static void test_frontier_beside_the_robot_given_up(void **state)
{
    (void)state;
    two_rooms(20u, 36u);
    assert_int_equal(result_at(31u, 27u, 1u), EXPLORE_WAY_NONE);
    assert_int_equal(result_at(10u, 30u, 2u), EXPLORE_WAY_NONE); /* for good */
}

/* The work is sliced: a large grid takes several calls, and a new request drops the one
 * under way. */
static void test_work_is_sliced(void **state)
{
    (void)state;
    setup_mode(EXPLORE_WALLS);
    grid_init(&grid, &cfg);
    for (uint32_t i = 0u; i < grid_cells(&grid); i++) {
        grid.om[i] = ew_om_free();
    }
    for (uint32_t b = 0u; b < grid.b_cells; b++) {
        for (uint32_t a = grid.a_cells - 5u; a < grid.a_cells; a++) {
            grid.om[b * grid.a_cells + a] = GRID_EVIDENCE_ZERO; /* an unknown edge */
        }
    }
    int32_t x;
    int32_t y;
    unsigned calls = 0u;
    odom_pose_t p = pose();
    explore_way_ask(&ex.way, &p, 1u);
    explore_way_work(&ex.way, &grid);
    explore_way_ask(&ex.way, &p, 2u); /* asked afresh: the first is dropped */
    explore_way_result_t res;
    assert_false(explore_way_answer(&ex.way, &res, &x, &y));
    unsigned n = 0u;
    while (!explore_way_answer(&ex.way, &res, &x, &y)) {
        explore_way_work(&ex.way, &grid);
        n++;
    }
    calls = n;
    printf("%u x %u cells: answered after %u calls\n", grid.a_cells, grid.b_cells, calls);
    assert_int_equal(res, EXPLORE_WAY_TO);
    assert_true(calls > 3u);
}

/* Every cell size the configuration accepts keeps the way cells within the capacity and
 * at least the body's width. */
static void test_way_cells_at_every_cell_size(void **state)
{
    (void)state;
    static const uint32_t sizes[] = {20000u, 33000u, 50000u, 75000u, 100000u};
    for (unsigned i = 0u; i < sizeof sizes / sizeof sizes[0]; i++) {
        setup_mode(EXPLORE_WALLS);
        cfg.cell_um = sizes[i];
        explore_init(&ex, &cfg);
        const explore_way_t *w = &ex.way;
        printf("cells of %u um: way cells of %u (%u mm), %u x %u\n", sizes[i], w->k,
               w->k * sizes[i] / 1000u, w->na, w->nb);
        assert_true(w->na <= EXPLORE_WAY_A && w->nb <= EXPLORE_WAY_B);
        assert_true((uint32_t)w->k * sizes[i] >= 200000u);
        assert_true((uint32_t)w->na * w->k >= grid_cells_a(&cfg)); /* the whole grid */
        assert_true((uint32_t)w->nb * w->k >= grid_cells_b(&cfg));
    }
}

/* A closed room, every wall known: the robot finds no frontier twice, a minute apart, says
 * it has explored everything it can reach, and stands. */
static void test_done_in_a_closed_room(void **state)
{
    (void)state;
    setup_grid();
    add_wall(-0.45, -1.45, 1.45, -1.45);
    add_wall(1.45, -1.45, 1.45, 1.45);
    add_wall(1.45, 1.45, -0.45, 1.45);
    add_wall(-0.45, 1.45, -0.45, -1.45);
    grid_cell_t lo;
    grid_cell_t hi;
    assert_int_equal(grid_cell_of(&grid, -450000, -1450000, &lo), SLAM_OK);
    assert_int_equal(grid_cell_of(&grid, 1450000, 1450000, &hi), SLAM_OK);
    free_box(lo.a, hi.a + 1u, lo.b, hi.b + 1u);
    for (uint32_t a = lo.a; a <= hi.a; a++) {
        set_cell(a, lo.b, ew_om_occupied());
        set_cell(a, hi.b, ew_om_occupied());
    }
    wall_column(lo.a, lo.b, hi.b + 1u);
    wall_column(hi.a, lo.b, hi.b + 1u);
    unsigned t = 0u;
    double closest = HUGE_VAL;
    while (t < 120000u && !explore_explored(&ex)) {
        world_tick();
        explore_way_work(&ex.way, &grid);
        closest = fmin(closest, clearance());
        t++;
    }
    printf("explored after %u ticks, %u ways, closest %.0f mm\n", t, ex.count.ways,
           closest / 1000.0);
    assert_true(closest > 90000.0); /* the body never touched a wall */
    assert_true(explore_explored(&ex));
    assert_true(explore_standing(&ex));
    assert_true(t >= 6000u); /* not before a minute of no way */
    for (unsigned i = 0u; i < 100u; i++) {
        world_tick();
        assert_int_equal(target[0], 0);
        assert_int_equal(target[1], 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_way_through_an_opening),
        cmocka_unit_test(test_way_round_a_corner),
        cmocka_unit_test(test_frontier_put_off_then_given_up),
        cmocka_unit_test(test_frontier_beside_the_robot_given_up),
        cmocka_unit_test(test_work_is_sliced),
        cmocka_unit_test(test_way_cells_at_every_cell_size),
        cmocka_unit_test(test_done_in_a_closed_room),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
