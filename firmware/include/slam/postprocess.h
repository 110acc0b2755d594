/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Offline post-processing of the obstacle map (paper §II.D), on a copy.
 *
 * The chain, each step reading the result of the one before:
 *   1. threshold: a cell with OM <= TH becomes 0 (no obstacle), any other becomes OMmax;
 *   2. template: an occupied cell with fewer than K occupied 8-neighbours becomes free
 *      (isolated cells come mostly from bad readings);
 *   3. insert: a free cell whose two opposite neighbours are both occupied, in any of the
 *      four orientations W-E, S-N, SW-NE, SE-NW, becomes occupied (gap filling).
 *
 * Maps are row-major w×h arrays of `uint8_t` (index y·w + x), as grid_t stores them;
 * a cell is occupied when it is non-zero. Neighbours beyond the border count as free.
 * Template and insert decide every cell from the map as it was before the step, yet work
 * in place: they keep two rows of the old map in a caller-owned scratch of 2·w bytes.
 * The work is proportional to the map: run it in robot_idle() or on the host, never in
 * the tick.
 */
#ifndef SLAM_POSTPROCESS_H
#define SLAM_POSTPROCESS_H

#include <stddef.h>
#include <stdint.h>

#include "slam/error.h"

/** Parameters of the chain. */
typedef struct {
    uint8_t threshold; /**< the OM byte at and below which a cell is free: TH in
                            OM_MODE_COUNT; grid_threshold_byte() gives it in any mode */
    uint8_t om_max;    /**< value of an occupied cell after thresholding */
    uint8_t k;         /**< template: minimum occupied 8-neighbours to stay occupied, 0..8
                            (0: the template changes nothing) */
    uint8_t insert;    /**< 1: run the insert step; 0: skip it */
} post_params_t;

/** Step 1 in place: OM <= TH becomes 0, anything else om_max. */
void post_threshold(uint8_t *map, size_t w, size_t h, uint8_t threshold, uint8_t om_max);

/**
 * Step 2 in place: occupied cells with fewer than k occupied 8-neighbours become 0.
 * @param scratch  2·w bytes owned by the caller
 */
void post_template(uint8_t *map, size_t w, size_t h, uint8_t k, uint8_t *scratch);

/**
 * Step 3 in place: free cells between two occupied opposite neighbours become om_max.
 * @param scratch  2·w bytes owned by the caller
 */
void post_insert(uint8_t *map, size_t w, size_t h, uint8_t om_max, uint8_t *scratch);

/**
 * The whole chain on a copy: out = insert(template(threshold(om))), insert only when
 * p->insert is set.
 * @param om       the live obstacle map, w·h cells; only read
 * @param out      w·h cells, the result (may not overlap om)
 * @param scratch  2·w bytes owned by the caller
 * @retval SLAM_OK      done
 * @retval SLAM_EINVAL  k > 8, insert > 1, a zero size, or om_max == 0; out is untouched
 */
int post_run(const uint8_t *om, uint8_t *out, size_t w, size_t h, const post_params_t *p,
             uint8_t *scratch);

#endif /* SLAM_POSTPROCESS_H */
