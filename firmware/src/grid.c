/* SPDX-License-Identifier: MIT */
/* The OM and TM grids: world-to-cell mapping (Eq. 1-2) and saturating updates (Eq. 6-7). */
#include "slam/grid.h"

#include <string.h>

#include "slam/error.h"

void grid_init(grid_t *g, const slam_config_t *cfg)
{
    int64_t half = (int64_t)cfg->cell_um / 2;
    /* The start pose sits at the centre of the start cell. */
    g->origin_x_um = (int32_t)(cfg->start_x_um - (int64_t)cfg->start_cell_a * cfg->cell_um - half);
    g->origin_y_um = (int32_t)(cfg->start_y_um - (int64_t)cfg->start_cell_b * cfg->cell_um - half);
    g->cell_um = cfg->cell_um;
    g->om_max = cfg->om_max;
    g->tm_max = cfg->tm_max;
    g->rejected = 0u;
    memset(g->om, 0, sizeof g->om);
    memset(g->tm, 0, sizeof g->tm);
}

/* One axis of Eq. 1-2: int((v - origin) / L), or -1 outside [0, n). The test on the
 * difference comes before the division, which truncates toward zero and would fold
 * points just below the origin into cell 0. */
static int32_t axis_cell(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t n)
{
    int64_t d = (int64_t)v_um - origin_um;
    if (d < 0 || d >= (int64_t)cell_um * n) {
        return -1;
    }
    return (int32_t)((uint32_t)d / cell_um);
}

int grid_cell_of(const grid_t *g, int32_t x_um, int32_t y_um, grid_cell_t *cell)
{
    int32_t a = axis_cell(x_um, g->origin_x_um, g->cell_um, SLAM_GRID_A);
    int32_t b = axis_cell(y_um, g->origin_y_um, g->cell_um, SLAM_GRID_B);
    if (a < 0 || b < 0) {
        return SLAM_EOUTSIDE;
    }
    cell->a = (uint16_t)a;
    cell->b = (uint16_t)b;
    return SLAM_OK;
}

/* Eq. 6 and 7 share one rule: +1 while below the maximum, else stay at the maximum. */
static int grid_count(grid_t *g, uint8_t *map, uint8_t max, int32_t x_um, int32_t y_um)
{
    grid_cell_t c;
    if (grid_cell_of(g, x_um, y_um, &c) != SLAM_OK) {
        if (g->rejected != UINT32_MAX) {
            g->rejected++;
        }
        return SLAM_EOUTSIDE;
    }
    uint8_t *cell = &map[grid_index(c)];
    *cell = (uint8_t)(*cell < max ? *cell + 1u : max);
    return SLAM_OK;
}

int grid_om_hit(grid_t *g, int32_t x_um, int32_t y_um)
{
    return grid_count(g, g->om, g->om_max, x_um, y_um);
}

int grid_tm_visit(grid_t *g, int32_t x_um, int32_t y_um)
{
    return grid_count(g, g->tm, g->tm_max, x_um, y_um);
}
