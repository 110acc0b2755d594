/* SPDX-License-Identifier: MIT */
/* What the robot could have mapped: wall cells its pings covered, and its closest approach. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "host_sim.h"

static const double PI = HOST_SIM_PI;
static const double wall_marks[3] = {0.5, 0.8, 0.9};

/*
 * The wall cells a robot could map from where it can go: truth cells that face the open
 * space around the start (4-adjacent to a non-truth cell reached from the start cell
 * through non-truth cells, whatever the robot's size: a wall behind a cabinet that stands
 * against it faces none) and whose centre lies within rc of the centre of a cell the
 * robot's centre can reach.
 */
int walls_init(run_t *r, const room_t *room, const sim_params_t *p, double rc_m, uint32_t start)
{
    const map_geom_t *g = &r->geom;
    size_t n = (size_t)g->a * g->b;
    uint8_t *open = calloc(n, 1u);
    uint32_t *queue = malloc(n * sizeof *queue);
    if (open == NULL || queue == NULL) {
        free(open);
        free(queue);
        return -1;
    }
    size_t head = 0;
    size_t tail = 0;
    open[start] = 1u;
    queue[tail++] = start;
    while (head < tail) {
        uint32_t c = queue[head++];
        uint32_t x = c % g->a;
        uint32_t y = c / g->a;
        uint32_t nb[4] = {x > 0u ? c - 1u : c, x + 1u < g->a ? c + 1u : c, y > 0u ? c - g->a : c,
                          y + 1u < g->b ? c + g->a : c};
        for (int k = 0; k < 4; k++) {
            if (!open[nb[k]] && !r->truth[nb[k]]) {
                open[nb[k]] = 1u;
                queue[tail++] = nb[k];
            }
        }
    }
    /* Reach of rc from a reachable cell, in cells: a square of offsets tested once. */
    long reach = (long)floor(rc_m / g->cell_m);
    for (uint32_t y = 0; y < g->b; y++) {
        for (uint32_t x = 0; x < g->a; x++) {
            size_t i = (size_t)y * g->a + x;
            if (!r->truth[i]) {
                continue;
            }
            bool faces = (x > 0u && open[i - 1u]) || (x + 1u < g->a && open[i + 1u]) ||
                         (y > 0u && open[i - g->a]) || (y + 1u < g->b && open[i + g->a]);
            bool near = false;
            for (long dy = -reach; faces && !near && dy <= reach; dy++) {
                long yy = (long)y + dy;
                if (yy < 0 || yy >= (long)g->b) {
                    continue;
                }
                for (long dx = -reach; dx <= reach; dx++) {
                    long xx = (long)x + dx;
                    if (xx >= 0 && xx < (long)g->a &&
                        r->reachable[(size_t)yy * g->a + (size_t)xx] &&
                        (double)(dx * dx + dy * dy) * g->cell_m * g->cell_m <= rc_m * rc_m) {
                        near = true;
                        break;
                    }
                }
            }
            if (faces && near) {
                r->wall_left[i >> 6] |= 1ull << (i & 63u);
                r->wall_cells++;
            }
        }
    }
    free(open);
    free(queue);
    r->room = room;
    r->rc_m = rc_m;
    r->half_cone = 0.5 * p->sonar_cone_deg * PI / 180.0;
    r->body_m = p->body_radius_m;
    r->wall_time_to[0] = r->wall_time_to[1] = r->wall_time_to[2] = -1.0;
    r->min_clearance = HUGE_VAL;
    r->clear_at = -1.0;
    r->touch_t = -1.0;
    return 0;
}

/* The cell bounds of the ping's sector: its apex and the arc's ends, middle and any
 * axis extreme between them. */
static void sector_bounds(const run_t *r, double sx, double sy, double bearing, long b[4])
{
    double lo_x = sx;
    double hi_x = sx;
    double lo_y = sy;
    double hi_y = sy;
    double h = r->half_cone;
    for (int k = 0; k < 7; k++) {
        double a;
        if (k < 3) {
            a = bearing + (double)(k - 1) * h;
        } else {
            /* An axis direction, when the arc reaches it. */
            a = (double)(k - 3) * PI / 2.0;
            if (fabs(remainder(a - bearing, 2.0 * PI)) > h) {
                continue;
            }
        }
        double x = sx + r->rc_m * cos(a);
        double y = sy + r->rc_m * sin(a);
        lo_x = fmin(lo_x, x);
        hi_x = fmax(hi_x, x);
        lo_y = fmin(lo_y, y);
        hi_y = fmax(hi_y, y);
    }
    const map_geom_t *g = &r->geom;
    b[0] = (long)floor((lo_x - g->origin_x) / g->cell_m);
    b[1] = (long)floor((hi_x - g->origin_x) / g->cell_m);
    b[2] = (long)floor((lo_y - g->origin_y) / g->cell_m);
    b[3] = (long)floor((hi_y - g->origin_y) / g->cell_m);
    b[0] = b[0] < 0 ? 0 : b[0];
    b[2] = b[2] < 0 ? 0 : b[2];
    b[1] = b[1] >= (long)g->a ? (long)g->a - 1 : b[1];
    b[3] = b[3] >= (long)g->b ? (long)g->b - 1 : b[3];
}

/*
 * One ping's confidence sector, from the true sensor position along the true beam axis:
 * a wall cell is covered when its centre lies closer than rc to the sensor, within the
 * beam's half-angle of its axis, and in sight (the first surface along the line to it is
 * no nearer than a cell short of its centre).
 */
void walls_ping(run_t *r, double sx, double sy, double bearing, double t)
{
    if (r->wall_cells == 0u || r->walls_covered == r->wall_cells) {
        return;
    }
    const map_geom_t *g = &r->geom;
    long b[4];
    sector_bounds(r, sx, sy, bearing, b);
    double cos_half = cos(r->half_cone);
    if (b[1] < b[0]) {
        return; /* the sector lies beside the grid */
    }
    for (long y = b[2]; y <= b[3]; y++) {
        /* The row's cells b[0]..b[1] in ascending order, 64 at a time, only those left. */
        size_t lo = (size_t)y * g->a + (size_t)b[0];
        size_t hi = (size_t)y * g->a + (size_t)b[1];
        for (size_t w = lo >> 6; w <= hi >> 6; w++) {
            uint64_t bits = r->wall_left[w];
            if (w == lo >> 6) {
                bits &= ~0ull << (lo & 63u);
            }
            if (w == hi >> 6) {
                bits &= ~0ull >> (63u - (hi & 63u));
            }
            for (; bits != 0u; bits &= bits - 1u) {
                size_t i = (w << 6) + (size_t)__builtin_ctzll(bits);
                long x = (long)(i - (size_t)y * g->a);
                double dx = g->origin_x + ((double)x + 0.5) * g->cell_m - sx;
                double dy = g->origin_y + ((double)y + 0.5) * g->cell_m - sy;
                double d = hypot(dx, dy);
                if (d >= r->rc_m ||
                    (d > 0.0 && (dx * cos(bearing) + dy * sin(bearing)) < d * cos_half)) {
                    continue;
                }
                if (d > g->cell_m &&
                    room_ray(r->room, sx, sy, atan2(dy, dx), d, NULL) < d - g->cell_m) {
                    continue;
                }
                r->wall_left[i >> 6] &= ~(1ull << (i & 63u));
                r->walls_covered++;
            }
        }
    }
    for (int k = 0; k < 3; k++) {
        if (r->wall_time_to[k] < 0.0 && r->walls_covered >= wall_marks[k] * r->wall_cells) {
            r->wall_time_to[k] = t;
        }
    }
}

/*
 * The smallest gap between the body and an obstacle so far. The gap shrinks no faster
 * than the robot moves, so the world is asked again only when the robot has come far
 * enough from where it last asked to possibly set a new smallest gap.
 */
void clearance_tick(run_t *r, double x, double y)
{
    if (r->clear_at >= 0.0) {
        double dx = x - r->clear_x;
        double dy = y - r->clear_y;
        /* Most periods the robot is well inside that distance: squares tell so without
         * hypot()'s cost, and the nanometre of margin is far above the rounding of either
         * way at a room's scale, so the answer is the exact test's. */
        double m = r->clear_at - r->min_clearance - 1e-9;
        if (m > 0.0 && dx * dx + dy * dy < m * m) {
            return;
        }
        if (r->clear_at - hypot(dx, dy) >= r->min_clearance) {
            return;
        }
    }
    double cap = r->body_m + CLEARANCE_CAP_M;
    double gap = room_clearance(r->room, x, y, cap) - r->body_m;
    r->clear_x = x;
    r->clear_y = y;
    r->clear_at = gap;
    if (gap < r->min_clearance) {
        r->min_clearance = gap;
    }
}

/*
 * The first touch, and where the obstacle lay: the nearest obstacle along 360 rays from the
 * body's centre, a degree apart (what is touched lies within the body's radius). Once a run.
 */
void touch_tick(run_t *r, bool contact, double x, double y, double th, double t, double pos_err,
                double th_err)
{
    if (!contact || r->touch_t >= 0.0) {
        return;
    }
    double reach = r->body_m + CLEARANCE_CAP_M;
    double best = HUGE_VAL;
    double bearing = 0.0;
    for (int k = 0; k < 360; k++) {
        double b = (k - 180) * PI / 180.0;
        double d = room_ray(r->room, x, y, th + b, reach, NULL);
        if (d < best) {
            best = d;
            bearing = b;
        }
    }
    r->touch_t = t;
    r->touch_x = x;
    r->touch_y = y;
    r->touch_th = th;
    r->touch_bearing = bearing;
    r->touch_pos_err = pos_err;
    r->touch_th_err = th_err;
}
