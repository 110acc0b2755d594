/* SPDX-License-Identifier: MIT */
/* Tests of the grids: Eq. 1-2 at the edges, saturation (Eq. 6-7), no write outside. */
#include <setjmp.h>
#include <stdarg.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "slam/error.h"
#include "slam/grid.h"
#include "test_rng.h"

#define L 50000 /* the default cell, µm */

/* A grid between two guard areas: a write outside the arrays shows up in a guard. */
typedef struct {
    uint8_t before[64];
    grid_t g;
    uint8_t after[64];
} guarded_grid_t;

static guarded_grid_t gg;

/* The paper's grid (Eq. 6 counts) unless a test says otherwise. */
static void init_default(void)
{
    slam_config_t c;
    test_config_default(&c);
    slam_config_paper(&c);
    memset(&gg, 0xA5, sizeof gg);
    grid_init(&gg.g, &c);
}

static int setup(void **state)
{
    (void)state;
    init_default();
    return 0;
}

static void expect_cell(int32_t x, int32_t y, int a, int b)
{
    grid_cell_t c = {0xFFFFu, 0xFFFFu};
    assert_int_equal(grid_cell_of(&gg.g, x, y, &c), SLAM_OK);
    assert_int_equal(c.a, a);
    assert_int_equal(c.b, b);
}

static void expect_outside(int32_t x, int32_t y)
{
    grid_cell_t c = {1234u, 4321u};
    assert_int_equal(grid_cell_of(&gg.g, x, y, &c), SLAM_EOUTSIDE);
    assert_int_equal(c.a, 1234u); /* untouched */
    assert_int_equal(c.b, 4321u);
}

static void test_origin_puts_start_at_centre_cell(void **state)
{
    (void)state;
    /* Start (0, 0) at the centre of cell (A/2, B/2). */
    assert_int_equal(gg.g.origin_x_um, -(int32_t)(SLAM_GRID_A / 2u) * L - L / 2);
    assert_int_equal(gg.g.origin_y_um, -(int32_t)(SLAM_GRID_B / 2u) * L - L / 2);
    expect_cell(0, 0, SLAM_GRID_A / 2, SLAM_GRID_B / 2);
    /* A start pose elsewhere, at another cell. */
    slam_config_t c;
    test_config_default(&c);
    c.start_x_um = 1000000;
    c.start_y_um = -2000000;
    c.start_cell_a = 3;
    c.start_cell_b = 7;
    grid_init(&gg.g, &c);
    expect_cell(1000000, -2000000, 3, 7);
    expect_cell(1000000 - 3 * L, -2000000 - 7 * L, 0, 0);
}

/* The default start pose (SLAM_START_UM, half a cell from the world's origin) puts the grid's
 * lines, and so an exported map's origin, on whole multiples of L; the start stays at the
 * centre of its cell. */
static void test_default_origin_is_whole_cells(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    grid_init(&gg.g, &c);
    assert_int_equal(gg.g.origin_x_um % L, 0);
    assert_int_equal(gg.g.origin_y_um % L, 0);
    assert_int_equal(gg.g.origin_x_um, -(int32_t)c.start_cell_a * L);
    expect_cell(c.start_x_um, c.start_y_um, c.start_cell_a, c.start_cell_b);
    expect_cell(c.start_x_um - L / 2, c.start_y_um - L / 2, c.start_cell_a, c.start_cell_b);
    expect_cell(c.start_x_um + L / 2 - 1, c.start_y_um + L / 2 - 1, c.start_cell_a, c.start_cell_b);
}

static void test_eq1_eq2_at_cell_edges(void **state)
{
    (void)state;
    int32_t ox = gg.g.origin_x_um;
    int32_t oy = gg.g.origin_y_um;
    /* The lower-left corner of a cell belongs to it; one µm less is the cell before. */
    expect_cell(ox, oy, 0, 0);
    expect_cell(ox + L - 1, oy + L - 1, 0, 0);
    expect_cell(ox + L, oy, 1, 0);
    expect_cell(ox, oy + L, 0, 1);
    expect_cell(ox + 17 * L, oy + 5 * L, 17, 5);
    expect_cell(ox + 17 * L - 1, oy + 5 * L - 1, 16, 4);
    /* Negative world coordinates: around the start cell's lower edge at -L/2. */
    int32_t ca = SLAM_GRID_A / 2;
    int32_t cb = SLAM_GRID_B / 2;
    expect_cell(-1, -1, ca, cb);
    expect_cell(-L / 2, -L / 2, ca, cb);
    expect_cell(-L / 2 - 1, -L / 2 - 1, ca - 1, cb - 1);
    expect_cell(-L / 2 - L, 0, ca - 1, cb);
    expect_cell(-L / 2 - L - 1, 0, ca - 2, cb);
    /* The last row and column, and just beyond. */
    int32_t xe = ox + (int32_t)SLAM_GRID_A * L;
    int32_t ye = oy + (int32_t)SLAM_GRID_B * L;
    expect_cell(xe - 1, ye - 1, SLAM_GRID_A - 1, SLAM_GRID_B - 1);
    expect_outside(xe, 0);
    expect_outside(0, ye);
    /* Just below the origin: a truncating division would fold these into cell 0. */
    expect_outside(ox - 1, oy);
    expect_outside(ox, oy - 1);
    expect_outside(ox - L + 1, oy);
    /* Far away. */
    expect_outside(INT32_MIN, 0);
    expect_outside(INT32_MAX, INT32_MAX);
    expect_outside(0, INT32_MIN);
}

typedef struct {
    int which; /* 0: OM, 1: TM */
    uint8_t max;
    unsigned hits;
    uint8_t expect;
} sat_case_t;

static void test_saturation_table(void **state)
{
    (void)state;
    static const sat_case_t cases[] = {
        {0, 9, 0, 0},      {0, 9, 1, 1},       {0, 9, 8, 8},       {0, 9, 9, 9},    {0, 9, 10, 9},
        {0, 9, 1000, 9},   {1, 30, 1, 1},      {1, 30, 29, 29},    {1, 30, 30, 30}, {1, 30, 31, 30},
        {1, 30, 5000, 30}, {0, 255, 256, 255}, {1, 255, 300, 255}, {0, 1, 3, 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const sat_case_t *k = &cases[i];
        slam_config_t c;
        test_config_default(&c);
        slam_config_paper(&c);
        c.om_max = k->which == 0 ? k->max : 9u;
        c.tm_max = k->which == 1 ? k->max : 30u;
        grid_init(&gg.g, &c);
        for (unsigned h = 0; h < k->hits; h++) {
            int rc = k->which == 0 ? grid_om_hit(&gg.g, 123456, -98765)
                                   : grid_tm_visit(&gg.g, 123456, -98765);
            assert_int_equal(rc, SLAM_OK);
        }
        grid_cell_t cell;
        assert_int_equal(grid_cell_of(&gg.g, 123456, -98765, &cell), SLAM_OK);
        const uint8_t *map = k->which == 0 ? gg.g.om : gg.g.tm;
        const uint8_t *other = k->which == 0 ? gg.g.tm : gg.g.om;
        assert_int_equal(map[grid_index(&gg.g, cell)], k->expect);
        assert_int_equal(other[grid_index(&gg.g, cell)], 0); /* the other map is untouched */
    }
}

static void test_outside_is_rejected_and_counted(void **state)
{
    (void)state;
    assert_int_equal(gg.g.rejected, 0u);
    assert_int_equal(grid_om_hit(&gg.g, INT32_MAX, 0), SLAM_EOUTSIDE);
    assert_int_equal(grid_tm_visit(&gg.g, 0, INT32_MIN), SLAM_EOUTSIDE);
    assert_int_equal(gg.g.rejected, 2u);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(gg.g.om[i], 0);
        assert_int_equal(gg.g.tm[i], 0);
    }
}

static void assert_guards_intact(void)
{
    for (size_t i = 0; i < sizeof gg.before; i++) {
        assert_int_equal(gg.before[i], 0xA5);
        assert_int_equal(gg.after[i], 0xA5);
    }
}

/* Eq. 1-2 worked independently: floor division in double. */
static int ref_cell(const grid_t *g, int32_t x, int32_t y, uint32_t *index)
{
    double a = floor(((double)x - g->origin_x_um) / L);
    double b = floor(((double)y - g->origin_y_um) / L);
    if (a < 0.0 || b < 0.0 || a >= SLAM_GRID_A || b >= SLAM_GRID_B) {
        return 0;
    }
    *index = (uint32_t)b * SLAM_GRID_A + (uint32_t)a;
    return 1;
}

static uint32_t shadow_om[SLAM_GRID_CELLS];
static uint32_t shadow_tm[SLAM_GRID_CELLS];

static uint8_t saturated(uint32_t count, uint8_t max)
{
    return count > max ? max : (uint8_t)count;
}

/* A grid smaller than the capacity, 100 x 50 cells: its own size bounds it and indexes its
 * rows, and nothing beyond its A·B cells is written. */
static void test_run_time_size(void **state)
{
    (void)state;
    slam_config_t c;
    test_config_default(&c);
    c.grid_a = 100u;
    c.grid_b = 50u;
    c.start_cell_a = 10u;
    c.start_cell_b = 20u;
    assert_int_equal(slam_config_check(&c, NULL), SLAM_OK);
    memset(&gg, 0xA5, sizeof gg);
    grid_init(&gg.g, &c);
    assert_int_equal(gg.g.a_cells, 100u);
    assert_int_equal(gg.g.b_cells, 50u);
    assert_int_equal(grid_cells(&gg.g), 5000u);
    const int32_t l = (int32_t)c.cell_um;
    /* The start at the centre of cell (10, 20); the last cell is (99, 49). */
    expect_cell(89 * l, 29 * l, 99, 49);
    expect_outside(90 * l, 0);
    expect_outside(0, 30 * l);
    expect_cell(-10 * l, -20 * l, 0, 0);
    grid_cell_t k;
    assert_int_equal(grid_cell_of(&gg.g, 89 * l, 29 * l, &k), SLAM_OK);
    assert_int_equal(grid_index(&gg.g, k), 49u * 100u + 99u);
    assert_int_equal(grid_om_hit(&gg.g, 89 * l, 29 * l), SLAM_OK);
    assert_int_equal(gg.g.om[4999], GRID_EVIDENCE_ZERO + c.om_hit);
    /* A ray across the whole grid and beyond it stays within the A·B cells. */
    assert_int_equal(grid_om_ray(&gg.g, 0, 0, 200 * l, 100 * l), 60u); /* to b = 49 */
    for (uint32_t i = grid_cells(&gg.g); i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(gg.g.om[i], 0xA5); /* never written, not even by grid_init() */
        assert_int_equal(gg.g.tm[i], 0xA5);
    }
    assert_guards_intact();
}

/* A million random points, anywhere, around the borders and inside: every cell holds what
 * an independent Eq. 1-2 says, every other point is counted as rejected, and nothing
 * outside the arrays changes. The sanitizer build checks the same soak for any
 * out-of-bounds access. */
static void test_random_point_soak(void **state)
{
    (void)state;
    test_rng_t rng = {99u};
    int32_t ox = gg.g.origin_x_um;
    int32_t oy = gg.g.origin_y_um;
    int32_t xe = ox + (int32_t)SLAM_GRID_A * L;
    int32_t ye = oy + (int32_t)SLAM_GRID_B * L;
    uint32_t outside = 0;
    memset(shadow_om, 0, sizeof shadow_om);
    memset(shadow_tm, 0, sizeof shadow_tm);
    for (int i = 0; i < 1000000; i++) {
        int32_t x;
        int32_t y;
        switch (i % 4) {
        case 0: /* anywhere */
            x = (int32_t)test_rng_u64(&rng);
            y = (int32_t)test_rng_u64(&rng);
            break;
        case 1: /* within a few µm of a border */
            x = test_rng_range(&rng, ox - 2 * L, xe + 2 * L);
            y = ((i >> 2) & 1) ? oy + test_rng_range(&rng, -3, 3)
                               : ye + test_rng_range(&rng, -3, 3);
            if ((i >> 3) & 1) {
                int32_t t = x - ox + oy;
                x = ((i >> 4) & 1) ? ox + (y - oy) : xe + (y - ye);
                y = t;
            }
            break;
        default: /* inside, mostly */
            x = test_rng_range(&rng, ox - L, xe + L);
            y = test_rng_range(&rng, oy - L, ye + L);
            break;
        }
        uint32_t idx = 0;
        int inside = ref_cell(&gg.g, x, y, &idx);
        if (i & 1) {
            assert_int_equal(grid_om_hit(&gg.g, x, y), inside ? SLAM_OK : SLAM_EOUTSIDE);
            shadow_om[idx] += (uint32_t)inside;
        } else {
            assert_int_equal(grid_tm_visit(&gg.g, x, y), inside ? SLAM_OK : SLAM_EOUTSIDE);
            shadow_tm[idx] += (uint32_t)inside;
        }
        outside += (uint32_t)!inside;
    }
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(gg.g.om[i], saturated(shadow_om[i], gg.g.om_max));
        assert_int_equal(gg.g.tm[i], saturated(shadow_tm[i], gg.g.tm_max));
    }
    assert_true(outside > 100000u); /* plenty were outside */
    assert_int_equal(gg.g.rejected, outside);
    assert_guards_intact();
}

static void test_state_reads_om_then_tm(void **state)
{
    (void)state;
    grid_t *g = &gg.g;
    const int32_t l = (int32_t)L;
    assert_int_equal(grid_tm_visit(g, 0, 0), SLAM_OK);     /* the start cell */
    assert_int_equal(grid_om_hit(g, 3 * l, 0), SLAM_OK);   /* three cells east */
    assert_int_equal(grid_tm_visit(g, 3 * l, 0), SLAM_OK); /* driven through too */
    grid_cell_t start, east, north;
    assert_int_equal(grid_cell_of(g, 0, 0, &start), SLAM_OK);
    assert_int_equal(grid_cell_of(g, 3 * l, 0, &east), SLAM_OK);
    assert_int_equal(grid_cell_of(g, 0, 3 * l, &north), SLAM_OK);
    assert_int_equal(grid_state(g, grid_index(g, start)), GRID_FREE);
    assert_int_equal(grid_state(g, grid_index(g, east)), GRID_OCCUPIED); /* OM wins */
    assert_int_equal(grid_state(g, grid_index(g, north)), GRID_UNKNOWN);
}

/* grid_occupied_above() is grid_state_of()'s occupied, for every byte of OM and TM. */
static void test_occupied_above_is_the_state_rule(void **state)
{
    (void)state;
    for (unsigned mode = 0; mode < OM_MODES; mode++) {
        uint8_t top = grid_occupied_above((uint8_t)mode);
        for (unsigned om = 0; om < 256u; om++) {
            for (unsigned tm = 0; tm < 256u; tm++) {
                bool occupied =
                    grid_state_of((uint8_t)mode, (uint8_t)om, (uint8_t)tm) == GRID_OCCUPIED;
                assert_int_equal(occupied, om > top);
            }
        }
    }
}

static void init_evidence(void)
{
    slam_config_t c;
    test_config_default(&c);
    assert_int_equal(c.om_mode, OM_MODE_EVIDENCE);
    memset(&gg, 0xA5, sizeof gg);
    grid_init(&gg.g, &c);
}

static uint8_t om_at(int32_t x, int32_t y)
{
    grid_cell_t c;
    assert_int_equal(grid_cell_of(&gg.g, x, y, &c), SLAM_OK);
    return gg.g.om[grid_index(&gg.g, c)];
}

/* A log-odds byte: 0 untouched, else 128 + L with L in [-127, 127]; +4 a hit, -1 a pass. */
static void test_evidence_steps_and_saturation(void **state)
{
    (void)state;
    init_evidence();
    const int32_t l = (int32_t)L;
    assert_int_equal(grid_om_hit(&gg.g, 0, 0), SLAM_OK);
    assert_int_equal(om_at(0, 0), 132);
    assert_int_equal(grid_om_free(&gg.g, 0, 0), SLAM_OK);
    assert_int_equal(om_at(0, 0), 131);
    assert_int_equal(grid_om_free(&gg.g, l, 0), SLAM_OK); /* untouched: 128, then -1 */
    assert_int_equal(om_at(l, 0), 127);
    assert_int_equal(
        grid_state(&gg.g, grid_index(&gg.g, (grid_cell_t){SLAM_GRID_A / 2u, SLAM_GRID_B / 2u})),
        GRID_OCCUPIED);
    for (int i = 0; i < 1000; i++) {
        (void)grid_om_hit(&gg.g, 0, 0);
        (void)grid_om_free(&gg.g, l, 0);
    }
    assert_int_equal(om_at(0, 0), 255); /* L = +127 */
    assert_int_equal(om_at(l, 0), 1);   /* L = -127 */
    for (int i = 0; i < 4; i++) {       /* a cell hit once is balanced by four passes */
        (void)grid_om_free(&gg.g, 2 * l, 0);
    }
    (void)grid_om_hit(&gg.g, 2 * l, 0);
    assert_int_equal(om_at(2 * l, 0), GRID_EVIDENCE_ZERO);
    grid_cell_t c;
    assert_int_equal(grid_cell_of(&gg.g, 2 * l, 0, &c), SLAM_OK);
    assert_int_equal(grid_state(&gg.g, grid_index(&gg.g, c)), GRID_UNKNOWN);
    assert_int_equal(grid_cell_of(&gg.g, l, 0, &c), SLAM_OK);
    assert_int_equal(grid_state(&gg.g, grid_index(&gg.g, c)), GRID_FREE);
    assert_int_equal(grid_cell_of(&gg.g, 0, 5 * l, &c), SLAM_OK);
    assert_int_equal(grid_tm_visit(&gg.g, 0, 5 * l), SLAM_OK);
    assert_int_equal(grid_state(&gg.g, grid_index(&gg.g, c)), GRID_UNKNOWN); /* TM is not OM */
    assert_guards_intact();
}

/* Part of a hit goes in and is taken back: the cell is as it was, both saturate, nothing
 * outside the grid is written or counted. */
static void test_part_of_a_hit_and_back(void **state)
{
    (void)state;
    init_evidence();
    const int32_t l = (int32_t)L;
    grid_om_part(&gg.g, 0, 0, 2u, false);
    assert_int_equal(om_at(0, 0), 130);
    grid_om_part(&gg.g, 0, 0, 2u, true);
    assert_int_equal(om_at(0, 0), GRID_EVIDENCE_ZERO);
    for (int i = 0; i < 200; i++) {
        grid_om_part(&gg.g, l, 0, 2u, false);
        grid_om_part(&gg.g, 2 * l, 0, 2u, true);
    }
    assert_int_equal(om_at(l, 0), 255);   /* L = +127 */
    assert_int_equal(om_at(2 * l, 0), 1); /* L = -127 */
    grid_om_part(&gg.g, INT32_MAX, 0, 2u, false);
    grid_om_part(&gg.g, 0, INT32_MIN, 2u, true);
    assert_int_equal(gg.g.rejected, 0u);
    assert_guards_intact();
}

/* The paper's mode ignores free-space evidence entirely. */
static void test_count_mode_has_no_free_space(void **state)
{
    (void)state;
    assert_int_equal(gg.g.mode, OM_MODE_COUNT);
    assert_int_equal(grid_om_free(&gg.g, 0, 0), SLAM_OK);
    assert_int_equal(grid_om_ray(&gg.g, 0, 0, 10 * (int32_t)L, 3 * (int32_t)L), 0u);
    grid_om_part(&gg.g, 0, 0, 2u, false);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(gg.g.om[i], 0);
    }
}

/* Distance from a cell's centre to the segment between two cell centres, in cells. */
static double seg_dist(double pa, double pb, double a0, double b0, double a1, double b1)
{
    double da = a1 - a0;
    double db = b1 - b0;
    double len2 = da * da + db * db;
    double t = len2 > 0.0 ? ((pa - a0) * da + (pb - b0) * db) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return hypot(pa - (a0 + t * da), pb - (b0 + t * db));
}

/* Random rays against the exact segment: the first and last cells are the end points',
 * exactly max(|da|, |db|) + 1 cells are lowered once each, every one of them within half
 * a cell of the exact line between the two cell centres (Bresenham's bound), and rays
 * that run off the grid stop at its edge with nothing written outside. */
static void test_ray_against_exact_segment(void **state)
{
    (void)state;
    test_rng_t rng = {7u};
    int32_t ox = gg.g.origin_x_um;
    int32_t oy = gg.g.origin_y_um;
    int32_t xe = ox + (int32_t)SLAM_GRID_A * L;
    int32_t ye = oy + (int32_t)SLAM_GRID_B * L;
    double worst = 0.0;
    for (int i = 0; i < 20000; i++) {
        init_evidence();
        int32_t x0 = test_rng_range(&rng, ox, xe - 1);
        int32_t y0 = test_rng_range(&rng, oy, ye - 1);
        int32_t x1 = x0 + test_rng_range(&rng, -25 * L, 25 * L);
        int32_t y1 = y0 + test_rng_range(&rng, -25 * L, 25 * L);
        double a0 = floor(((double)x0 - ox) / L);
        double b0 = floor(((double)y0 - oy) / L);
        double a1 = floor(((double)x1 - ox) / L);
        double b1 = floor(((double)y1 - oy) / L);
        double span = fmax(fabs(a1 - a0), fabs(b1 - b0));
        uint32_t n = grid_om_ray(&gg.g, x0, y0, x1, y1);
        bool leaves = a1 < 0 || b1 < 0 || a1 >= SLAM_GRID_A || b1 >= SLAM_GRID_B;
        if (leaves) {
            assert_true(n <= span + 1.0);
        } else {
            assert_int_equal(n, (uint32_t)span + 1u);
            assert_int_equal(gg.g.om[(uint32_t)b1 * SLAM_GRID_A + (uint32_t)a1], 127);
        }
        assert_int_equal(gg.g.om[(uint32_t)b0 * SLAM_GRID_A + (uint32_t)a0], 127);
        uint32_t lowered = 0;
        for (uint32_t k = 0; k < SLAM_GRID_CELLS; k++) {
            if (gg.g.om[k] == GRID_EVIDENCE_ZERO) {
                continue;
            }
            assert_int_equal(gg.g.om[k], 127); /* each cell once */
            lowered++;
            double d = seg_dist(k % SLAM_GRID_A, k / SLAM_GRID_A, a0, b0, a1, b1);
            worst = d > worst ? d : worst;
        }
        assert_int_equal(lowered, n);
        assert_guards_intact();
    }
    assert_true(worst <= 0.5 + 1e-9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_origin_puts_start_at_centre_cell, setup),
        cmocka_unit_test(test_default_origin_is_whole_cells),
        cmocka_unit_test_setup(test_eq1_eq2_at_cell_edges, setup),
        cmocka_unit_test_setup(test_saturation_table, setup),
        cmocka_unit_test_setup(test_outside_is_rejected_and_counted, setup),
        cmocka_unit_test_setup(test_run_time_size, setup),
        cmocka_unit_test_setup(test_random_point_soak, setup),
        cmocka_unit_test_setup(test_state_reads_om_then_tm, setup),
        cmocka_unit_test(test_occupied_above_is_the_state_rule),
        cmocka_unit_test_setup(test_evidence_steps_and_saturation, setup),
        cmocka_unit_test_setup(test_count_mode_has_no_free_space, setup),
        cmocka_unit_test_setup(test_part_of_a_hit_and_back, setup),
        cmocka_unit_test(test_ray_against_exact_segment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
