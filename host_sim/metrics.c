/* SPDX-License-Identifier: MIT */
/* Scoring a map against ground truth (DESIGN.md §5) and marking cells near a point. */
#include <math.h>
#include <string.h>

#include "host_sim.h"

/* Whether any cell within Chebyshev distance 1 of (x, y) is non-zero in map. */
static bool near_any(const map_geom_t *g, const uint8_t *map, uint32_t x, uint32_t y)
{
    uint32_t x0 = x > 0u ? x - 1u : 0u;
    uint32_t y0 = y > 0u ? y - 1u : 0u;
    uint32_t x1 = x + 1u < g->a ? x + 1u : x;
    uint32_t y1 = y + 1u < g->b ? y + 1u : y;
    for (uint32_t j = y0; j <= y1; j++) {
        for (uint32_t i = x0; i <= x1; i++) {
            if (map[(size_t)j * g->a + i] != 0u) {
                return true;
            }
        }
    }
    return false;
}

void score_map(const map_geom_t *g, const uint8_t *map, const uint8_t *truth,
               const uint8_t *observable, score_t *out)
{
    score_t s = {0};
    for (uint32_t y = 0; y < g->b; y++) {
        for (uint32_t x = 0; x < g->a; x++) {
            size_t i = (size_t)y * g->a + x;
            if (map[i] != 0u) {
                s.mapped++;
                s.true_pos += near_any(g, truth, x, y);
            }
            if (truth[i] != 0u && observable[i] != 0u) {
                s.observable++;
                s.matched += near_any(g, map, x, y);
            }
        }
    }
    s.precision = s.mapped > 0u ? (double)s.true_pos / s.mapped : 0.0;
    s.recall = s.observable > 0u ? (double)s.matched / s.observable : 0.0;
    s.f1 = s.precision + s.recall > 0.0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall)
                                        : 0.0;
    *out = s;
}

/* Whether cell column i of a row dy away lies in the disc: the one test every cell is held
 * to, so the spans below mark exactly the cells a test of each would. */
static bool in_disc(long i, double fx, double dy, double r)
{
    double dx = (double)i - fx;
    return dx * dx + dy * dy <= r * r;
}

void mark_disc(const map_geom_t *g, uint8_t *marks, double x, double y, double radius_m)
{
    double fx = (x - g->origin_x) / g->cell_m - 0.5; /* in cell-centre units */
    double fy = (y - g->origin_y) / g->cell_m - 0.5;
    double r = radius_m / g->cell_m;
    long x0 = (long)ceil(fx - r);
    long x1 = (long)floor(fx + r);
    long y0 = (long)ceil(fy - r);
    long y1 = (long)floor(fy + r);
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= (long)g->a ? (long)g->a - 1 : x1;
    y1 = y1 >= (long)g->b ? (long)g->b - 1 : y1;
    if (x0 > x1) {
        return;
    }
    /* Along a row the test's left side falls to the column nearest fx and rises beyond it
     * (rounding keeps that order), so the cells in the disc are one span around that
     * column: found from the circle's chord, then each end moved until the test agrees. */
    long c = lround(fx);
    c = c < x0 ? x0 : c > x1 ? x1 : c;
    for (long j = y0; j <= y1; j++) {
        double dy = (double)j - fy;
        if (!in_disc(c, fx, dy, r)) {
            continue; /* the nearest column is out: so is the row */
        }
        double chord = r * r - dy * dy;
        long half = chord > 0.0 ? (long)sqrt(chord) : 0;
        long a = c - half < x0 ? x0 : c - half;
        long b = c + half > x1 ? x1 : c + half;
        while (a > x0 && in_disc(a - 1, fx, dy, r)) {
            a--;
        }
        while (!in_disc(a, fx, dy, r)) {
            a++;
        }
        while (b < x1 && in_disc(b + 1, fx, dy, r)) {
            b++;
        }
        while (!in_disc(b, fx, dy, r)) {
            b--;
        }
        memset(&marks[(size_t)j * g->a + (size_t)a], 1, (size_t)(b - a + 1));
    }
}
