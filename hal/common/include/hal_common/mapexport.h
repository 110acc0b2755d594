/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The one meaning of an exported map, for every program that writes one (host_sim,
 * sonarslam-linux) and every tool that reads one: a ROS map_server image in trinary mode.
 *
 *   MAPX_OCCUPIED (0, black)     obstacle evidence
 *   MAPX_FREE (254, white)       known free: a beam passed, or the robot stood there
 *   MAPX_UNKNOWN (205, grey)     never seen
 *
 * With map_server's rule p = (255 − v) / 255 and the thresholds of mapx_yaml()
 * (occupied above 0.65, free below 0.196) these load as occupied, free and unknown. The
 * image's first row is the grid's last (largest y), as map_server expects. What a cell is
 * comes from grid_state_of(): the map's own rule, in either OM mode.
 *
 * The trajectory map is exported by mapx_counts() as a plain grey image of visit counts,
 * with no YAML: no map loader should read where the robot drove as obstacles.
 *
 * Arrays are the grid's: w×h cells, index b·w + a. No grid_t crosses this interface, so
 * it serves a core built with any grid size.
 */
#ifndef HAL_COMMON_MAPEXPORT_H
#define HAL_COMMON_MAPEXPORT_H

#include <stddef.h>
#include <stdint.h>

#define MAPX_OCCUPIED 0u
#define MAPX_FREE 254u
#define MAPX_UNKNOWN 205u

/**
 * The trinary image of a map.
 * @param mode    the OM mode (an om_mode_t)
 * @param om, tm  the grid's maps; tm may be NULL (no cell is then free for having been
 *                visited, which matters only in OM_MODE_COUNT)
 * @param occ     NULL: cells are what grid_state_of() says of om and tm. Otherwise a
 *                post-processed or ground-truth map: a cell is occupied where occ is
 *                non-zero, and elsewhere free if om and tm know it, else unknown; with
 *                om NULL too, every cell occ does not mark is free (ground truth)
 * @param img     out: w·h bytes, first row the grid's last
 */
void mapx_trinary(uint8_t mode, const uint8_t *om, const uint8_t *tm, const uint8_t *occ,
                  uint32_t w, uint32_t h, uint8_t *img);

/**
 * A grey image of counts: 255 for 0, down to 0 for @p max and above, rounded; first row
 * the grid's last. For TM, which is not a map to load.
 */
void mapx_counts(const uint8_t *cells, uint8_t max, uint32_t w, uint32_t h, uint8_t *img);

/**
 * The map_server YAML of a trinary image, in text that never depends on the locale or
 * the floating-point library (positions in whole µm, printed as metres).
 * @param image   the image's file name, as the YAML names it
 * @param cell_um, origin_x_um, origin_y_um  the grid's geometry
 * @return the length written (less than n), or -1 when it does not fit
 */
int mapx_yaml(char *buf, size_t n, const char *image, uint32_t cell_um, int32_t origin_x_um,
              int32_t origin_y_um);

#endif /* HAL_COMMON_MAPEXPORT_H */
