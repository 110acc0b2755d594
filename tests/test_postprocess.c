/* SPDX-License-Identifier: MIT */
/* Tests of post-processing on small hand-drawn maps: each operation, the chain, borders. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "slam/error.h"
#include "slam/grid.h"
#include "slam/postprocess.h"

/* Maps are drawn one string a row: '.' is 0, '1'..'9' that OM value, '#' is OMmax (9). */
#define MAXW 16
#define MAXH 16

typedef struct {
    size_t w;
    size_t h;
    uint8_t c[MAXW * MAXH];
} map_t;

static map_t draw(const char *const *rows, size_t h)
{
    map_t m = {.w = strlen(rows[0]), .h = h};
    assert_true(m.w <= MAXW && h <= MAXH);
    for (size_t y = 0; y < h; y++) {
        assert_int_equal(strlen(rows[y]), m.w);
        for (size_t x = 0; x < m.w; x++) {
            char ch = rows[y][x];
            m.c[y * m.w + x] = ch == '.' ? 0u : ch == '#' ? 9u : (uint8_t)(ch - '0');
        }
    }
    return m;
}

static void print_map(const char *title, const map_t *m)
{
    printf("%s\n", title);
    for (size_t y = 0; y < m->h; y++) {
        printf("  ");
        for (size_t x = 0; x < m->w; x++) {
            uint8_t v = m->c[y * m->w + x];
            putchar(v == 0u ? '.' : v == 9u ? '#' : (char)('0' + v));
        }
        putchar('\n');
    }
}

static void assert_map(const map_t *got, const char *const *rows, size_t h)
{
    map_t want = draw(rows, h);
    assert_int_equal(got->w, want.w);
    assert_int_equal(got->h, want.h);
    if (memcmp(got->c, want.c, want.w * want.h) != 0) {
        print_map("got:", got);
        print_map("want:", &want);
        fail_msg("maps differ");
    }
}

#define ROWS(...)                                                                                  \
    ((const char *const[]){__VA_ARGS__}),                                                          \
        (sizeof((const char *const[]){__VA_ARGS__}) / sizeof(const char *))

static uint8_t scratch[2 * MAXW];

static void test_threshold(void **state)
{
    (void)state;
    map_t m = draw(ROWS("0123456789", "3344..9911"));
    post_threshold(m.c, m.w, m.h, 3u, 9u);
    assert_map(&m, ROWS("....######", "..##..##.."));
    /* TH 0: every hit counts. */
    m = draw(ROWS("0123456789"));
    post_threshold(m.c, m.w, m.h, 0u, 9u);
    assert_map(&m, ROWS(".#########"));
}

static void test_template_removes_isolated_cells(void **state)
{
    (void)state;
    map_t m = draw(ROWS("#.......", "........", "...#....", "........", "......##", "#######."));
    /* K = 1: cells without any occupied neighbour go; pairs and lines stay. */
    post_template(m.c, m.w, m.h, 1u, scratch);
    assert_map(&m, ROWS("........", "........", "........", "........", "......##", "#######."));
    /* K = 2: the ends of the line (one neighbour) go too; each cell is judged on the map
     * before the step, so the line shrinks by one cell at each end, not more. */
    post_template(m.c, m.w, m.h, 2u, scratch);
    assert_map(&m, ROWS("........", "........", "........", "........", "......##", ".######."));
    /* K = 0 removes nothing. */
    map_t before = m;
    post_template(m.c, m.w, m.h, 0u, scratch);
    assert_memory_equal(m.c, before.c, m.w * m.h);
}

static void test_template_counts_eight_neighbours(void **state)
{
    (void)state;
    /* The centre cell has exactly 8, 4 (diagonals) and 4 (edges) occupied neighbours. */
    map_t m = draw(ROWS("###", "###", "###"));
    post_template(m.c, m.w, m.h, 8u, scratch);
    assert_map(&m, ROWS("...", ".#.", "..."));
    m = draw(ROWS("#.#", ".#.", "#.#"));
    post_template(m.c, m.w, m.h, 4u, scratch);
    assert_map(&m, ROWS("...", ".#.", "..."));
    m = draw(ROWS(".#.", "###", ".#."));
    post_template(m.c, m.w, m.h, 5u, scratch);
    assert_map(&m, ROWS("...", "...", "..."));
}

static void test_insert_fills_gaps_in_four_orientations(void **state)
{
    (void)state;
    /* W-E at the top left, S-N at the top right, and the two diagonals below. */
    map_t m =
        draw(ROWS("#.#.........#...", "................", "............#...", "................",
                  "#.......#.......", "................", "..#...#........."));
    post_insert(m.c, m.w, m.h, 9u, scratch);
    assert_map(&m,
               ROWS("###.........#...", "............#...", "............#...", "................",
                    "#.......#.......", ".#.....#........", "..#...#........."));
}

static void test_insert_decides_on_the_map_before_the_step(void **state)
{
    (void)state;
    /* "#..#" has no cell between two occupied ones; "#.#.#" fills both gaps at once. */
    map_t m = draw(ROWS("#..#....", "#.#.#..."));
    post_insert(m.c, m.w, m.h, 9u, scratch);
    assert_map(&m, ROWS("#..#....", "#####..."));
}

static void test_borders(void **state)
{
    (void)state;
    /* Beyond the border is free: corner and edge cells keep fewer neighbours, and an edge
     * cell is never between a neighbour and the outside. */
    map_t m = draw(ROWS("##..", "#...", "...#", "..##"));
    map_t t = m;
    post_template(t.c, t.w, t.h, 2u, scratch);
    assert_map(&t, ROWS("##..", "#...", "...#", "..##"));
    post_template(t.c, t.w, t.h, 3u, scratch);
    assert_map(&t, ROWS("....", "....", "....", "...."));
    /* Insert along the edges: the top row's gap is filled, the corners are not invented. */
    m = draw(ROWS("#.#.", "....", "....", ".#.#"));
    post_insert(m.c, m.w, m.h, 9u, scratch);
    assert_map(&m, ROWS("###.", "....", "....", ".###"));
    /* One-row and one-column maps. */
    m = draw(ROWS("#.#.#"));
    post_insert(m.c, m.w, m.h, 9u, scratch);
    assert_map(&m, ROWS("#####"));
    m = draw(ROWS("#", ".", "#", "."));
    post_insert(m.c, m.w, m.h, 9u, scratch);
    assert_map(&m, ROWS("#", "#", "#", "."));
    post_template(m.c, m.w, m.h, 1u, scratch);
    assert_map(&m, ROWS("#", "#", "#", "."));
}

/* The full chain on a raw map: a wall seen 2-9 times with a gap and a stray hit. */
static void test_full_chain_on_a_copy(void **state)
{
    (void)state;
    map_t om = draw(ROWS("..........", ".5697.8964", ".1........", "......2...", "...4......",
                         "..........", ".......9..", "......89.."));
    map_t keep = om;
    map_t out = {.w = om.w, .h = om.h};
    post_params_t p = {.threshold = 3u, .om_max = 9u, .k = 1u, .insert = 1u};
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_OK);
    assert_memory_equal(om.c, keep.c, om.w * om.h); /* the live map is untouched */
    /* threshold drops 1, 2 and 3; template drops the lone 4; insert closes the wall's gap
     * and leaves the small block as it is (no cell of it lies between two others). */
    assert_map(&out, ROWS("..........", ".#########", "..........", "..........", "..........",
                          "..........", ".......#..", "......##.."));
}

static void test_bad_parameters_change_nothing(void **state)
{
    (void)state;
    map_t om = draw(ROWS("#..", "...", "..#"));
    map_t out = draw(ROWS("123", "456", "789"));
    map_t keep = out;
    post_params_t p = {.threshold = 3u, .om_max = 9u, .k = 9u, .insert = 1u};
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_EINVAL);
    p.k = 1u;
    p.insert = 2u;
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_EINVAL);
    p.insert = 1u;
    p.om_max = 0u;
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_EINVAL);
    p.om_max = 9u;
    assert_int_equal(post_run(om.c, out.c, 0u, om.h, &p, scratch), SLAM_EINVAL);
    assert_memory_equal(out.c, keep.c, out.w * out.h);
}

/* The evidence map's threshold is a log-odds: the byte 128 + TH, below which unknown (0)
 * and free cells fall; template and insert are skipped when off. */
static void test_evidence_threshold_and_steps_off(void **state)
{
    (void)state;
    map_t om = {.w = 4u, .h = 1u};
    const uint8_t row[4] = {0u, 100u, 131u, 140u}; /* unknown, free, L = 3, L = 12 */
    memcpy(om.c, row, sizeof row);
    map_t out = {.w = 4u, .h = 1u};
    post_params_t p = {.threshold = grid_threshold_byte(OM_MODE_EVIDENCE, 4u),
                       .om_max = 9u,
                       .k = 0u,
                       .insert = 0u};
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_OK);
    const uint8_t want[4] = {0u, 0u, 0u, 9u};
    assert_memory_equal(out.c, want, sizeof want);
    p.threshold = grid_threshold_byte(OM_MODE_EVIDENCE, 0u);
    assert_int_equal(post_run(om.c, out.c, om.w, om.h, &p, scratch), SLAM_OK);
    const uint8_t want0[4] = {0u, 0u, 9u, 9u};
    assert_memory_equal(out.c, want0, sizeof want0); /* no template: lone cells stay */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threshold),
        cmocka_unit_test(test_evidence_threshold_and_steps_off),
        cmocka_unit_test(test_template_removes_isolated_cells),
        cmocka_unit_test(test_template_counts_eight_neighbours),
        cmocka_unit_test(test_insert_fills_gaps_in_four_orientations),
        cmocka_unit_test(test_insert_decides_on_the_map_before_the_step),
        cmocka_unit_test(test_borders),
        cmocka_unit_test(test_full_chain_on_a_copy),
        cmocka_unit_test(test_bad_parameters_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
