/* SPDX-License-Identifier: MIT */
/* The exploration's bottom layer: geometry (geom.c) and the state machine (machine.c),
 * which every file above may use and which use nothing of the exploration. */
#ifndef SLAM_EXPLORE_BASE_H
#define SLAM_EXPLORE_BASE_H

#include "slam/explore.h"
#include "slam/fixed.h"

#define EXPLORE_DEG(d) ((bam32_t)((uint64_t)(d)*0x100000000ull / 360u))
#define EXPLORE_NO_CELL UINT32_MAX /* explore_cell_q16(): outside the grid */

/* explore_cell_q16() takes a negative coordinate for one beyond the grid's far side. */
_Static_assert(SLAM_GRID_A <= 0x8000u && SLAM_GRID_B <= 0x8000u,
               "a negative Q16 cell coordinate must read as outside the grid");

/* ---- geom.c ------------------------------------------------------------------------- */

/* The integer square root of v (below 2^30: the squares stay in 32 bits). */
uint32_t explore_isqrt(uint32_t v);

/* The squared distance from a pose to a world point, defined for any two positions: the
 * differences are taken modulo 2^32 (exact within 2 km, and defined after any encoder
 * glitch); the squares fit 63 bits and their sum 64. Inline: the tick measures the trail
 * with it. */
static inline uint64_t explore_dist2(const odom_pose_t *pose, int32_t x_um, int32_t y_um)
{
    int32_t dx = (int32_t)((uint32_t)pose->x_um - (uint32_t)x_um);
    int32_t dy = (int32_t)((uint32_t)pose->y_um - (uint32_t)y_um);
    return (uint64_t)((int64_t)dx * dx) + (uint64_t)((int64_t)dy * dy);
}

/* A world coordinate in Q16 cells of the grid (n cells along it); -1 outside. The
 * fraction is taken to 1/256 of a cell, which keeps every product in 32 bits. */
int32_t explore_q16_cells(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t n);

/* The frame of the robot at a pose. */
static inline explore_frame_t explore_frame_of(const odom_pose_t *pose)
{
    return (explore_frame_t){pose->x_um, pose->y_um, fix_cos(pose->heading),
                             fix_sin(pose->heading)};
}

/* The index of the cell at a position in Q16 cells of a grid of na x nb cells, or
 * EXPLORE_NO_CELL outside it. The loops that call it hold the grid's size in locals: OM's
 * bytes may alias anything, so g->a_cells would be read again at every cell. */
static inline uint32_t explore_cell_q16(uint32_t na, uint32_t nb, int32_t fx, int32_t fy)
{
    uint32_t a = (uint32_t)fx >> 16;
    uint32_t b = (uint32_t)fy >> 16;
    return a < na && b < nb ? b * na + a : EXPLORE_NO_CELL;
}

/* A ray's next cell: one step on, and the index of the cell it reaches (EXPLORE_NO_CELL
 * outside the grid). The caller counts the steps left. */
static inline uint32_t explore_ray_next(explore_ray_t *r, uint32_t na, uint32_t nb)
{
    r->fx += r->dx;
    r->fy += r->dy;
    return explore_cell_q16(na, nb, r->fx, r->fy);
}

/* The straight walk from cell (a0, b0) to cell (a1, b1), centre to centre, a cell a step
 * (at least one step). */
explore_ray_t explore_ray_between(uint32_t a0, uint32_t b0, uint32_t a1, uint32_t b1);

/* Bit k of a bit map (the frontier's blocks, the way's planes). */
static inline bool explore_bit(const uint8_t *map, uint32_t k)
{
    return (map[k >> 3] & (1u << (k & 7u))) != 0u;
}

static inline void explore_put_bit(uint8_t *map, uint32_t k, bool v)
{
    uint8_t m = (uint8_t)(1u << (k & 7u));
    map[k >> 3] = (uint8_t)(v ? map[k >> 3] | m : map[k >> 3] & ~m);
}

/* ---- machine.c ---------------------------------------------------------------------- */

/* Enter a state: its tick count and its count of readings start again. */
void explore_enter(explore_t *e, explore_state_t s);

/* A number below n from the exploration's own random stream. */
uint32_t explore_rng_below(explore_t *e, uint32_t n);

#endif /* SLAM_EXPLORE_BASE_H */
