/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A map grid as an image file: binary PGM (P5) with a ROS map_server YAML beside it.
 *
 * Cells are row-major w×h (index b·w + a, b growing with world y), as grid_t stores them.
 * The image puts world +y up, so its first row is the grid's last. A cell's value v
 * (saturated at max) becomes the grey level 255 − v·255/max: empty cells are white,
 * saturated ones black, which is how map_server reads an occupancy image (negate 0).
 * Both files are written atomically (store_write_file()).
 */
#ifndef LHAL_MAPFILE_H
#define LHAL_MAPFILE_H

#include <stdint.h>

/** Where the grid lies in the world. */
typedef struct {
    uint32_t cell_um;    /**< side of a cell */
    int32_t origin_x_um; /**< world x of the lower-left corner of cell (0, 0) */
    int32_t origin_y_um; /**< world y of the lower-left corner of cell (0, 0) */
} mapfile_geometry_t;

/**
 * Write DIR/NAME.pgm and DIR/NAME.yaml.
 * @param max  the value drawn black, > 0
 * @return 0, or -errno of the first file that could not be written
 */
int mapfile_write(const char *dir, const char *name, const uint8_t *cells, uint32_t w,
                  uint32_t h, uint8_t max, const mapfile_geometry_t *geo);

#endif /* LHAL_MAPFILE_H */
