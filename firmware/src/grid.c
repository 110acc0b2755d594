/* SPDX-License-Identifier: MIT */
/* The OM and TM grids: world-to-cell mapping (Eq. 1-2), saturating updates (Eq. 6-7) and
 * the free-space evidence of OM_MODE_EVIDENCE. */
#include "slam/grid.h"

#include <stdbool.h>
#include <string.h>

#include "slam/error.h"

void grid_init(grid_t *g, const slam_config_t *cfg)
{
    g->origin_x_um = grid_origin_um(cfg->start_x_um, cfg->start_cell_a, cfg->cell_um);
    g->origin_y_um = grid_origin_um(cfg->start_y_um, cfg->start_cell_b, cfg->cell_um);
    g->cell_um = cfg->cell_um;
    g->a_cells = grid_cells_a(cfg);
    g->b_cells = grid_cells_b(cfg);
    grid_set_spans(g);
    g->om_max = cfg->om_max;
    g->tm_max = cfg->tm_max;
    g->mode = cfg->om_mode;
    g->hit = cfg->om_hit;
    g->miss = cfg->om_miss;
    g->rejected = 0u;
    /* The A·B cells used: nothing reads past them, and a large capacity (the simulator's
     * 2 MiB) costs nothing where the run's grid is small. */
    memset(g->om, g->mode == OM_MODE_EVIDENCE ? (int)GRID_EVIDENCE_ZERO : 0, grid_cells(g));
    memset(g->tm, 0, grid_cells(g));
}

/* One axis of Eq. 1-2: int((v - origin) / L), or -1 outside [0, n), span = n·L. The
 * difference is taken modulo 2^32: a point below the origin, or beyond the grid, wraps to a
 * value past n·L, since n·L stays below 1 km (slam_config_check()) while v and the origin
 * lie within ±2^31 µm. So one unsigned compare tests both sides, and a 32-bit division (one
 * instruction on the MCU) does the rest. */
static int32_t axis_cell(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t span_um)
{
    uint32_t d = (uint32_t)v_um - (uint32_t)origin_um;
    if (d >= span_um) {
        return -1;
    }
    return (int32_t)(d / cell_um);
}

int grid_cell_of(const grid_t *g, int32_t x_um, int32_t y_um, grid_cell_t *cell)
{
    int32_t a = axis_cell(x_um, g->origin_x_um, g->cell_um, g->span_x_um);
    int32_t b = axis_cell(y_um, g->origin_y_um, g->cell_um, g->span_y_um);
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
    return &map[grid_index(g, c)];
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

#ifndef GRID_EVIDENCE_CAP
#define GRID_EVIDENCE_CAP GRID_EVIDENCE_MAX
#endif
#define GRID_EVIDENCE_LO (GRID_EVIDENCE_ZERO - GRID_EVIDENCE_CAP)
#define GRID_EVIDENCE_HI (GRID_EVIDENCE_ZERO + GRID_EVIDENCE_CAP)

/* Evidence: the byte stays in LO..HI. A miss lowers it, down to floor at most. */
static inline uint8_t evidence_lower(uint8_t v, uint8_t miss, uint32_t floor)
{
    return (uint8_t)(v > floor + miss ? (uint32_t)v - miss : floor);
}

static void evidence_raise(uint8_t *cell, uint8_t step)
{
    uint32_t b = (uint32_t)*cell + step;
    *cell = (uint8_t)(b < GRID_EVIDENCE_HI ? b : GRID_EVIDENCE_HI);
}

int grid_om_add(grid_t *g, int32_t x_um, int32_t y_um, uint8_t step)
{
    if (g->mode != OM_MODE_EVIDENCE) {
        return grid_count(g, g->om, g->om_max, x_um, y_um);
    }
    uint8_t *cell = cell_at(g, g->om, x_um, y_um);
    if (cell == NULL) {
        return SLAM_EOUTSIDE;
    }
    evidence_raise(cell, step);
    return SLAM_OK;
}

int grid_om_hit(grid_t *g, int32_t x_um, int32_t y_um)
{
    return grid_om_add(g, x_um, y_um, g->hit);
}

void grid_om_part(grid_t *g, int32_t x_um, int32_t y_um, uint8_t step, bool take_back)
{
    grid_cell_t c;
    if (g->mode == OM_MODE_EVIDENCE && grid_cell_of(g, x_um, y_um, &c) == SLAM_OK) {
        uint8_t *cell = &g->om[grid_index(g, c)];
        if (take_back) {
            *cell = evidence_lower(*cell, step, GRID_EVIDENCE_LO);
        } else {
            evidence_raise(cell, step);
        }
    }
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
    *cell = evidence_lower(*cell, g->miss, GRID_EVIDENCE_LO);
    return SLAM_OK;
}

void grid_om_behind(grid_t *g, grid_cell_t c)
{
    uint8_t *cell = &g->om[grid_index(g, c)];
    if (g->mode == OM_MODE_EVIDENCE && *cell > GRID_EVIDENCE_ZERO) {
        *cell = evidence_lower(*cell, g->miss, GRID_EVIDENCE_ZERO);
    }
}

/* Cell coordinate of a point along one axis, unbounded: the ray needs the end cell even
 * when it lies outside the grid. floor((v - origin) / L): the difference fits 32 bits (the
 * world is within 1 km), and a 32-bit division is one instruction on the MCU. */
static int32_t axis_coord(int32_t v_um, int32_t origin_um, uint32_t cell_um)
{
    int32_t d = (int32_t)((uint32_t)v_um - (uint32_t)origin_um);
    return d >= 0 ? (int32_t)((uint32_t)d / cell_um)
                  : -(int32_t)(((uint32_t)-d + cell_um - 1u) / cell_um);
}

uint32_t grid_om_ray(grid_t *g, int32_t x0_um, int32_t y0_um, int32_t x1_um, int32_t y1_um)
{
    int32_t a = axis_coord(x0_um, g->origin_x_um, g->cell_um);
    int32_t b = axis_coord(y0_um, g->origin_y_um, g->cell_um);
    const uint32_t na_cells = g->a_cells;
    const uint32_t nb_cells = g->b_cells;
    if (g->mode != OM_MODE_EVIDENCE || (uint32_t)a >= na_cells || (uint32_t)b >= nb_cells) {
        return 0u;
    }
    int32_t a1 = axis_coord(x1_um, g->origin_x_um, g->cell_um);
    int32_t b1 = axis_coord(y1_um, g->origin_y_um, g->cell_um);
    int32_t da = a1 - a;
    int32_t db = b1 - b;
    int32_t sa = da < 0 ? -1 : 1;
    int32_t sb = db < 0 ? -1 : 1;
    da = da < 0 ? -da : da;
    db = db < 0 ? -db : db;
    /* Bresenham along the longer axis: one cell a step, the shorter axis follows. */
    bool along_a = da >= db;
    int32_t major = along_a ? da : db;
    int32_t minor = along_a ? db : da;
    int32_t step_major = along_a ? sa : sb * (int32_t)na_cells;
    int32_t step_minor = along_a ? sb * (int32_t)na_cells : sa;
    uint8_t *cell = &g->om[(uint32_t)b * na_cells + (uint32_t)a];
    uint32_t miss = g->miss;
    int32_t err = major / 2;
    if ((uint32_t)a1 < na_cells && (uint32_t)b1 < nb_cells) {
        /* Both ends inside: so is every cell between (the grid is convex), and the walk
         * is the tight loop of a reading's cost, a few instructions a cell. */
        uint32_t n = (uint32_t)major + 1u;
        for (uint32_t k = n; k != 0u; k--) {
            int32_t v = (int32_t)*cell - (int32_t)miss;
            v = v < (int32_t)GRID_EVIDENCE_LO ? (int32_t)GRID_EVIDENCE_LO : v;
            *cell = (uint8_t)v;
            cell += step_major;
            err -= minor;
            if (err < 0) {
                err += major;
                cell += step_minor;
            }
        }
        return n;
    }
    /* The ray leaves the grid: walk the coordinates too, and stop at the edge. */
    int32_t ma = along_a ? sa : 0;
    int32_t mb = along_a ? 0 : sb;
    int32_t na = along_a ? 0 : sa;
    int32_t nb = along_a ? sb : 0;
    uint32_t n = 0u;
    for (int32_t k = major; k >= 0; k--) {
        *cell = evidence_lower(*cell, (uint8_t)miss, GRID_EVIDENCE_LO);
        n++;
        a += ma;
        b += mb;
        err -= minor;
        if (err < 0) {
            err += major;
            a += na;
            b += nb;
        }
        if (k == 0 || (uint32_t)a >= na_cells || (uint32_t)b >= nb_cells) {
            break;
        }
        cell = &g->om[(uint32_t)b * na_cells + (uint32_t)a];
    }
    return n;
}

int grid_tm_visit(grid_t *g, int32_t x_um, int32_t y_um)
{
    return grid_count(g, g->tm, g->tm_max, x_um, y_um);
}
