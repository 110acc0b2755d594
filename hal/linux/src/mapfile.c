/* SPDX-License-Identifier: MIT */
/* Map images as PGM files with ROS map_server YAML, written atomically. */
#include "lhal/mapfile.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/mapexport.h"
#include "lhal/store.h"

int mapfile_write(const char *dir, const char *name, const uint8_t *img, uint32_t w, uint32_t h,
                  bool yaml, const mapfile_geometry_t *geo)
{
    char header[64];
    int hlen = snprintf(header, sizeof header, "P5\n%u %u\n255\n", (unsigned)w, (unsigned)h);
    size_t npix = (size_t)w * h;
    uint8_t *file_bytes = malloc((size_t)hlen + npix);
    if (file_bytes == NULL) {
        return -ENOMEM;
    }
    memcpy(file_bytes, header, (size_t)hlen);
    memcpy(file_bytes + hlen, img, npix);
    char file[96];
    snprintf(file, sizeof file, "%s.pgm", name);
    int rc = store_write_file(dir, file, file_bytes, (size_t)hlen + npix);
    free(file_bytes);
    if (rc != 0 || !yaml) {
        return rc;
    }
    char text[320];
    int len = mapx_yaml(text, sizeof text, file, geo->cell_um, geo->origin_x_um, geo->origin_y_um);
    if (len < 0) {
        return -ENAMETOOLONG;
    }
    snprintf(file, sizeof file, "%s.yaml", name);
    return store_write_file(dir, file, text, (size_t)len);
}
