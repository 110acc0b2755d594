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
#define LOC_LINEAR_PERCENT                                                                         \
    35 /* smaller eigenvalue at most this share of the larger: walls                               \
          a few cells thick still count; corners and blobs do not */
#endif

bool loc_known_free(const grid_t *g, int32_t x, int32_t y, uint32_t *cell)
{
    grid_cell_t k;
    if (grid_cell_of(g, x, y, &k) != SLAM_OK) {
        return true;
    }
    uint32_t i = grid_index(g, k);
    *cell = i;
    return g->mode == OM_MODE_EVIDENCE ? (uint32_t)g->om[i] + g->miss < GRID_EVIDENCE_ZERO
                                       : grid_state(g, i) == GRID_FREE;
}

/* Whether OM holds cell (a, b) occupied: its byte above `top` (grid_occupied_above()). */
static bool occupied(const grid_t *g, uint8_t top, int32_t a, int32_t b)
{
    return (uint32_t)a < g->a_cells && (uint32_t)b < g->b_cells &&
           g->om[(uint32_t)b * g->a_cells + (uint32_t)a] > top;
}

/* The sums below are written out for a 5×5 block. */
_Static_assert(LOC_NORMAL_HALF == 2, "wall_normal() sums a 5x5 block");

/* Cells a − 2 … a + 2 of row b: 1 where occupied, 0 where not or off the grid. */
static void row_of_five(const grid_t *g, uint8_t top, int32_t a, int32_t b, int32_t o[5])
{
    if ((uint32_t)b >= g->b_cells) {
        o[0] = o[1] = o[2] = o[3] = o[4] = 0;
    } else if (a >= 2 && a + 2 < (int32_t)g->a_cells) {
        const uint8_t *row = &g->om[(uint32_t)b * g->a_cells + (uint32_t)a - 2u];
        for (unsigned i = 0; i < 5u; i++) {
            o[i] = row[i] > top;
        }
    } else {
        for (int32_t i = 0; i < 5; i++) {
            o[i] = occupied(g, top, a - 2 + i, b);
        }
    }
}

/* The normal of the wall through cell (a, b), Q12, from the occupied cells of the 5×5
 * block around it: the direction of least spread, when the cells lie along a line. */
static bool wall_normal(const grid_t *g, uint8_t top, int32_t a, int32_t b, int32_t *nx,
                        int32_t *ny)
{
    /* Over the occupied cells at offsets (i, j): their number, Σi, Σj, Σi², Σj², Σij. */
    int32_t n = 0;
    int32_t sx = 0;
    int32_t sy = 0;
    int32_t sxx = 0;
    int32_t syy = 0;
    int32_t sxy = 0;
    for (int32_t j = -2; j <= 2; j++) {
        int32_t o[5];
        row_of_five(g, top, a, b + j, o);
        int32_t rn = o[0] + o[1] + o[2] + o[3] + o[4];
        int32_t rs = 2 * (o[4] - o[0]) + o[3] - o[1]; /* Σi over the row */
        n += rn;
        sx += rs;
        sxx += 4 * (o[0] + o[4]) + o[1] + o[3];
        sy += j * rn;
        syy += j * j * rn;
        sxy += j * rs;
    }
    if (n < LOC_NORMAL_MIN_CELLS) {
        return false;
    }
    /* n² times the covariance of the cells: small integers. With n <= 25, |Σi| <= 15,
     * Σi² <= 50 and |Σij| <= 36, |cxx|, |cyy| <= 1250 and |cxy| <= 1125, so every value
     * below, squares included, stays within 32 bits. */
    int32_t cxx = n * sxx - sx * sx;
    int32_t cyy = n * syy - sy * sy;
    int32_t cxy = n * sxy - sx * sy;
    int32_t diff = cxx - cyy;
    int32_t disc = (int32_t)lkf_isqrt((uint32_t)(diff * diff + 4 * cxy * cxy)); /* λ1 − λ2 */
    int32_t tr = cxx + cyy;                                                     /* λ1 + λ2 */
    /* λ2 <= p·λ1: (tr − disc)·100 <= p·(tr + disc). */
    if (tr <= 0 || (tr - disc) * 100 > LOC_LINEAR_PERCENT * (tr + disc)) {
        return false;
    }
    /* The line's direction, the eigenvector of λ1 = (tr + disc) / 2: (2·cxy, disc − diff)
     * or, where that vanishes (a line along x), (disc + diff, 2·cxy). */
    int32_t vx = 2 * cxy;
    int32_t vy = disc - diff;
    if (vx == 0 && vy == 0) {
        vx = disc + diff;
        vy = 2 * cxy;
    }
    int32_t len = (int32_t)lkf_isqrt((uint32_t)(vx * vx + vy * vy));
    if (len == 0) {
        return false;
    }
    *nx = -vy * LKF_J_ONE / len;
    *ny = vx * LKF_J_ONE / len;
    return true;
}

/* The cells within LOC_ASSOC_CELLS (3) cells of a point's cell, nearest first, and among
 * equals in row order: the first occupied one is the nearest (Euclidean, in cells). */
/* clang-format off */
#define LOC_ASSOC_ORDER(X)                                                                   \
    X(0, 0) X(0, -1) X(-1, 0) X(1, 0) X(0, 1) X(-1, -1) X(1, -1) X(-1, 1) X(1, 1) X(0, -2)   \
    X(-2, 0) X(2, 0) X(0, 2) X(-1, -2) X(1, -2) X(-2, -1) X(2, -1) X(-2, 1) X(2, 1) X(-1, 2) \
    X(1, 2) X(-2, -2) X(2, -2) X(-2, 2) X(2, 2) X(0, -3) X(-3, 0) X(3, 0) X(0, 3)
/* clang-format on */
#define LOC_ASSOC_PAIR(da, db) {da, db},
static const int8_t loc_assoc_order[][2] = {LOC_ASSOC_ORDER(LOC_ASSOC_PAIR)};
#define LOC_ASSOC_N (sizeof loc_assoc_order / sizeof loc_assoc_order[0])
_Static_assert(LOC_ASSOC_CELLS == 3, "loc_assoc_order holds the cells within 3");
_Static_assert(LOC_ASSOC_N < UINT8_MAX, "loc_assoc_t's wall indexes the order");
_Static_assert(3 * SLAM_GRID_A + 3 <= INT16_MAX, "a step fits an int16_t");

/* The same cells as steps in OM's array, for a cell LOC_ASSOC_CELLS inside a grid of
 * loc_assoc_row cells a row: worked out again when a grid of another A asks (a step a
 * load, where the offsets and a multiply cost three instructions more each). */
static int16_t loc_assoc_step[LOC_ASSOC_N];
static uint16_t loc_assoc_row;

static const int16_t *assoc_steps(const grid_t *g)
{
    if (loc_assoc_row != g->a_cells) {
        for (size_t k = 0; k < LOC_ASSOC_N; k++) {
            loc_assoc_step[k] =
                (int16_t)(loc_assoc_order[k][0] + loc_assoc_order[k][1] * (int32_t)g->a_cells);
        }
        loc_assoc_row = g->a_cells;
    }
    return loc_assoc_step;
}

/* The wall of a point in cell c: its place in loc_assoc_order and its normal, or
 * UINT8_MAX. */
static uint8_t wall_of(const grid_t *g, grid_cell_t c, int16_t n[2])
{
    const uint8_t top = grid_occupied_above(g->mode);
    const int32_t r = LOC_ASSOC_CELLS;
    size_t k = 0;
    if (c.a >= r && c.a + r < (int32_t)g->a_cells && c.b >= r && c.b + r < (int32_t)g->b_cells) {
        const uint8_t *at = &g->om[grid_index(g, c)];
        const int16_t *step = assoc_steps(g);
        while (k < LOC_ASSOC_N && at[step[k]] <= top) {
            k++;
        }
    } else {
        while (k < LOC_ASSOC_N &&
               !occupied(g, top, c.a + loc_assoc_order[k][0], c.b + loc_assoc_order[k][1])) {
            k++;
        }
    }
    int32_t nx;
    int32_t ny;
    if (k == LOC_ASSOC_N ||
        !wall_normal(g, top, c.a + loc_assoc_order[k][0], c.b + loc_assoc_order[k][1], &nx, &ny)) {
        return UINT8_MAX;
    }
    n[0] = (int16_t)nx; /* a unit normal: within ±LKF_J_ONE */
    n[1] = (int16_t)ny;
    return (uint8_t)k;
}

bool loc_wall_near(const grid_t *g, int32_t x_um, int32_t y_um, loc_assoc_t *w, int32_t *wx,
                   int32_t *wy, int32_t *nx, int32_t *ny)
{
    grid_cell_t c;
    if (grid_cell_of(g, x_um, y_um, &c) != SLAM_OK) {
        return false;
    }
    if (c.a != w->cell.a || c.b != w->cell.b) {
        w->cell = c;
        w->wall = wall_of(g, c, w->n);
    }
    if (w->wall == UINT8_MAX) {
        return false;
    }
    int32_t half = (int32_t)(g->cell_um / 2u);
    *wx = g->origin_x_um + (c.a + loc_assoc_order[w->wall][0]) * (int32_t)g->cell_um + half;
    *wy = g->origin_y_um + (c.b + loc_assoc_order[w->wall][1]) * (int32_t)g->cell_um + half;
    *nx = w->n[0];
    *ny = w->n[1];
    return true;
}

bool loc_unseen_face(const grid_t *g, int32_t cx, int32_t cy, int32_t qx, int32_t qy, int32_t wx,
                     int32_t wy, const int32_t n[2], int64_t h)
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
