/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A map as an image file: binary PGM (P5), with a ROS map_server YAML beside it when it is
 * a map to load.
 *
 * The image comes made: hal_common/mapexport.h turns a grid into the one trinary meaning
 * every program exports (and TM into a count image with no YAML), first row the grid's
 * last. Both files are written atomically (store_write_file()).
 */
#ifndef LHAL_MAPFILE_H
#define LHAL_MAPFILE_H

#include <stdbool.h>
#include <stdint.h>

/** Where the grid lies in the world. */
typedef struct {
    uint32_t cell_um;    /**< side of a cell */
    int32_t origin_x_um; /**< world x of the lower-left corner of cell (0, 0) */
    int32_t origin_y_um; /**< world y of the lower-left corner of cell (0, 0) */
} mapfile_geometry_t;

/**
 * Write DIR/NAME.pgm and, when @p yaml, DIR/NAME.yaml (mapx_yaml()).
 * @param img  w·h bytes, first row the northern one
 * @return 0, or -errno of the first file that could not be written
 */
int mapfile_write(const char *dir, const char *name, const uint8_t *img, uint32_t w, uint32_t h,
                  bool yaml, const mapfile_geometry_t *geo);

#endif /* LHAL_MAPFILE_H */
