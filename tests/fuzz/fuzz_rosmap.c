/* SPDX-License-Identifier: MIT */
/*
 * Fuzz target: the ROS map loader (a map_server YAML and the PGM it names), with or without
 * a crop. Input: the YAML's length (2 bytes, little-endian), a crop byte (0: none), four
 * signed crop bytes (x, y, w, h in tenths of a metre), then the YAML, then the image.
 */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "host/sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 7u) {
        return 0;
    }
    size_t ylen = (size_t)data[0] | (size_t)data[1] << 8;
    ylen = ylen > size - 7u ? size - 7u : ylen;
    room_crop_t crop = {(int8_t)data[3] * 0.1, (int8_t)data[4] * 0.1, (int8_t)data[5] * 0.1,
                        (int8_t)data[6] * 0.1};
    const char *yaml = (const char *)data + 7;
    const char *pgm = yaml + ylen;
    size_t plen = size - 7u - ylen;
    room_t r;
    char err[512] = "";
    if (room_parse_ros(&r, "fuzz.yaml", yaml, ylen, "fuzz.pgm", pgm, plen,
                       data[2] != 0u ? &crop : NULL, err, sizeof err) != 0) {
        FUZZ_CHECK(strncmp(err, "fuzz.", 5) == 0); /* the YAML or the image is named */
        return 0;
    }
    FUZZ_CHECK(r.occ != NULL && r.occ_w > 0u && r.occ_h > 0u && r.occ_res > 0.0);
    size_t occupied = 0;
    for (size_t i = 0; i < (size_t)r.occ_w * r.occ_h; i++) {
        FUZZ_CHECK(r.occ[i] <= 1u && !(r.occ[i] && r.occ_free[i]));
        occupied += r.occ[i];
    }
    FUZZ_CHECK(occupied > 0u);
    FUZZ_CHECK(r.min_x <= r.max_x && r.min_y <= r.max_y);
    double x;
    double y;
    double th;
    if (room_find_start(&r, 0.1, &x, &y, &th) == 0) {
        FUZZ_CHECK(room_disc_free(&r, x, y, 0.1) && room_encloses(&r, x, y, NULL));
    }
    double cx = 0.5 * (r.min_x + r.max_x);
    double cy = 0.5 * (r.min_y + r.max_y);
    for (int k = 0; k < 8; k++) {
        double c = 0.0;
        double d = room_ray(&r, cx, cy, k * 0.785398163397448, 20.0, &c);
        FUZZ_CHECK(d >= 0.0 && (d > 20.0 || (c >= 0.0 && c <= 1.0 + 1e-9)));
        FUZZ_CHECK(room_clearance(&r, cx + k, cy, 0.5) >= 0.0);
    }
    static uint8_t truth[48 * 48];
    room_rasterize(&r, r.min_x, r.min_y, fmax(0.01, (r.max_x - r.min_x) / 40.0), 48u, 48u, truth);
    room_free(&r);
    return 0;
}
