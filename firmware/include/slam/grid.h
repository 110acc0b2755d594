/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The two occupancy grids of the paper: the obstacle map OM and the trajectory map TM.
 *
 * Both are A×B arrays of `uint8_t` cells of side L (Eq. 1-2), A cells along world x and
 * B along world y. A and B are the grid's own (a_cells, b_cells), set at grid_init() from
 * the configuration's grid_a and grid_b within the capacity the build reserves,
 * SLAM_GRID_A × SLAM_GRID_B: one firmware image serves a small room and a whole flat, and a
 * saved map records its size. Cell (a, b) covers x in [ox + a·L, ox + (a+1)·L) and y likewise,
 * where (ox, oy) is the grid origin: the world position of the lower-left corner of cell (0, 0).
 * The origin puts the start pose at the centre of a configurable start cell, so negative
 * world coordinates map into the grid.
 *
 * Storage is row by row of constant y: cell (a, b) is at index b·A + a, so a dump of the
 * array is an image with x to the right and y downwards (flip it for a map).
 *
 * What an OM cell holds depends on the configured om_mode:
 * - OM_MODE_COUNT, the paper's Eq. 6: the number of sonar hits, saturating at OMmax; 0 is
 *   a cell never hit, and nothing ever decrements.
 * - OM_MODE_EVIDENCE: a cell holds v = GRID_EVIDENCE_ZERO + L, L a log-odds of occupancy
 *   in [−127, 127]; every cell starts at L = 0, unknown. A hit adds om_hit, a beam that
 *   passes through (or the robot standing on the cell) takes om_miss, both saturating.
 *   L > 0 is occupied, L < 0 free, L = 0 unknown (never seen, or as much evidence for as
 *   against). With hit 4 and miss 1 a cell stays occupied until four beams have passed
 *   through it for every hit.
 *
 * TM counts control periods spent in a cell and saturates at TMmax (Eq. 7); it never
 * decrements. A point outside the grid is rejected and counted; nothing is ever written
 * outside the arrays.
 */
#ifndef SLAM_GRID_H
#define SLAM_GRID_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"

/* The capacity: the most cells along each side a run may ask for (grid_a, grid_b), the
 * size of the static arrays. A run's grid uses the first A·B cells of each. */
#ifndef SLAM_GRID_A
#define SLAM_GRID_A 160u /**< most cells along world x (8 m at the default 50 mm) */
#endif
#ifndef SLAM_GRID_B
#define SLAM_GRID_B 160u /**< most cells along world y */
#endif
#define SLAM_GRID_CELLS ((uint32_t)SLAM_GRID_A * (uint32_t)SLAM_GRID_B)

#if SLAM_GRID_A < 3 || SLAM_GRID_B < 3 || SLAM_GRID_A > 4096 || SLAM_GRID_B > 4096
#error "SLAM_GRID_A and SLAM_GRID_B must be between 3 and 4096"
#endif

/** OM_MODE_EVIDENCE: the byte of log-odds 0, and the largest |log-odds|. */
#define GRID_EVIDENCE_ZERO 128u
#define GRID_EVIDENCE_MAX 127u

/** A cell index: a along x, b along y. */
typedef struct {
    uint16_t a;
    uint16_t b;
} grid_cell_t;

/** OM, TM and the geometry that maps world points to their cells. */
typedef struct {
    int32_t origin_x_um;         /**< world x of the lower-left corner of cell (0, 0) */
    int32_t origin_y_um;         /**< world y of the lower-left corner of cell (0, 0) */
    uint32_t cell_um;            /**< L */
    uint16_t a_cells;            /**< A: cells along x, 3..SLAM_GRID_A */
    uint16_t b_cells;            /**< B: cells along y, 3..SLAM_GRID_B */
    uint32_t span_x_um;          /**< A·L, kept: every point's test compares with it */
    uint32_t span_y_um;          /**< B·L */
    uint8_t om_max;              /**< OMmax */
    uint8_t tm_max;              /**< TMmax */
    uint8_t mode;                /**< an om_mode_t */
    uint8_t hit;                 /**< OM_MODE_EVIDENCE: log-odds step of a hit */
    uint8_t miss;                /**< OM_MODE_EVIDENCE: log-odds step of a pass */
    uint32_t rejected;           /**< points that fell outside the grid (saturating) */
    uint8_t om[SLAM_GRID_CELLS]; /**< obstacle map, index b·A + a (A·B cells used) */
    uint8_t tm[SLAM_GRID_CELLS]; /**< trajectory map, index b·A + a (A·B cells used) */
} grid_t;

/**
 * World coordinate of the grid's lower-left corner along one axis: the start pose sits at
 * the centre of the start cell. (At its corner the grid lines would lie on whole multiples
 * of L from the start; host_sim/experiments.md has what that did to the maps. The default
 * start, SLAM_START_UM, half a cell from the world's origin, puts them on whole multiples
 * of L from the world's origin instead.)
 */
static inline int32_t grid_origin_um(int32_t start_um, uint16_t start_cell, uint32_t cell_um)
{
    return (int32_t)(start_um - (int64_t)start_cell * cell_um - (int64_t)(cell_um / 2u));
}

/** The cells along x and y a configuration asks for: grid_a and grid_b, or the capacity
 *  where they are 0. */
static inline uint16_t grid_cells_a(const slam_config_t *cfg)
{
    return cfg->grid_a != 0u ? cfg->grid_a : (uint16_t)SLAM_GRID_A;
}
static inline uint16_t grid_cells_b(const slam_config_t *cfg)
{
    return cfg->grid_b != 0u ? cfg->grid_b : (uint16_t)SLAM_GRID_B;
}

/** A·B, the cells of each map a grid uses. */
static inline uint32_t grid_cells(const grid_t *g)
{
    return (uint32_t)g->a_cells * g->b_cells;
}

/** Keep span_x_um and span_y_um with the grid's size and cell: after any change of them. */
static inline void grid_set_spans(grid_t *g)
{
    g->span_x_um = g->cell_um * g->a_cells;
    g->span_y_um = g->cell_um * g->b_cells;
}

/**
 * Clear both maps (OM to unknown: 0 counted hits, or log-odds 0) and set the geometry from the
 * configuration (A and B, L, start pose, start cell, OMmax, TMmax). The configuration must
 * have passed slam_config_check().
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
 * One sonar hit at a world point: OM of its cell += 1 up to OMmax (Eq. 6), or, in
 * OM_MODE_EVIDENCE, its log-odds += om_hit up to +127.
 * @retval SLAM_OK        the cell was updated (or was already saturated)
 * @retval SLAM_EOUTSIDE  the point is outside; g->rejected counts it, no cell changes
 * ISR-safe, O(1).
 */
int grid_om_hit(grid_t *g, int32_t x_um, int32_t y_um);

/** grid_om_hit() with a log-odds step of its own in OM_MODE_EVIDENCE (OM_MODE_COUNT counts
 *  the hit as grid_om_hit() does). Same return values. ISR-safe, O(1). */
int grid_om_add(grid_t *g, int32_t x_um, int32_t y_um, uint8_t step);

/**
 * OM_MODE_EVIDENCE: part of a hit ahead of the rest, its cell's log-odds += step up to
 * +127, or, taken back, −= step down to −127 (localize.c places half of a held-back hit
 * when it leaves the matched window and the rest when it leaves the hold, and takes the
 * halves out of OM while it matches). Nothing outside the grid, nothing counted; nothing
 * in OM_MODE_COUNT. ISR-safe, O(1).
 */
void grid_om_part(grid_t *g, int32_t x_um, int32_t y_um, uint8_t step, bool take_back);

/**
 * OM_MODE_EVIDENCE: free-space evidence at one world point (the robot stands there):
 * its cell's log-odds −= om_miss down to −127. Nothing in OM_MODE_COUNT.
 * Return values as grid_om_hit(). ISR-safe, O(1).
 */
int grid_om_free(grid_t *g, int32_t x_um, int32_t y_um);

/**
 * OM_MODE_EVIDENCE: a cell just behind a wall face the sonar has heard, where no beam
 * reaches: evidence of a wall there came from readings placed wrongly (a pose or a range
 * error), and its log-odds −= om_miss while above 0, down to 0 (unknown): never to free,
 * for nothing has been seen there. Nothing in OM_MODE_COUNT. ISR-safe, O(1).
 */
void grid_om_behind(grid_t *g, grid_cell_t c);

/**
 * OM_MODE_EVIDENCE: free-space evidence along a beam: the log-odds of every cell on the
 * line from the cell of (x0, y0) to the cell of (x1, y1), both included, −= om_miss.
 * The line is walked one cell a step along its longer axis (Bresenham between the cell
 * centres), so it touches max(|Δa|, |Δb|) + 1 cells; it stops where it leaves the grid
 * (the start must be inside). Nothing in OM_MODE_COUNT. ISR-safe.
 * @return the cells lowered
 */
uint32_t grid_om_ray(grid_t *g, int32_t x0_um, int32_t y0_um, int32_t x1_um, int32_t y1_um);

/**
 * One control period spent at a world point: TM of its cell += 1 up to TMmax (Eq. 7).
 * Return values as grid_om_hit(). ISR-safe, O(1).
 */
int grid_tm_visit(grid_t *g, int32_t x_um, int32_t y_um);

/** The array index b·A + a of a cell of a grid. */
static inline uint32_t grid_index(const grid_t *g, grid_cell_t c)
{
    return (uint32_t)c.b * g->a_cells + c.a;
}

/** What the maps say of a cell. */
typedef enum {
    GRID_UNKNOWN = 0, /**< nothing has been seen there */
    GRID_FREE,        /**< known free */
    GRID_OCCUPIED,    /**< OM holds obstacle evidence */
} grid_state_t;

/**
 * What the maps say of a cell, from its OM and TM bytes in a mode. Exploration, the map
 * exports and the scoring all read cells through this one rule. ISR-safe, O(1).
 * - OM_MODE_COUNT: GRID_OCCUPIED when OM >= 1 (the raw map of Eq. 6), else GRID_FREE
 *   when the robot has been there (TM > 0), else GRID_UNKNOWN.
 * - OM_MODE_EVIDENCE: from OM alone (the robot's own cells get free-space evidence at
 *   every reading): GRID_OCCUPIED when the log-odds is > 0, GRID_FREE when < 0, else
 *   GRID_UNKNOWN.
 */
static inline grid_state_t grid_state_of(uint8_t mode, uint8_t om, uint8_t tm)
{
    if (mode == OM_MODE_EVIDENCE) {
        if (om > GRID_EVIDENCE_ZERO) {
            return GRID_OCCUPIED;
        }
        return om < GRID_EVIDENCE_ZERO ? GRID_FREE : GRID_UNKNOWN;
    }
    if (om != 0u) {
        return GRID_OCCUPIED;
    }
    return tm != 0u ? GRID_FREE : GRID_UNKNOWN;
}

/**
 * The largest OM byte grid_state_of() does not call occupied in a mode: a cell is
 * GRID_OCCUPIED exactly when its OM byte is above it, whatever its TM byte. One compare a
 * cell, for the searches that read many (the pose correction's wall lines). ISR-safe.
 */
static inline uint8_t grid_occupied_above(uint8_t mode)
{
    return mode == OM_MODE_EVIDENCE ? (uint8_t)GRID_EVIDENCE_ZERO : 0u;
}

/** grid_state_of() for the cell at an array index of a grid. */
static inline grid_state_t grid_state(const grid_t *g, uint32_t index)
{
    return grid_state_of(g->mode, g->om[index], g->tm[index]);
}

/**
 * The OM byte at and below which post_threshold() frees a cell, for threshold TH in a
 * mode: TH itself in OM_MODE_COUNT, log-odds TH in OM_MODE_EVIDENCE (unknown cells are
 * always at or below it).
 */
static inline uint8_t grid_threshold_byte(uint8_t mode, uint8_t th)
{
    return mode == OM_MODE_EVIDENCE ? (uint8_t)(GRID_EVIDENCE_ZERO + th) : th;
}

#endif /* SLAM_GRID_H */
