/* SPDX-License-Identifier: MIT */
/* The pose correction's held-back hits: held as odometry points, entering OM in two halves,
 * flushed before a map is exported, and the obstacle ahead among them. */
#include "loc_hold.h"

#include "loc_filter.h"
#include "loc_walls.h"

void loc_hold_init(loc_hold_t *h, const slam_config_t *cfg)
{
    *h = (loc_hold_t){0};
    /* LOC_REACH_CELLS within 2^15 units, the same for every grid up to 256 cells a side (the
     * host's grid and the MCU's then hold a point alike): 1 mm for 50 mm cells. A longer
     * side doubles the reach until it is twice that side, 4 mm for 1024 cells. Cells of
     * 5 mm to 1 m make the reach 2^16 µm or more, and slam_config_check()'s 1 km over the
     * capacity's side keeps it within 32 bits. */
    uint32_t side = grid_cells_a(cfg) > grid_cells_b(cfg) ? grid_cells_a(cfg) : grid_cells_b(cfg);
    uint32_t reach = LOC_REACH_CELLS;
    while (reach < 2u * side) {
        reach *= 2u;
    }
    h->point_shift = (uint8_t)(17 - __builtin_clz(reach * cfg->cell_um));
    h->placed.c = FIX_Q30_ONE; /* no correction: cos 0 is one, the rest is zero */
    h->clear_um = (int32_t)cfg->clearance_um;
}

/* Held-back hit i in the odometry frame, µm. */
static void hold_odom(const loc_hold_t *h, const grid_t *g, unsigned i, int32_t *ox, int32_t *oy)
{
    const loc_point_t *p = &h->win[(h->first + i) % LOC_HOLD];
    /* Modulo 2^32 as grid.c's cells: the point came from an int32_t within the reach. */
    unsigned k = h->point_shift;
    *ox = (int32_t)((uint32_t)g->origin_x_um + ((uint32_t)(int32_t)p->x << k));
    *oy = (int32_t)((uint32_t)g->origin_y_um + ((uint32_t)(int32_t)p->y << k));
}

void loc_hold_point(const loc_hold_t *h, const grid_t *g, const loc_corr_t *c, unsigned i,
                    int32_t *x, int32_t *y)
{
    int32_t ox;
    int32_t oy;
    hold_odom(h, g, i, &ox, &oy);
    loc_corr_point(c, ox, oy, x, y);
}

/* Whether held-back hit i goes into OM at all: not when it lay just behind a wall. */
static bool held_mapped(const loc_hold_t *h, unsigned i)
{
    unsigned slot = (h->first + i) % LOC_HOLD;
    return ((h->shadowed[slot / 32u] >> (slot % 32u)) & 1u) == 0u;
}

/* A point of the odometry frame as a loc_point_t, rounded to its unit; false when it lies
 * beyond a loc_point_t's reach (a grid's length and more off the grid). */
static bool to_point(const loc_hold_t *h, const grid_t *g, int32_t x, int32_t y, loc_point_t *p)
{
    /* The differences modulo 2^32, as grid.c's: points and origin lie within 1 km. Halved
     * last, so that the rounding cannot overflow. */
    unsigned half = h->point_shift - 1u;
    int32_t u = (((int32_t)((uint32_t)x - (uint32_t)g->origin_x_um) >> half) + 1) >> 1;
    int32_t v = (((int32_t)((uint32_t)y - (uint32_t)g->origin_y_um) >> half) + 1) >> 1;
    if ((((uint32_t)u + 32768u) | ((uint32_t)v + 32768u)) > UINT16_MAX) {
        return false; /* one of them outside int16_t */
    }
    *p = (loc_point_t){(int16_t)u, (int16_t)v};
    return true;
}

/* The first half of a hit's log-odds step, placed when it leaves the window (half of one
 * in OM_MODE_COUNT is none). */
static uint8_t early_half(const loc_hold_t *h, const grid_t *g, unsigned i)
{
    return i + LOC_WINDOW < h->count && g->mode == OM_MODE_EVIDENCE ? g->hit / 2u : 0u;
}

void loc_hold_halves(loc_hold_t *h, grid_t *g, const loc_corr_t *corr, bool take_back)
{
    if (!take_back) {
        h->placed = *corr;
    }
    if (g->mode != OM_MODE_EVIDENCE) {
        return; /* no halves */
    }
    const uint8_t half = early_half(h, g, 0u); /* every hit here is past the window */
    for (unsigned i = 0; i + LOC_WINDOW < h->count; i++) {
        if (held_mapped(h, i)) {
            int32_t x;
            int32_t y;
            loc_hold_point(h, g, &h->placed, i, &x, &y);
            grid_om_part(g, x, y, half, take_back);
        }
    }
}

/* The oldest held-back hit leaves the hold: the rest of it enters OM, at the correction now
 * (its half stays where it lies). */
static void hit_enters_map(loc_hold_t *h, mapper_t *m, grid_t *g, const loc_corr_t *corr)
{
    if (held_mapped(h, 0u)) {
        int32_t x;
        int32_t y;
        loc_hold_point(h, g, corr, 0u, &x, &y);
        (void)mapper_hit_rest(m, g, x, y, early_half(h, g, 0u));
    }
    h->first = (uint16_t)((h->first + 1u) % LOC_HOLD);
    h->count--;
}

bool loc_hold_add(loc_hold_t *h, mapper_t *m, grid_t *g, const loc_corr_t *corr, int32_t x,
                  int32_t y, bool shadowed)
{
    loc_point_t pt;
    if (!to_point(h, g, x, y, &pt)) {
        loc_count(&m->outside); /* a grid's length off the grid: nothing to match or map */
        return false;
    }
    if (h->count == LOC_HOLD) {
        hit_enters_map(h, m, g, corr);
    }
    unsigned slot = (h->first + h->count) % LOC_HOLD;
    h->win[slot] = pt;
    uint32_t *word = &h->shadowed[slot / 32u];
    *word = (*word & ~(1u << (slot % 32u))) | ((uint32_t)shadowed << (slot % 32u));
    h->count++;
    /* The hit that just left the window: half of it enters OM now, with the other halves,
     * so that what exploration reads in OM holds the walls just seen; the rest enters
     * when it leaves the hold, where the correction then puts it. */
    unsigned left = h->count - LOC_WINDOW - 1u; /* (wraps when none has left yet) */
    if (h->count > LOC_WINDOW && held_mapped(h, left)) {
        loc_hold_point(h, g, &h->placed, left, &x, &y);
        grid_om_part(g, x, y, early_half(h, g, left), false);
    }
    return true;
}

void loc_hold_flush(loc_hold_t *h, mapper_t *m, grid_t *g, const loc_corr_t *corr)
{
    while (h->count > 0u) {
        hit_enters_map(h, m, g, corr);
    }
}

/*
 * The square of a distance from the ping, in the odometry frame, beyond which a hit lies
 * outside the corridor ahead in the map frame too, so that most hits (nine in ten) are
 * left out before the correction is applied to them. In the corridor, 0 < ahead < reach
 * and |side| < clear, and ahead and side are the floors of the map-frame offset d turned
 * by (cos, sin) of the heading, whose length ρ is 1 within ε = √2·FIX_SIN_MAX_ERR_Q30 /
 * 2^30: so ρ·|d| < B = √((reach + 1)² + (clear + 1)²). And d is the odometry offset d_o
 * turned by the correction's (c, s), of length 1 within ε too, give or take the rounding
 * of both points (< 1.5 µm): |d_o| < (B + 1.5) / (1 − ε)² <= (B + 1.5)(1 + 3ε). For ε <=
 * 2^-13 its square stays below B² + B²/1024 (B >= reach: the linear terms fit in the
 * rest), and 2^20 µm² more is for good measure.
 */
_Static_assert(FIX_SIN_MAX_ERR_Q30 <= 92000, "sqrt(2) times the sine's error within 2^-13");
static int64_t corridor_far2(int32_t clear_um)
{
    int64_t b2 = (int64_t)(LOC_AHEAD_REACH_UM + 1) * (LOC_AHEAD_REACH_UM + 1) +
                 (int64_t)(clear_um + 1) * (clear_um + 1);
    return b2 + (b2 >> 10) + (1 << 20);
}

void loc_hold_ahead(const loc_hold_t *h, const grid_t *g, const loc_corr_t *corr,
                    const odom_pose_t *ping, int32_t pt[2])
{
    odom_pose_t at = loc_apply(corr, ping);
    const fix_frame_t frame = {at.x_um, at.y_um, fix_cos(at.heading), fix_sin(at.heading)};
    const int64_t far2 = corridor_far2(h->clear_um);
    /* A hit's offset from the ping in the odometry frame is its point (hold_odom()) from
     * the grid's origin, plus the origin's offset from the ping. Differences modulo 2^32,
     * exact within the 1 km world slam_config_check() allows; their products with Q30
     * values fit 64 bits. */
    const uint32_t bx = (uint32_t)g->origin_x_um - (uint32_t)ping->x_um;
    const uint32_t by = (uint32_t)g->origin_y_um - (uint32_t)ping->y_um;
    const unsigned k = h->point_shift;
    /* The nearest hit (its cell k1) and the nearest in any other cell, ahead of the axle. */
    int32_t near[2] = {INT32_MAX, INT32_MAX};
    int32_t near_pt[2][2] = {{LOC_AHEAD_NONE, 0}, {LOC_AHEAD_NONE, 0}};
    uint32_t k1 = UINT32_MAX;
    unsigned first = h->count > LOC_WINDOW ? h->count - LOC_WINDOW : 0u;
    for (unsigned i = first; i < h->count; i++) {
        unsigned slot = (h->first + i) % LOC_HOLD;
        if (((h->shadowed[slot / 32u] >> (slot % 32u)) & 1u) != 0u) {
            continue; /* not mapped (held_mapped()) */
        }
        const loc_point_t *p = &h->win[slot];
        int64_t dxo = (int32_t)(bx + ((uint32_t)(int32_t)p->x << k));
        int64_t dyo = (int32_t)(by + ((uint32_t)(int32_t)p->y << k));
        if (dxo * dxo + dyo * dyo >= far2) {
            continue;
        }
        int32_t ox;
        int32_t oy;
        hold_odom(h, g, i, &ox, &oy);
        int32_t x;
        int32_t y;
        uint32_t cell;
        loc_corr_point(corr, ox, oy, &x, &y);
        int32_t side;
        int32_t ahead = fix_frame_point(&frame, x, y, &side);
        /* The corridor first, the map after: most hits lie outside it, and a hit at or
         * beyond the second nearest is out whatever its cell (near[0] <= near[1]). */
        if (ahead <= 0 || ahead >= LOC_AHEAD_REACH_UM || side <= -h->clear_um ||
            side >= h->clear_um || ahead >= near[1] || loc_known_free(g, x, y, &cell) ||
            (cell == k1 && ahead >= near[0])) {
            continue;
        }
        if (ahead < near[0]) {
            if (cell != k1) {
                near[1] = near[0];
                near_pt[1][0] = near_pt[0][0];
                near_pt[1][1] = near_pt[0][1];
            }
            k1 = cell;
            near[0] = ahead;
            near_pt[0][0] = x;
            near_pt[0][1] = y;
        } else {
            near[1] = ahead;
            near_pt[1][0] = x;
            near_pt[1][1] = y;
        }
    }
    pt[0] = near_pt[1][0];
    pt[1] = near_pt[1][1];
}
