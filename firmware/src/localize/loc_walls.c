/* SPDX-License-Identifier: MIT */
/* Walls in OM for the pose correction: what is known free, the wall line near a point, and
 * the faces of walls never seen from the robot's side. */
#include "loc_walls.h"

#include <stddef.h>

#include "loc_filter.h"
#include "slam/error.h"

/* A 5×5 block says where a wall runs. */
#ifndef LOC_NORMAL_HALF
#define LOC_NORMAL_HALF 2
#endif
#ifndef LOC_NORMAL_MIN_CELLS
#define LOC_NORMAL_MIN_CELLS 4
#endif
#ifndef LOC_LINEAR_PERCENT
#define LOC_LINEAR_PERCENT 35 /* smaller eigenvalue at most this share of the larger: walls
                                 a few cells thick still count; corners and blobs do not */
#endif

bool loc_known_free(const grid_t *g, int32_t x, int32_t y, uint32_t *cell)
{
    grid_cell_t k;
    if (grid_cell_of(g, x, y, &k) != SLAM_OK) {
        return true;
    }
    uint32_t i = grid_index(k);
    *cell = i;
    return g->mode == OM_MODE_EVIDENCE ? (uint32_t)g->om[i] + g->miss < GRID_EVIDENCE_ZERO
                                       : grid_state(g, i) == GRID_FREE;
}

static bool occupied(const grid_t *g, int32_t a, int32_t b)
{
    return (uint32_t)a < SLAM_GRID_A && (uint32_t)b < SLAM_GRID_B &&
           grid_state(g, (uint32_t)b * SLAM_GRID_A + (uint32_t)a) == GRID_OCCUPIED;
}

/* The normal of the wall through cell (a, b), Q12, from the occupied cells of the 5×5
 * block around it: the direction of least spread, when the cells lie along a line. */
static bool wall_normal(const grid_t *g, int32_t a, int32_t b, int32_t *nx, int32_t *ny)
{
    int32_t n = 0;
    int32_t sx = 0;
    int32_t sy = 0;
    int32_t sxx = 0;
    int32_t syy = 0;
    int32_t sxy = 0;
    for (int32_t j = -LOC_NORMAL_HALF; j <= LOC_NORMAL_HALF; j++) {
        for (int32_t i = -LOC_NORMAL_HALF; i <= LOC_NORMAL_HALF; i++) {
            if (occupied(g, a + i, b + j)) {
                n++;
                sx += i;
                sy += j;
                sxx += i * i;
                syy += j * j;
                sxy += i * j;
            }
        }
    }
    if (n < LOC_NORMAL_MIN_CELLS) {
        return false;
    }
    /* n² times the covariance of the cells: small integers. */
    int64_t cxx = (int64_t)n * sxx - (int64_t)sx * sx;
    int64_t cyy = (int64_t)n * syy - (int64_t)sy * sy;
    int64_t cxy = (int64_t)n * sxy - (int64_t)sx * sy;
    int64_t diff = cxx - cyy;
    int64_t disc = lkf_isqrt((uint64_t)(diff * diff + 4 * cxy * cxy)); /* λ1 − λ2 */
    int64_t tr = cxx + cyy;                                           /* λ1 + λ2 */
    /* λ2 <= p·λ1: (tr − disc)·100 <= p·(tr + disc). */
    if (tr <= 0 || (tr - disc) * 100 > LOC_LINEAR_PERCENT * (tr + disc)) {
        return false;
    }
    /* The line's direction, the eigenvector of λ1 = (tr + disc) / 2: (2·cxy, disc − diff)
     * or, where that vanishes (a line along x), (disc + diff, 2·cxy). */
    int64_t vx = 2 * cxy;
    int64_t vy = disc - diff;
    if (vx == 0 && vy == 0) {
        vx = disc + diff;
        vy = 2 * cxy;
    }
    int64_t len = lkf_isqrt((uint64_t)(vx * vx + vy * vy));
    if (len == 0) {
        return false;
    }
    *nx = (int32_t)fix_div_s64(-vy * LKF_J_ONE, len);
    *ny = (int32_t)fix_div_s64(vx * LKF_J_ONE, len);
    return true;
}

/* The cells within LOC_ASSOC_CELLS (3) cells of a point's cell, nearest first, and among
 * equals in row order: the first occupied one is the nearest (Euclidean, in cells). */
static const int8_t loc_assoc_order[][2] = {
    {0, 0},   {0, -1},  {-1, 0}, {1, 0},  {0, 1},  {-1, -1}, {1, -1}, {-1, 1}, {1, 1},  {0, -2},
    {-2, 0},  {2, 0},   {0, 2},  {-1, -2}, {1, -2}, {-2, -1}, {2, -1}, {-2, 1}, {2, 1}, {-1, 2},
    {1, 2},   {-2, -2}, {2, -2}, {-2, 2}, {2, 2},  {0, -3},  {-3, 0}, {3, 0},  {0, 3},
};
_Static_assert(LOC_ASSOC_CELLS == 3, "loc_assoc_order holds the cells within 3");

bool loc_wall_near(const grid_t *g, int32_t x_um, int32_t y_um, int32_t *wx, int32_t *wy,
                   int32_t *nx, int32_t *ny)
{
    grid_cell_t c;
    if (grid_cell_of(g, x_um, y_um, &c) != SLAM_OK) {
        return false;
    }
    size_t k = 0;
    const size_t n = sizeof loc_assoc_order / sizeof loc_assoc_order[0];
    while (k < n && !occupied(g, c.a + loc_assoc_order[k][0], c.b + loc_assoc_order[k][1])) {
        k++;
    }
    if (k == n) {
        return false;
    }
    int32_t ba = c.a + loc_assoc_order[k][0];
    int32_t bb = c.b + loc_assoc_order[k][1];
    if (!wall_normal(g, ba, bb, nx, ny)) {
        return false;
    }
    int32_t half = (int32_t)(g->cell_um / 2u);
    *wx = g->origin_x_um + ba * (int32_t)g->cell_um + half;
    *wy = g->origin_y_um + bb * (int32_t)g->cell_um + half;
    return true;
}

bool loc_unseen_face(const grid_t *g, int32_t cx, int32_t cy, int32_t qx, int32_t qy,
                     int32_t wx, int32_t wy, const int32_t n[2], int64_t h)
{
    /* Differences modulo 2^32, as grid.c's: exact, since every position lies within the
     * 1 km world slam_config_check() allows; their products fit 64 bits. */
    int32_t ax = (int32_t)((uint32_t)wx - (uint32_t)qx);
    int32_t ay = (int32_t)((uint32_t)wy - (uint32_t)qy);
    int32_t bx = (int32_t)((uint32_t)qx - (uint32_t)cx);
    int32_t by = (int32_t)((uint32_t)qy - (uint32_t)cy);
    int32_t cell = (int32_t)g->cell_um;
    if ((int64_t)ax * bx + (int64_t)ay * by <= 0 ||
        (int64_t)ax * ax + (int64_t)ay * ay <= (int64_t)cell * cell) {
        return false;
    }
    int32_t side = h < 0 ? -cell : cell;
    uint32_t k;
    return !loc_known_free(g, wx + (int32_t)(((int64_t)n[0] * side) >> LKF_J_SHIFT),
                           wy + (int32_t)(((int64_t)n[1] * side) >> LKF_J_SHIFT), &k);
}
