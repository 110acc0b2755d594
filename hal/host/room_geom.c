/* SPDX-License-Identifier: MIT */
/* Room geometry: rays, clearance, free start poses and the ground-truth raster. */
#include <math.h>
#include <string.h>

#include "host/sim.h"
#include "room_internal.h"

/* Occupancy of a raster pixel; 0 outside the raster. */
static int px_occ(const room_t *r, long ix, long iy)
{
    if (ix < 0 || iy < 0 || ix >= (long)r->occ_w || iy >= (long)r->occ_h) {
        return 0;
    }
    return r->occ[(size_t)iy * r->occ_w + (size_t)ix];
}

/*
 * The normal of a raster surface, seen from the free pixel in front of it: the Sobel
 * gradient of the occupancy there points into the obstacle. A staircase of pixels then
 * reflects like the slanted wall it was drawn from, where the faces of single pixels
 * would make every diagonal wall look like a 45° one. Returns |cos| of the incidence, or
 * -1 when the gradient vanishes; sets @p normal (the unit gradient) when it does not and
 * it is not NULL.
 */
static double sobel_cos(const room_t *r, long ix, long iy, double dx, double dy, double *normal)
{
    int gx = (px_occ(r, ix + 1, iy - 1) + 2 * px_occ(r, ix + 1, iy) + px_occ(r, ix + 1, iy + 1)) -
             (px_occ(r, ix - 1, iy - 1) + 2 * px_occ(r, ix - 1, iy) + px_occ(r, ix - 1, iy + 1));
    int gy = (px_occ(r, ix - 1, iy + 1) + 2 * px_occ(r, ix, iy + 1) + px_occ(r, ix + 1, iy + 1)) -
             (px_occ(r, ix - 1, iy - 1) + 2 * px_occ(r, ix, iy - 1) + px_occ(r, ix + 1, iy - 1));
    if (gx == 0 && gy == 0) {
        return -1.0;
    }
    double n = sqrt((double)(gx * gx + gy * gy));
    if (normal != NULL) {
        normal[0] = (double)gx / n;
        normal[1] = (double)gy / n;
    }
    return fabs((double)gx * dx + (double)gy * dy) / n;
}

double room_hit_raster(const room_t *r, double ox, double oy, double dx, double dy, double max_m,
                       double *cosi, double *normal)
{
    const double res = r->occ_res;
    room_walk_t w;
    if (!room_walk_start(&w, (ox - r->occ_x0) / res, (oy - r->occ_y0) / res, dx, dy, max_m / res,
                         (long)r->occ_w, (long)r->occ_h)) {
        return HOST_INF;
    }
    long pix = -1; /* the free pixel before the current one */
    long piy = -1;
    for (;;) {
        if (r->occ[(size_t)w.iy * r->occ_w + (size_t)w.ix]) {
            double c = -1.0;
            if (pix >= 0) {
                c = sobel_cos(r, pix, piy, dx, dy, normal);
            }
            if (c < 0.0) {
                /* The face of the pixel entered; a ray that starts in one meets it head-on. */
                c = w.axis == 0 ? fabs(dx) : (w.axis == 1 ? fabs(dy) : 1.0);
                if (normal != NULL) {
                    normal[0] = w.axis == 0 ? 1.0 : (w.axis == 1 ? 0.0 : dx);
                    normal[1] = w.axis == 0 ? 0.0 : (w.axis == 1 ? 1.0 : dy);
                }
            }
            *cosi = c;
            return w.t * res;
        }
        pix = w.ix;
        piy = w.iy;
        if (!room_walk_next(&w)) {
            return HOST_INF;
        }
    }
}

double room_ray(const room_t *r, double x, double y, double dir, double max_m,
                double *cos_incidence)
{
    double dx = cos(dir);
    double dy = sin(dir);
    double best = HOST_INF;
    double ci = 1.0;
    if (r->index != NULL) {
        double cd;
        double sd2;
        if (room_index_near(r, x, y, 0.0, &cd, &sd2) == 1) {
            best = 0.0; /* inside a solid box */
        } else {
            best = room_index_ray(r, x, y, dx, dy, max_m, &ci, NULL);
        }
    } else {
        for (size_t i = 0; i < r->nboxes; i++) {
            if (room_in_box(&r->boxes[i], x, y)) {
                best = 0.0;
            }
        }
        for (size_t i = 0; i < r->nsegs && best > 0.0; i++) {
            best = room_hit_segment(&r->segs[i], x, y, dx, dy, best, &ci);
        }
        for (size_t i = 0; i < r->ncircles && best > 0.0; i++) {
            best = room_hit_circle(&r->circles[i], x, y, dx, dy, best, &ci);
        }
    }
    if (r->occ != NULL && best > 0.0) {
        double rc = 1.0;
        double d = room_hit_raster(r, x, y, dx, dy, fmin(max_m, best), &rc, NULL);
        if (d < best) {
            best = d;
            ci = rc;
        }
    }
    if (!(best <= max_m)) {
        return max_m + 1.0;
    }
    if (cos_incidence != NULL) {
        *cos_incidence = ci;
    }
    return best;
}

/* Squared distance to the nearest occupied pixel, looking within cap (best2 = cap²). */
static double raster_dist2(const room_t *r, double x, double y, double cap, double best2)
{
    const double res = r->occ_res;
    double fx0 = floor((x - cap - r->occ_x0) / res);
    double fx1 = floor((x + cap - r->occ_x0) / res);
    double fy0 = floor((y - cap - r->occ_y0) / res);
    double fy1 = floor((y + cap - r->occ_y0) / res);
    if (fx1 < 0.0 || fy1 < 0.0 || fx0 >= (double)r->occ_w || fy0 >= (double)r->occ_h) {
        return best2;
    }
    long ix0 = fx0 < 0.0 ? 0 : (long)fx0;
    long iy0 = fy0 < 0.0 ? 0 : (long)fy0;
    long ix1 = fx1 >= (double)r->occ_w ? (long)r->occ_w - 1 : (long)fx1;
    long iy1 = fy1 >= (double)r->occ_h ? (long)r->occ_h - 1 : (long)fy1;
    for (long iy = iy0; iy <= iy1; iy++) {
        double py0 = r->occ_y0 + (double)iy * res;
        double ddy = fmax(fmax(py0 - y, y - (py0 + res)), 0.0);
        if (ddy * ddy >= best2) {
            continue;
        }
        const uint8_t *row = &r->occ[(size_t)iy * r->occ_w];
        for (long ix = ix0; ix <= ix1; ix++) {
            if (row[ix]) {
                double px0 = r->occ_x0 + (double)ix * res;
                double ddx = fmax(fmax(px0 - x, x - (px0 + res)), 0.0);
                double d2 = ddx * ddx + ddy * ddy;
                if (d2 < best2) {
                    best2 = d2;
                }
            }
        }
    }
    return best2;
}

double room_clearance(const room_t *r, double x, double y, double cap_m)
{
    double best = cap_m;
    /* Squared distances for segments. "found" rather than comparing with cap² again:
       with x87 arithmetic (-m32) sqrt(cap·cap) need not give back cap exactly. */
    double best2;
    bool found = false;
    if (r->index != NULL) {
        /* The same arithmetic on the objects near the point: the same answer. */
        double cd;
        double sd2;
        if (room_index_near(r, x, y, cap_m, &cd, &sd2) == 1 || cd <= 0.0) {
            return 0.0;
        }
        best = fmin(best, cd);
        best2 = best * best;
        if (sd2 < best2) {
            best2 = sd2;
            found = true;
        }
    } else {
        for (size_t i = 0; i < r->nboxes; i++) {
            if (room_in_box(&r->boxes[i], x, y)) {
                return 0.0;
            }
        }
        for (size_t i = 0; i < r->ncircles; i++) {
            const room_circle_t *c = &r->circles[i];
            double d = hypot(x - c->cx, y - c->cy) - c->r;
            if (d <= 0.0) {
                return 0.0;
            }
            best = fmin(best, d);
        }
        best2 = best * best;
        for (size_t i = 0; i < r->nsegs; i++) {
            double d2 = room_seg_dist2(&r->segs[i], x, y);
            if (d2 < best2) {
                best2 = d2;
                found = true;
            }
        }
    }
    if (r->occ != NULL) {
        double d2 = raster_dist2(r, x, y, best, best2);
        if (d2 < best2) {
            best2 = d2;
            found = true;
        }
    }
    return found ? fmin(sqrt(best2), best) : best;
}

bool room_disc_free(const room_t *r, double x, double y, double r_m)
{
    return room_clearance(r, x, y, r_m) >= r_m;
}

bool room_encloses(const room_t *r, double x, double y, double *open_deg)
{
    double reach = 2.0 * hypot(r->max_x - r->min_x, r->max_y - r->min_y) + 1.0;
    for (int k = 0; k < 8; k++) {
        if (!(room_ray(r, x, y, (double)k * (HOST_PI / 4.0), reach, NULL) <= reach)) {
            if (open_deg != NULL) {
                *open_deg = 45.0 * k;
            }
            return false;
        }
    }
    return true;
}

/* A start candidate: clear, on known free ground, and walled in all round. */
static bool start_ok(const room_t *r, double x, double y, double clearance)
{
    if (x < r->min_x || x > r->max_x || y < r->min_y || y > r->max_y) {
        return false;
    }
    if (r->occ != NULL) {
        double fx = floor((x - r->occ_x0) / r->occ_res);
        double fy = floor((y - r->occ_y0) / r->occ_res);
        if (fx < 0.0 || fy < 0.0 || fx >= (double)r->occ_w || fy >= (double)r->occ_h ||
            !r->occ_free[(size_t)fy * r->occ_w + (size_t)fx]) {
            return false;
        }
    }
    return room_disc_free(r, x, y, clearance) && room_encloses(r, x, y, NULL);
}

int room_find_start(const room_t *r, double clearance_m, double *x, double *y, double *th)
{
    if (!(clearance_m >= 0.0) || !(r->max_x >= r->min_x) || !(r->max_y >= r->min_y)) {
        return -1;
    }
    double step = r->occ != NULL ? r->occ_res : 0.02;
    double mx = 0.5 * (r->min_x + r->max_x);
    double my = 0.5 * (r->min_y + r->max_y);
    if (r->occ != NULL) { /* candidates at pixel centres */
        mx = r->occ_x0 + (floor((mx - r->occ_x0) / step) + 0.5) * step;
        my = r->occ_y0 + (floor((my - r->occ_y0) / step) + 0.5) * step;
    }
    long kmax = (long)ceil(fmax(r->max_x - r->min_x, r->max_y - r->min_y) / step) + 1;
    long best_i = 0;
    long best_j = 0;
    long best_d2 = -1;
    for (long k = 0; k <= kmax; k++) {
        if (best_d2 >= 0 && k * k > best_d2) {
            break; /* every point of this ring and beyond is farther */
        }
        long n = k == 0 ? 1 : 8 * k;
        for (long m = 0; m < n; m++) {
            long i;
            long j;
            if (k == 0) {
                i = 0;
                j = 0;
            } else if (m < 2 * k + 1) {
                i = m - k;
                j = -k;
            } else if (m < 4 * k + 2) {
                i = m - (3 * k + 1);
                j = k;
            } else if (m < 6 * k + 1) {
                i = -k;
                j = m - (5 * k + 1);
            } else {
                i = k;
                j = m - (7 * k);
            }
            long d2 = i * i + j * j;
            if (best_d2 >= 0 && d2 >= best_d2) {
                continue;
            }
            if (start_ok(r, mx + (double)i * step, my + (double)j * step, clearance_m)) {
                best_i = i;
                best_j = j;
                best_d2 = d2;
            }
        }
    }
    if (best_d2 < 0) {
        return -1;
    }
    *x = mx + (double)best_i * step;
    *y = my + (double)best_j * step;
    *th = 0.0;
    return 0;
}

/* ---- ground truth ------------------------------------------------------------------- */

typedef struct {
    double ox, oy, cell;
    uint32_t a, b;
    uint8_t *out;
} raster_out_t;

static void mark(const raster_out_t *g, long a, long b)
{
    if (a >= 0 && b >= 0 && a < (long)g->a && b < (long)g->b) {
        g->out[(size_t)b * g->a + (size_t)a] = 1u;
    }
}

/* Every cell a segment passes through: clip to the grid, then walk it (grid DDA). */
static void mark_segment(const raster_out_t *g, const room_segment_t *s)
{
    double u0 = (s->x1 - g->ox) / g->cell;
    double v0 = (s->y1 - g->oy) / g->cell;
    double du = (s->x2 - g->ox) / g->cell - u0;
    double dv = (s->y2 - g->oy) / g->cell - v0;
    double t0 = 0.0;
    double t1 = 1.0;
    /* Liang-Barsky against [0, a] x [0, b]. */
    const double pq[4][2] = {
        {-du, u0}, {du, (double)g->a - u0}, {-dv, v0}, {dv, (double)g->b - v0}};
    for (int k = 0; k < 4; k++) {
        double p = pq[k][0];
        double q = pq[k][1];
        if (p == 0.0) {
            if (q < 0.0) {
                return;
            }
        } else {
            double t = q / p;
            if (p < 0.0) {
                t0 = fmax(t0, t);
            } else {
                t1 = fmin(t1, t);
            }
        }
    }
    if (t0 > t1) {
        return;
    }
    double pu = u0 + t0 * du;
    double pv = v0 + t0 * dv;
    long ia = (long)floor(pu);
    long ib = (long)floor(pv);
    const long sa = du > 0.0 ? 1 : -1;
    const long sb = dv > 0.0 ? 1 : -1;
    const double tda = du == 0.0 ? HOST_INF : 1.0 / fabs(du);
    const double tdb = dv == 0.0 ? HOST_INF : 1.0 / fabs(dv);
    double tma =
        du == 0.0 ? HOST_INF : t0 + (du > 0.0 ? ((double)ia + 1.0 - pu) : (pu - (double)ia)) * tda;
    double tmb =
        dv == 0.0 ? HOST_INF : t0 + (dv > 0.0 ? ((double)ib + 1.0 - pv) : (pv - (double)ib)) * tdb;
    mark(g, ia, ib);
    for (;;) {
        if (tma < tmb) {
            if (tma > t1) {
                break;
            }
            ia += sa;
            tma += tda;
        } else {
            if (tmb > t1) {
                break;
            }
            ib += sb;
            tmb += tdb;
        }
        mark(g, ia, ib);
    }
}

/* Cells whose square the circle's outline crosses: nearest point inside, farthest outside. */
static void mark_circle(const raster_out_t *g, const room_circle_t *c)
{
    double fa0 = floor((c->cx - c->r - g->ox) / g->cell);
    double fa1 = floor((c->cx + c->r - g->ox) / g->cell);
    double fb0 = floor((c->cy - c->r - g->oy) / g->cell);
    double fb1 = floor((c->cy + c->r - g->oy) / g->cell);
    if (fa1 < 0.0 || fb1 < 0.0 || fa0 >= (double)g->a || fb0 >= (double)g->b) {
        return;
    }
    long a0 = fa0 < 0.0 ? 0 : (long)fa0;
    long b0 = fb0 < 0.0 ? 0 : (long)fb0;
    long a1 = fa1 >= (double)g->a ? (long)g->a - 1 : (long)fa1;
    long b1 = fb1 >= (double)g->b ? (long)g->b - 1 : (long)fb1;
    for (long b = b0; b <= b1; b++) {
        double y0 = g->oy + (double)b * g->cell - c->cy;
        double y1 = y0 + g->cell;
        double ny = fmax(fmax(y0, -y1), 0.0);
        double fy = fmax(fabs(y0), fabs(y1));
        for (long a = a0; a <= a1; a++) {
            double x0 = g->ox + (double)a * g->cell - c->cx;
            double x1 = x0 + g->cell;
            double nx = fmax(fmax(x0, -x1), 0.0);
            double fx = fmax(fabs(x0), fabs(x1));
            if (nx * nx + ny * ny <= c->r * c->r && fx * fx + fy * fy >= c->r * c->r) {
                mark(g, a, b);
            }
        }
    }
}

/* Cells that overlap an occupied pixel by a positive area. */
static void mark_pixels(const raster_out_t *g, const room_t *r)
{
    const double eps = 1e-9;
    for (uint32_t iy = 0; iy < r->occ_h; iy++) {
        double y0 = (r->occ_y0 + (double)iy * r->occ_res - g->oy) / g->cell;
        double y1 = (r->occ_y0 + (double)(iy + 1u) * r->occ_res - g->oy) / g->cell;
        long b0 = (long)floor(y0 + eps);
        long b1 = (long)ceil(y1 - eps) - 1;
        if (b1 < 0 || b0 >= (long)g->b) {
            continue;
        }
        for (uint32_t ix = 0; ix < r->occ_w; ix++) {
            if (!r->occ[(size_t)iy * r->occ_w + ix]) {
                continue;
            }
            double x0 = (r->occ_x0 + (double)ix * r->occ_res - g->ox) / g->cell;
            double x1 = (r->occ_x0 + (double)(ix + 1u) * r->occ_res - g->ox) / g->cell;
            long a0 = (long)floor(x0 + eps);
            long a1 = (long)ceil(x1 - eps) - 1;
            for (long b = b0; b <= b1; b++) {
                for (long a = a0; a <= a1; a++) {
                    mark(g, a, b);
                }
            }
        }
    }
}

void room_rasterize(const room_t *r, double origin_x, double origin_y, double cell_m,
                    uint32_t a_cells, uint32_t b_cells, uint8_t *out)
{
    memset(out, 0, (size_t)a_cells * b_cells);
    if (!(cell_m > 0.0)) {
        return;
    }
    const raster_out_t g = {origin_x, origin_y, cell_m, a_cells, b_cells, out};
    for (size_t i = 0; i < r->nsegs; i++) {
        mark_segment(&g, &r->segs[i]);
    }
    for (size_t i = 0; i < r->ncircles; i++) {
        mark_circle(&g, &r->circles[i]);
    }
    if (r->occ != NULL) {
        mark_pixels(&g, r);
    }
}
