/* SPDX-License-Identifier: MIT */
/* The corridor ahead on the map: occupied cells the body would sweep, a few a tick. */
#include "sight.h"

#define EXPLORE_MAP_CELLS 8u /* cells read a tick */

_Static_assert(SLAM_CORRIDOR_CELLS_MAX <= UINT8_MAX, "the corridor's walk counts in a byte");

/* The whole corridor at every cell size: slam_config_check() refuses a cell size and
 * clearance whose corridor would not fit SLAM_CORRIDOR_CELLS_MAX, so nothing is cut. */
void explore_corridor_init(explore_t *e, const slam_config_t *cfg)
{
    e->corridor.along = (uint8_t)slam_corridor_rows(cfg->cell_um);
    e->corridor.across = (uint8_t)slam_corridor_columns(cfg->cell_um, cfg->clearance_um);
}

/*
 * The corridor is a lattice of cell-spaced samples in the robot's frame: `along` rows
 * from one cell ahead of the axle, `across` columns spread over ±clearance. A row's
 * samples are walked from the row's left end, a cell to the right at a time.
 */
void explore_corridor_begin(explore_t *e, const grid_t *g, const explore_frame_t *f)
{
    explore_corridor_t *c = &e->corridor;
    c->next = 0u;
    c->hits = 0u;
    c->work_um = INT32_MAX;
    int32_t fx = explore_q16_cells(f->x_um, g->origin_x_um, g->cell_um, g->a_cells);
    int32_t fy = explore_q16_cells(f->y_um, g->origin_y_um, g->cell_um, g->b_cells);
    if (fx < 0 || fy < 0) {
        c->next = (uint8_t)(c->along * c->across); /* nothing to read */
        return;
    }
    /* One cell along the heading and one to the right, in Q16 cells. */
    c->dx = f->cos >> 14;
    c->dy = f->sin >> 14;
    /* The left end of the first row: a cell ahead, (across - 1) / 2 cells to the left. */
    int32_t half = (int32_t)(c->across - 1u) * 0x8000; /* half the row, Q16 cells */
    c->fx = fx + c->dx - (int32_t)(((int64_t)half * (f->sin >> 14)) >> 16);
    c->fy = fy + c->dy + (int32_t)(((int64_t)half * (f->cos >> 14)) >> 16);
    c->x = c->fx;
    c->y = c->fy;
    c->row = 0u;
    c->col = 0u;
}

bool explore_corridor_cells(explore_t *e, const grid_t *g)
{
    explore_corridor_t *c = &e->corridor;
    uint8_t total = (uint8_t)(c->along * c->across);
    /* The walk's position in locals: OM's bytes may alias anything, so fields of e would
     * be read again after every cell (this runs in the tick). */
    uint8_t next = c->next;
    uint8_t row = c->row;
    uint8_t col = c->col;
    int32_t x = c->x;
    int32_t y = c->y;
    const uint32_t na = g->a_cells;
    const uint32_t nb = g->b_cells;
    for (uint32_t n = 0; n < EXPLORE_MAP_CELLS && next < total; n++) {
        /* Sample next: row next / across (along the heading), column next % across (to
         * the right), kept as a running position. */
        if (col == c->across) {
            col = 0u;
            row++;
            x = c->fx + (int32_t)row * c->dx;
            y = c->fy + (int32_t)row * c->dy;
        }
        uint32_t k = explore_cell_q16(na, nb, x, y);
        x += c->dy; /* a cell to the right */
        y -= c->dx;
        col++;
        next++;
        /* A lone occupied cell is left alone (a ghost echo, or the cone's smear beside
         * an edge); the second one stops the robot: a wall fills several. */
        if (k == EXPLORE_NO_CELL || grid_state(g, k) != GRID_OCCUPIED) {
            continue;
        }
        /* A cell holding more than one hit's evidence, after the beams that passed
         * through it, is no ghost: it stops the robot alone (the end of a thin screen,
         * whose faces beyond the grazing angle send nothing back). */
        c->hits =
            (uint8_t)(c->hits + 1u +
                      (g->mode == OM_MODE_EVIDENCE && g->om[k] > GRID_EVIDENCE_ZERO + g->hit));
        if (c->hits >= 2u) {
            c->work_um = (int32_t)(row + 1u) * (int32_t)e->cfg.cell_um;
            next = total; /* rows further on can only be further: done */
        }
    }
    c->next = next;
    c->row = row;
    c->col = col;
    c->x = x;
    c->y = y;
    return next >= total;
}
