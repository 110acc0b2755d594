/* SPDX-License-Identifier: MIT */
/* The exploration's geometry: square roots, and world coordinates in Q16 cells. */
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
