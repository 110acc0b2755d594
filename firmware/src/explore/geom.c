/* SPDX-License-Identifier: MIT */
/* The exploration's geometry: square roots, world coordinates in Q16 cells, a straight walk
 * between two cells. */
#include "base.h"

uint32_t explore_isqrt(uint32_t v)
{
    uint32_t r = 0u;
    for (uint32_t b = 1u << 15; b != 0u; b >>= 1) {
        if ((r + b) * (r + b) <= v) {
            r += b;
        }
    }
    return r;
}

explore_ray_t explore_ray_between(uint32_t a0, uint32_t b0, uint32_t a1, uint32_t b1)
{
    int32_t dx = (int32_t)a1 - (int32_t)a0;
    int32_t dy = (int32_t)b1 - (int32_t)b0;
    uint32_t len = explore_isqrt((uint32_t)(dx * dx + dy * dy));
    len = len < 1u ? 1u : len;
    return (explore_ray_t){
        .fx = ((int32_t)a0 << 16) + 0x8000,
        .fy = ((int32_t)b0 << 16) + 0x8000,
        .dx = (dx * 65536) / (int32_t)len,
        .dy = (dy * 65536) / (int32_t)len,
        .left = len,
    };
}

int32_t explore_q16_cells(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t n)
{
    int64_t d = (int64_t)v_um - origin_um;
    if (d < 0 || d >= (int64_t)cell_um * n) {
        return -1;
    }
    uint32_t u = (uint32_t)d;
    uint32_t whole = u / cell_um;
    uint32_t frac = ((u - whole * cell_um) << 8) / cell_um;
    return (int32_t)((whole << 16) | (frac << 8));
}
