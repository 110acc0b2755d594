/* SPDX-License-Identifier: MIT */
/* The OM and TM grids: world-to-cell mapping (Eq. 1-2), saturating updates (Eq. 6-7) and
 * the free-space evidence of OM_MODE_EVIDENCE. */
#include "slam/grid.h"

#include <stdbool.h>
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
    g->mode = cfg->om_mode;
    g->hit = cfg->om_hit;
    g->miss = cfg->om_miss;
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

/* The cell of a point, or a rejection counted. */
static uint8_t *cell_at(grid_t *g, uint8_t *map, int32_t x_um, int32_t y_um)
{
    grid_cell_t c;
    if (grid_cell_of(g, x_um, y_um, &c) != SLAM_OK) {
        if (g->rejected != UINT32_MAX) {
            g->rejected++;
        }
        return NULL;
    }
    return &map[grid_index(c)];
}

/* Eq. 6 and 7 share one rule: +1 while below the maximum, else stay at the maximum. */
static int grid_count(grid_t *g, uint8_t *map, uint8_t max, int32_t x_um, int32_t y_um)
{
    uint8_t *cell = cell_at(g, map, x_um, y_um);
    if (cell == NULL) {
        return SLAM_EOUTSIDE;
    }
    *cell = (uint8_t)(*cell < max ? *cell + 1u : max);
    return SLAM_OK;
}

/* Evidence: an untouched cell (0) starts at log-odds 0; the byte stays in 1..255. */
static inline uint8_t evidence_lower(uint8_t v, uint8_t miss)
{
    uint32_t b = v != 0u ? v : GRID_EVIDENCE_ZERO;
    return (uint8_t)(b > 1u + miss ? b - miss : 1u);
}

int grid_om_hit(grid_t *g, int32_t x_um, int32_t y_um)
{
    if (g->mode != OM_MODE_EVIDENCE) {
        return grid_count(g, g->om, g->om_max, x_um, y_um);
    }
    uint8_t *cell = cell_at(g, g->om, x_um, y_um);
    if (cell == NULL) {
        return SLAM_EOUTSIDE;
    }
    uint32_t b = (*cell != 0u ? *cell : GRID_EVIDENCE_ZERO) + (uint32_t)g->hit;
    *cell = (uint8_t)(b < 255u ? b : 255u);
    return SLAM_OK;
}

int grid_om_free(grid_t *g, int32_t x_um, int32_t y_um)
{
    if (g->mode != OM_MODE_EVIDENCE) {
        return SLAM_OK;
    }
    uint8_t *cell = cell_at(g, g->om, x_um, y_um);
    if (cell == NULL) {
        return SLAM_EOUTSIDE;
    }
    *cell = evidence_lower(*cell, g->miss);
    return SLAM_OK;
}

/* Cell coordinate of a point along one axis, unbounded: the ray needs the end cell even
 * when it lies outside the grid. floor((v - origin) / L) for |v - origin| < 2^31 µm. */
static int32_t axis_coord(int32_t v_um, int32_t origin_um, uint32_t cell_um)
{
    int64_t d = (int64_t)v_um - origin_um;
    int64_t q = d / (int64_t)cell_um;
    return (int32_t)(d < 0 && q * (int64_t)cell_um != d ? q - 1 : q);
}

uint32_t grid_om_ray(grid_t *g, int32_t x0_um, int32_t y0_um, int32_t x1_um, int32_t y1_um)
{
    grid_cell_t c0;
    if (g->mode != OM_MODE_EVIDENCE || grid_cell_of(g, x0_um, y0_um, &c0) != SLAM_OK) {
        return 0u;
    }
    int32_t a = c0.a;
    int32_t b = c0.b;
    int32_t da = axis_coord(x1_um, g->origin_x_um, g->cell_um) - a;
    int32_t db = axis_coord(y1_um, g->origin_y_um, g->cell_um) - b;
    int32_t sa = da < 0 ? -1 : 1;
    int32_t sb = db < 0 ? -1 : 1;
    da = da < 0 ? -da : da;
    db = db < 0 ? -db : db;
    /* Bresenham along the longer axis: one cell a step, the shorter axis follows. */
    bool along_a = da >= db;
    int32_t major = along_a ? da : db;
    int32_t minor = along_a ? db : da;
    int32_t err = major / 2;
    uint32_t n = 0u;
    uint8_t miss = g->miss;
    for (int32_t k = 0;; k++) {
        uint8_t *cell = &g->om[(uint32_t)b * SLAM_GRID_A + (uint32_t)a];
        *cell = evidence_lower(*cell, miss);
        n++;
        if (k == major) {
            break;
        }
        err -= minor;
        bool step_minor = err < 0;
        err += step_minor ? major : 0;
        if (along_a) {
            a += sa;
            b += step_minor ? sb : 0;
        } else {
            b += sb;
            a += step_minor ? sa : 0;
        }
        if ((uint32_t)a >= SLAM_GRID_A || (uint32_t)b >= SLAM_GRID_B) {
            break;
        }
    }
    return n;
}

int grid_tm_visit(grid_t *g, int32_t x_um, int32_t y_um)
{
    return grid_count(g, g->tm, g->tm_max, x_um, y_um);
}
