/* SPDX-License-Identifier: MIT */
/* The corridor ahead on the map at every cell size the configuration accepts: its rows
 * reach SLAM_CORRIDOR_REACH_UM, its columns ±clearance_um, nothing cut and nothing
 * wrapped, and the configuration refuses a corridor that would not fit. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "sight.h"
#include "slam/config_fields.h"
#include "slam/error.h"

static slam_config_t cfg;
static explore_t ex;
static grid_t grid;

/* The widest clearance the cell size takes: its corridor just fits. */
static uint32_t widest_clearance(uint32_t cell_um)
{
    uint32_t columns = SLAM_CORRIDOR_CELLS_MAX / slam_corridor_rows(cell_um);
    return (columns * cell_um - 1u) / 2u;
}

/* A configuration of this cell size and clearance (follow_um kept above it). */
static void set_up(uint32_t cell_um, uint32_t clearance_um)
{
    slam_config_default(&cfg);
    cfg.cell_um = cell_um;
    cfg.clearance_um = clearance_um;
    if (cfg.follow_um <= clearance_um) {
        cfg.follow_um = clearance_um + 1u;
    }
    const char *bad = NULL;
    if (slam_config_check(&cfg, &bad) != SLAM_OK) {
        fail_msg("cell %u µm, clearance %u µm: refused (%s)", (unsigned)cell_um,
                 (unsigned)clearance_um, bad);
    }
    explore_init(&ex, &cfg);
    grid_init(&grid, &cfg);
}

/*
 * One pass over the corridor of a robot at the start cell's centre, heading along +x,
 * with one cell k cells ahead and j cells to the left occupied with the evidence of
 * several hits (which stops the robot alone); returns the distance the pass found.
 */
static int32_t pass_with_cell_at(int32_t k, int32_t j)
{
    grid_cell_t c = {(uint16_t)(cfg.start_cell_a + k), (uint16_t)(cfg.start_cell_b + j)};
    grid.om[grid_index(&grid, c)] = UINT8_MAX;
    explore_frame_t f = {cfg.start_x_um, cfg.start_y_um, FIX_Q30_ONE, 0};
    explore_corridor_begin(&ex, &grid, &f);
    unsigned slices = 0;
    while (!explore_corridor_cells(&ex, &grid)) {
        slices++;
    }
    grid.om[grid_index(&grid, c)] = GRID_EVIDENCE_ZERO;
    /* Read 8 cells a slice: the largest corridor in 30 slices. */
    assert_true(slices < SLAM_CORRIDOR_CELLS_MAX / 8u);
    return ex.corridor.work_um;
}

/* Every cell the corridor must see is seen at its distance; none beyond it is. */
static void check_corridor(uint32_t cell_um, uint32_t clearance_um)
{
    set_up(cell_um, clearance_um);
    uint32_t rows = slam_corridor_rows(cell_um);
    uint32_t columns = slam_corridor_columns(cell_um, clearance_um);
    assert_int_equal(ex.corridor.along, rows);
    assert_int_equal(ex.corridor.across, columns);
    assert_true(rows * columns <= SLAM_CORRIDOR_CELLS_MAX);
    /* The rows reach the last cell whose centre is within the reach. */
    assert_true(rows == 1u || rows * cell_um <= SLAM_CORRIDOR_REACH_UM);
    assert_true((rows + 1u) * cell_um > SLAM_CORRIDOR_REACH_UM);
    int32_t cell = (int32_t)cell_um;
    int32_t clear = (int32_t)clearance_um;
    int32_t side = clear / cell + 2;
    for (int32_t k = 1; k <= (int32_t)rows + 1; k++) {
        for (int32_t j = -side; j <= side; j++) {
            int32_t found = pass_with_cell_at(k, j);
            int32_t lateral = (j < 0 ? -j : j) * cell;
            bool inside = k <= (int32_t)rows && lateral + cell / 2 <= clear;
            bool outside = k > (int32_t)rows || lateral - cell / 2 >= clear + cell;
            if (inside && found != k * cell) {
                fail_msg("cell %d µm, clearance %d µm: the cell %d ahead, %d left, "
                         "found at %d µm",
                         cell, clear, k, j, found);
            }
            if (outside && found != INT32_MAX) {
                fail_msg("cell %d µm, clearance %d µm: the cell %d ahead, %d left, outside "
                         "the corridor, found at %d µm",
                         cell, clear, k, j, found);
            }
        }
    }
}

/* Every whole millimetre from 20 to 100 mm, and larger cells up to the 1 m the
 * configuration takes, with the narrowest, the default and the widest clearance each
 * takes. */
static void test_every_cell_size(void **state)
{
    (void)state;
    static const uint32_t large_mm[] = {110, 125, 150, 200, 250, 300, 301, 500, 1000};
    for (uint32_t n = 0; n < 81u + sizeof large_mm / sizeof large_mm[0]; n++) {
        uint32_t cell_um = 1000u * (n < 81u ? 20u + n : large_mm[n - 81u]);
        uint32_t widest = widest_clearance(cell_um);
        check_corridor(cell_um, 10000u);
        check_corridor(cell_um, 130000u < widest ? 130000u : widest);
        check_corridor(cell_um, widest < 1999999u ? widest : 1999999u); /* below follow_um's top */
    }
}

/* A clearance one µm wider than the widest is refused by its name, at every cell size
 * where the range of clearance_um allows it. */
static void test_too_wide_is_refused(void **state)
{
    (void)state;
    for (uint32_t cell_mm = 20u; cell_mm <= 1000u; cell_mm++) {
        uint32_t cell_um = 1000u * cell_mm;
        uint32_t wider = widest_clearance(cell_um) + 1u;
        if (wider > 2000000u) {
            continue;
        }
        slam_config_default(&cfg);
        cfg.cell_um = cell_um;
        cfg.clearance_um = wider;
        cfg.follow_um = wider + 1u;
        const char *bad = NULL;
        assert_int_equal(slam_config_check(&cfg, &bad), SLAM_EINVAL);
        assert_string_equal(bad, "clearance_um");
    }
    /* Below 20 mm no cell size is taken at all. */
    slam_config_default(&cfg);
    cfg.cell_um = 19999u;
    cfg.clearance_um = 10000u;
    assert_int_equal(slam_config_check(&cfg, NULL), SLAM_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_cell_size),
        cmocka_unit_test(test_too_wide_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
