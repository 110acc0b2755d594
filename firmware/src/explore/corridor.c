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
    /* The walk in locals, stored back once at the end: a store to a byte may alias
     * anything, so with one in the loop every field of e and g would be read again after
     * it (this runs in the tick). */
    const uint32_t across = c->across;
    const uint32_t total = (uint32_t)c->along * across;
    const int32_t dx = c->dx;
    const int32_t dy = c->dy;
    const uint32_t na = g->a_cells;
    const uint32_t nb = g->b_cells;
    const uint8_t *om = g->om;
    /* grid_state()'s occupied, one compare a cell. A cell holding more than one hit's
     * evidence, after the beams that passed through it, is no ghost: it stops the robot
     * alone (the end of a thin screen, whose faces beyond the grazing angle send nothing
     * back). */
    const uint32_t occupied = grid_occupied_above(g->mode);
    const uint32_t strong =
        g->mode == OM_MODE_EVIDENCE ? GRID_EVIDENCE_ZERO + (uint32_t)g->hit : UINT32_MAX;
    uint32_t next = c->next;
    uint32_t row = c->row;
    uint32_t col = c->col;
    uint32_t hits = c->hits;
    int32_t x = c->x;
    int32_t y = c->y;
    uint32_t end = next + EXPLORE_MAP_CELLS < total ? next + EXPLORE_MAP_CELLS : total;
    for (; next < end; next++) {
        /* Sample next: row next / across (along the heading), column next % across (to
         * the right), kept as a running position. */
        if (col == across) {
            col = 0u;
            row++;
            x = c->fx + (int32_t)row * dx;
            y = c->fy + (int32_t)row * dy;
        }
        uint32_t k = explore_cell_q16(na, nb, x, y);
        x += dy; /* a cell to the right */
        y -= dx;
        col++;
        /* A lone occupied cell is left alone (a ghost echo, or the cone's smear beside
         * an edge); the second one stops the robot: a wall fills several. */
        if (k == EXPLORE_NO_CELL || om[k] <= occupied) {
            continue;
        }
        hits += om[k] > strong ? 2u : 1u;
        if (hits >= 2u) {
            c->work_um = (int32_t)(row + 1u) * (int32_t)e->cfg.cell_um;
            next = total; /* rows further on can only be further: done */
            break;
        }
    }
    c->next = (uint8_t)next;
    c->row = (uint8_t)row;
    c->col = (uint8_t)col;
    c->hits = (uint8_t)hits;
    c->x = x;
    c->y = y;
    return next >= total;
}
