/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The two occupancy grids of the paper: the obstacle map OM and the trajectory map TM.
 *
 * Both are A×B arrays of `uint8_t` cells of side L (Eq. 1-2), A cells along world x and
 * B along world y. Cell (a, b) covers x in [ox + a·L, ox + (a+1)·L) and y likewise, where
 * (ox, oy) is the grid origin: the world position of the lower-left corner of cell (0, 0).
 * The origin puts the start pose at the centre of a configurable start cell, so negative
 * world coordinates map into the grid.
 *
 * Storage is row by row of constant y: cell (a, b) is at index b·A + a, so a dump of the
 * array is an image with x to the right and y downwards (flip it for a map).
 *
 * OM counts sonar hits and saturates at OMmax (Eq. 6); TM counts control periods spent in
 * a cell and saturates at TMmax (Eq. 7). Neither ever decrements. A point outside the grid
 * is rejected and counted; nothing is ever written outside the arrays.
 */
#ifndef SLAM_GRID_H
#define SLAM_GRID_H

#include <stdint.h>

#include "slam/config.h"

#ifndef SLAM_GRID_A
#define SLAM_GRID_A 160u /**< cells along world x (8 m at the default 50 mm) */
#endif
#ifndef SLAM_GRID_B
#define SLAM_GRID_B 160u /**< cells along world y */
#endif
#define SLAM_GRID_CELLS ((uint32_t)SLAM_GRID_A * (uint32_t)SLAM_GRID_B)

#if SLAM_GRID_A < 3 || SLAM_GRID_B < 3 || SLAM_GRID_A > 4096 || SLAM_GRID_B > 4096
#error "SLAM_GRID_A and SLAM_GRID_B must be between 3 and 4096"
#endif

/** A cell index: a along x, b along y. */
typedef struct {
    uint16_t a;
    uint16_t b;
} grid_cell_t;

/** OM, TM and the geometry that maps world points to their cells. */
typedef struct {
    int32_t origin_x_um; /**< world x of the lower-left corner of cell (0, 0) */
    int32_t origin_y_um; /**< world y of the lower-left corner of cell (0, 0) */
    uint32_t cell_um;    /**< L */
    uint8_t om_max;      /**< OMmax */
    uint8_t tm_max;      /**< TMmax */
    uint32_t rejected;   /**< points that fell outside the grid (saturating) */
    uint8_t om[SLAM_GRID_CELLS]; /**< obstacle map, index b·A + a */
    uint8_t tm[SLAM_GRID_CELLS]; /**< trajectory map, index b·A + a */
} grid_t;

/**
 * Clear both maps and set the geometry from the configuration (L, start pose, start
 * cell, OMmax, TMmax). The configuration must have passed slam_config_check().
 */
void grid_init(grid_t *g, const slam_config_t *cfg);

/**
 * The cell of a world point (Eq. 1-2 with the origin offset).
 * @param x_um, y_um  world point in µm
 * @param cell        out: the cell; untouched when the point is outside
 * @retval SLAM_OK        the point is inside the grid
 * @retval SLAM_EOUTSIDE  the point is outside; nothing is counted
 * ISR-safe, O(1).
 */
int grid_cell_of(const grid_t *g, int32_t x_um, int32_t y_um, grid_cell_t *cell);

/**
 * One sonar hit at a world point: OM of its cell += 1 up to OMmax (Eq. 6).
 * @retval SLAM_OK        the cell was updated (or was already at OMmax)
 * @retval SLAM_EOUTSIDE  the point is outside; g->rejected counts it, no cell changes
 * ISR-safe, O(1).
 */
int grid_om_hit(grid_t *g, int32_t x_um, int32_t y_um);

/**
 * One control period spent at a world point: TM of its cell += 1 up to TMmax (Eq. 7).
 * Return values as grid_om_hit(). ISR-safe, O(1).
 */
int grid_tm_visit(grid_t *g, int32_t x_um, int32_t y_um);

/** The array index b·A + a of a cell. */
static inline uint32_t grid_index(grid_cell_t c)
{
    return (uint32_t)c.b * SLAM_GRID_A + c.a;
}

/** What the maps say of a cell. */
typedef enum {
    GRID_UNKNOWN = 0, /**< nothing has been seen there */
    GRID_FREE,        /**< known free: the robot has been there */
    GRID_OCCUPIED,    /**< OM holds obstacle evidence */
} grid_state_t;

/**
 * What OM and TM say of the cell at an array index: GRID_OCCUPIED when OM holds any
 * obstacle evidence (OM >= 1, the raw map of Eq. 6), else GRID_FREE when the robot has
 * been there (TM > 0), else GRID_UNKNOWN. Exploration, the map exports and the scoring all
 * read cells through this one rule. ISR-safe, O(1).
 */
static inline grid_state_t grid_state(const grid_t *g, uint32_t index)
{
    if (g->om[index] != 0u) {
        return GRID_OCCUPIED;
    }
    return g->tm[index] != 0u ? GRID_FREE : GRID_UNKNOWN;
}

#endif /* SLAM_GRID_H */
