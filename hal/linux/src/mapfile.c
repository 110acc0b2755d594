/* SPDX-License-Identifier: MIT */
/* Map grids as PGM images with ROS map_server YAML, written atomically. */
#include "lhal/mapfile.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lhal/store.h"

/* Micrometres as metres with six decimals, without floating point. */
static void mapfile_metres(char *buf, size_t n, int32_t um)
{
    uint32_t mag = um < 0 ? (uint32_t)(-(int64_t)um) : (uint32_t)um;
    snprintf(buf, n, "%s%u.%06u", um < 0 ? "-" : "", (unsigned)(mag / 1000000u),
             (unsigned)(mag % 1000000u));
}

int mapfile_write(const char *dir, const char *name, const uint8_t *cells, uint32_t w,
                  uint32_t h, uint8_t max, const mapfile_geometry_t *geo)
{
    char header[64];
    int hlen = snprintf(header, sizeof header, "P5\n%u %u\n255\n", (unsigned)w, (unsigned)h);
    size_t npix = (size_t)w * h;
    uint8_t *img = malloc((size_t)hlen + npix);
    if (img == NULL) {
        return -ENOMEM;
    }
    memcpy(img, header, (size_t)hlen);
    uint8_t *px = img + hlen;
    for (uint32_t row = 0u; row < h; row++) {
        const uint8_t *src = cells + (size_t)(h - 1u - row) * w;
        for (uint32_t a = 0u; a < w; a++) {
            uint32_t v = src[a] < max ? src[a] : max;
            px[(size_t)row * w + a] = (uint8_t)(255u - v * 255u / max);
        }
    }
    char file[96];
    snprintf(file, sizeof file, "%s.pgm", name);
    int rc = store_write_file(dir, file, img, (size_t)hlen + npix);
    free(img);
    if (rc != 0) {
        return rc;
    }

    char res[24];
    char ox[24];
    char oy[24];
    mapfile_metres(res, sizeof res, (int32_t)geo->cell_um);
    mapfile_metres(ox, sizeof ox, geo->origin_x_um);
    mapfile_metres(oy, sizeof oy, geo->origin_y_um);
    char yaml[320];
    int ylen = snprintf(yaml, sizeof yaml,
                        "image: %s.pgm\nresolution: %s\norigin: [%s, %s, 0.0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
                        name, res, ox, oy);
    snprintf(file, sizeof file, "%s.yaml", name);
    return store_write_file(dir, file, yaml, (size_t)ylen);
}
