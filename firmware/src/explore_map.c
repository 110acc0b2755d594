/* SPDX-License-Identifier: MIT */
/* The corridor ahead on the map: occupied cells the body would sweep, a few a tick. */
#include "explore_internal.h"

void explore_map_init(explore_t *e, const slam_config_t *cfg)
{
    uint32_t along = EXPLORE_MAP_REACH_UM / cfg->cell_um;
    uint32_t across = 2u * cfg->clearance_um / cfg->cell_um + 1u;
    e->map_along = (uint8_t)(along < 1u ? 1u : (along > EXPLORE_MAP_ALONG ? EXPLORE_MAP_ALONG : along));
    e->map_across = (uint8_t)(across > EXPLORE_MAP_ACROSS ? EXPLORE_MAP_ACROSS : across);
}

int32_t explore_q16_cells(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t n)
{
    int64_t d = (int64_t)v_um - origin_um;
    if (d < 0 || d >= (int64_t)cell_um * n) {
        return -1;
    }
    uint32_t u = (uint32_t)d;
    uint32_t whole = u / cell_um;
    uint32_t frac = ((u - whole * cell_um) << 8) / cell_um;
    return (int32_t)((whole << 16) | (frac << 8));
}

/*
 * The corridor is a lattice of cell-spaced samples in the robot's frame: map_along rows
 * from one cell ahead of the axle, map_across columns spread over ±clearance. A row's
 * samples are walked from the row's left end, a cell to the right at a time.
 */
void explore_map_begin(explore_t *e, const odom_pose_t *pose, const grid_t *g, q1_30_t c,
                       q1_30_t s)
{
    e->map_next = 0u;
    e->map_hits = 0u;
    e->map_work_um = INT32_MAX;
    int32_t fx = explore_q16_cells(pose->x_um, g->origin_x_um, g->cell_um, SLAM_GRID_A);
    int32_t fy = explore_q16_cells(pose->y_um, g->origin_y_um, g->cell_um, SLAM_GRID_B);
    if (fx < 0 || fy < 0) {
        e->map_next = (uint8_t)(e->map_along * e->map_across); /* nothing to read */
        return;
    }
    /* One cell along the heading and one to the right, in Q16 cells. */
    e->map_dx = c >> 14;
    e->map_dy = s >> 14;
    /* The left end of the first row: a cell ahead, (across - 1) / 2 cells to the left. */
    int32_t half = (int32_t)(e->map_across - 1u) * 0x8000; /* half the row, Q16 cells */
    e->map_fx = fx + e->map_dx - (int32_t)(((int64_t)half * (s >> 14)) >> 16);
    e->map_fy = fy + e->map_dy + (int32_t)(((int64_t)half * (c >> 14)) >> 16);
    e->map_x = e->map_fx;
    e->map_y = e->map_fy;
    e->map_row = 0u;
    e->map_col = 0u;
}

bool explore_map_cells(explore_t *e, const grid_t *g)
{
    uint8_t total = (uint8_t)(e->map_along * e->map_across);
    /* The pass's position in locals: OM's bytes may alias anything, so fields of e would be
     * read again after every cell (this runs in the tick). */
    uint8_t next = e->map_next;
    uint8_t row = e->map_row;
    uint8_t col = e->map_col;
    int32_t x = e->map_x;
    int32_t y = e->map_y;
    for (uint32_t n = 0; n < EXPLORE_MAP_CELLS && next < total; n++) {
        /* Sample next: row next / across (along the heading), column next % across (to
         * the right), kept as a running position. */
        if (col == e->map_across) {
            col = 0u;
            row++;
            x = e->map_fx + (int32_t)row * e->map_dx;
            y = e->map_fy + (int32_t)row * e->map_dy;
        }
        int32_t sx = x;
        int32_t sy = y;
        x += e->map_dy; /* a cell to the right */
        y -= e->map_dx;
        col++;
        next++;
        uint32_t a = (uint32_t)sx >> 16;
        uint32_t b = (uint32_t)sy >> 16;
        if (sx < 0 || sy < 0 || a >= SLAM_GRID_A || b >= SLAM_GRID_B) {
            continue;
        }
        /* A lone occupied cell is left alone (a ghost echo, or the cone's smear beside
         * an edge); the second one stops the robot: a wall fills several. */
        uint32_t k = b * SLAM_GRID_A + a;
        if (grid_state(g, k) != GRID_OCCUPIED) {
            continue;
        }
        /* A cell holding more than one hit's evidence, after the beams that passed through it,
         * is no ghost: it stops the robot alone (the end of a thin screen, whose faces beyond the
         * grazing angle send nothing back). */
        e->map_hits = (uint8_t)(e->map_hits + 1u +
                                (g->mode == OM_MODE_EVIDENCE &&
                                 g->om[k] > GRID_EVIDENCE_ZERO + g->hit));
        if (e->map_hits >= 2u) {
            e->map_work_um = (int32_t)(row + 1u) * (int32_t)e->cell_um;
            next = total; /* rows further on can only be further: done */
        }
    }
    e->map_next = next;
    e->map_row = row;
    e->map_col = col;
    e->map_x = x;
    e->map_y = y;
    return next >= total;
}
