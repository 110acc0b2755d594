/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Walls in OM for the pose correction (localize.h): what OM holds free, the wall line a
 * held-back hit lies on (its nearest occupied cell and the principal axis of the occupied
 * cells around it), and the faces of walls never seen from the robot's side.
 *
 * Internal to the core. Above loc_filter.h (its square root); stateless but for the
 * wall a caller keeps per hit (loc_assoc_t).
 */
#ifndef SLAM_LOC_WALLS_H
#define SLAM_LOC_WALLS_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/grid.h"

#ifndef LOC_ASSOC_CELLS
#define LOC_ASSOC_CELLS 3 /**< a hit's wall lies within this many cells */
#endif

/**
 * Whether OM holds the cell of (x, y) µm free by more than one beam's pass: a wall that one
 * beam grazed past is not yet free. Off the grid counts as free: nothing is mapped there.
 * On the grid, *cell is the cell's index.
 */
bool loc_known_free(const grid_t *g, int32_t x, int32_t y, uint32_t *cell);

/** A hit's wall while a match runs: the cell its point fell in and the wall found from
 *  there, which the next pass reuses while the point stays in that cell. */
typedef struct {
    grid_cell_t cell; /**< the point's cell; a = UINT16_MAX: none yet */
    int16_t n[2];     /**< the wall's unit normal, Q12 */
    uint8_t wall;     /**< where the wall cell lies (loc_walls.c's search order);
                           UINT8_MAX: no wall line there */
} loc_assoc_t;

/** Forget a hit's wall: a new match, where OM may have changed since the last. */
static inline void loc_assoc_forget(loc_assoc_t *w)
{
    w->cell.a = UINT16_MAX;
}

/**
 * The wall a point (µm) lies on: the nearest occupied cell within LOC_ASSOC_CELLS cells,
 * its centre (*wx, *wy) µm and its unit normal (*nx, *ny) in Q12 (LKF_J_ONE). The wall
 * depends on the point's cell alone: @p w holds the last cell asked about and its wall,
 * reused while OM does not change and the point stays in that cell (loc_assoc_forget()
 * when OM may have changed).
 * @retval false  no occupied cell near, or the cells around it do not lie along a line
 */
bool loc_wall_near(const grid_t *g, int32_t x_um, int32_t y_um, loc_assoc_t *w, int32_t *wx,
                   int32_t *wy, int32_t *nx, int32_t *ny);

/**
 * Whether hit q, associated with wall cell w (normal n, Q12; h the hit's offset along it),
 * lies on a face of that wall never seen from the robot's side: the wall cell lies more
 * than a cell beyond the hit as the robot at c sees it, and the cell next to it on the
 * hit's side is not known free (loc_known_free()). The far face of a thin wall, first seen
 * through a door, is then not matched to the face mapped from the other room, a wall's
 * thickness away.
 */
bool loc_unseen_face(const grid_t *g, int32_t cx, int32_t cy, int32_t qx, int32_t qy, int32_t wx,
                     int32_t wy, const int32_t n[2], int64_t h);

#endif /* SLAM_LOC_WALLS_H */
