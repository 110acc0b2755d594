/* SPDX-License-Identifier: MIT */
/* Exported maps: trinary map_server images, TM as counts, and their YAML. */
#include "hal_common/mapexport.h"

#include <stdio.h>

#include "slam/grid.h"

void mapx_trinary(uint8_t mode, const uint8_t *om, const uint8_t *tm, const uint8_t *occ,
                  uint32_t w, uint32_t h, uint8_t *img)
{
    for (uint32_t row = 0; row < h; row++) {
        size_t src = (size_t)(h - 1u - row) * w;
        uint8_t *dst = img + (size_t)row * w;
        for (uint32_t a = 0; a < w; a++) {
            size_t i = src + a;
            grid_state_t s = GRID_FREE;
            if (om != NULL) {
                s = grid_state_of(mode, om[i], tm != NULL ? tm[i] : 0u);
            }
            if (occ != NULL) {
                s = occ[i] != 0u ? GRID_OCCUPIED : s == GRID_UNKNOWN ? GRID_UNKNOWN : GRID_FREE;
            }
            dst[a] = (uint8_t)(s == GRID_OCCUPIED ? MAPX_OCCUPIED
                               : s == GRID_FREE   ? MAPX_FREE
                                                  : MAPX_UNKNOWN);
        }
    }
}

void mapx_counts(const uint8_t *cells, uint8_t max, uint32_t w, uint32_t h, uint8_t *img)
{
    uint32_t m = max != 0u ? max : 1u;
    for (uint32_t row = 0; row < h; row++) {
        const uint8_t *src = cells + (size_t)(h - 1u - row) * w;
        for (uint32_t a = 0; a < w; a++) {
            uint32_t v = src[a] < m ? src[a] : m;
            img[(size_t)row * w + a] = (uint8_t)(255u - (v * 255u + m / 2u) / m);
        }
    }
}

/* Whole µm as metres with six decimals. */
static void metres(char *buf, size_t n, int64_t um)
{
    uint64_t mag = um < 0 ? (uint64_t)(-um) : (uint64_t)um;
    snprintf(buf, n, "%s%llu.%06llu", um < 0 ? "-" : "", (unsigned long long)(mag / 1000000u),
             (unsigned long long)(mag % 1000000u));
}

int mapx_yaml(char *buf, size_t n, const char *image, uint32_t cell_um, int32_t origin_x_um,
              int32_t origin_y_um)
{
    char res[32];
    char ox[32];
    char oy[32];
    metres(res, sizeof res, cell_um);
    metres(ox, sizeof ox, origin_x_um);
    metres(oy, sizeof oy, origin_y_um);
    int len = snprintf(buf, n,
                       "image: %s\nmode: trinary\nresolution: %s\norigin: [%s, %s, 0.0]\n"
                       "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
                       image, res, ox, oy);
    return len < 0 || (size_t)len >= n ? -1 : len;
}
