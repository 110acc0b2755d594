/* SPDX-License-Identifier: MIT */
/* A uniform grid over a room's objects, so that rays and clearance look only nearby. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "host/sim.h"
#include "room_internal.h"

/* Index cells are padded by this (in cells): an object on a cell's edge is in both cells,
 * whatever the rounding of a query's walk. */
#define INDEX_EPS 1e-6
/* The most cells along a side. */
#define INDEX_MAX_SIDE 65535.0

static uint64_t examined; /* objects looked at by indexed queries, for tests */

uint64_t room_index_examined(void)
{
    return examined;
}

/* A callback per (cell, object) pair: counting, then filling. */
typedef struct {
    room_index_t *ix;
    uint32_t *fill; /* NULL while counting */
} pass_t;

static void put(pass_t *ps, uint32_t cx, uint32_t cy, uint32_t id)
{
    room_index_t *ix = ps->ix;
    size_t c = (size_t)cy * ix->nx + cx;
    if (ps->fill == NULL) {
        ix->start[c + 1u]++;
    } else {
        ix->items[ps->fill[c]++] = id;
    }
}

/* Cell range [lo, hi] along one axis for the grid coordinate interval [a, b], clamped. */
static void span(double a, double b, uint32_t n, uint32_t *lo, uint32_t *hi)
{
    double l = floor(a - INDEX_EPS);
    double h = floor(b + INDEX_EPS);
    l = l < 0.0 ? 0.0 : (l > (double)n - 1.0 ? (double)n - 1.0 : l);
    h = h < 0.0 ? 0.0 : (h > (double)n - 1.0 ? (double)n - 1.0 : h);
    *lo = (uint32_t)l;
    *hi = (uint32_t)h;
}

static void put_box(pass_t *ps, double x0, double y0, double x1, double y1, uint32_t id)
{
    const room_index_t *ix = ps->ix;
    uint32_t a0;
    uint32_t a1;
    uint32_t b0;
    uint32_t b1;
    span((x0 - ix->x0) * ix->inv, (x1 - ix->x0) * ix->inv, ix->nx, &a0, &a1);
    span((y0 - ix->y0) * ix->inv, (y1 - ix->y0) * ix->inv, ix->ny, &b0, &b1);
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            put(ps, a, b, id);
        }
    }
}

/* Every cell a segment passes through (or within INDEX_EPS of): row by row, the part of
 * the segment inside the row's band. */
static void put_segment(pass_t *ps, const room_segment_t *s, uint32_t id)
{
    const room_index_t *ix = ps->ix;
    double u0 = (s->x1 - ix->x0) * ix->inv;
    double v0 = (s->y1 - ix->y0) * ix->inv;
    double u1 = (s->x2 - ix->x0) * ix->inv;
    double v1 = (s->y2 - ix->y0) * ix->inv;
    uint32_t r0;
    uint32_t r1;
    span(fmin(v0, v1), fmax(v0, v1), ix->ny, &r0, &r1);
    double dv = v1 - v0;
    for (uint32_t r = r0; r <= r1; r++) {
        double ua = fmin(u0, u1);
        double ub = fmax(u0, u1);
        if (fabs(dv) > 1e-12) {
            /* The parameters where the segment enters and leaves the band [r, r + 1]. */
            double ta = ((double)r - INDEX_EPS - v0) / dv;
            double tb = ((double)r + 1.0 + INDEX_EPS - v0) / dv;
            double t0 = fmax(fmin(ta, tb), 0.0);
            double t1 = fmin(fmax(ta, tb), 1.0);
            if (t0 > t1) {
                continue;
            }
            double pa = u0 + t0 * (u1 - u0);
            double pb = u0 + t1 * (u1 - u0);
            ua = fmin(pa, pb);
            ub = fmax(pa, pb);
        }
        uint32_t c0;
        uint32_t c1;
        span(ua, ub, ix->nx, &c0, &c1);
        for (uint32_t c = c0; c <= c1; c++) {
            put(ps, c, r, id);
        }
    }
}

static void pass(pass_t *ps, const room_t *r)
{
    for (size_t i = 0; i < r->nsegs; i++) {
        put_segment(ps, &r->segs[i], (uint32_t)i);
    }
    for (size_t i = 0; i < r->ncircles; i++) {
        const room_circle_t *c = &r->circles[i];
        put_box(ps, c->cx - c->r, c->cy - c->r, c->cx + c->r, c->cy + c->r,
                (uint32_t)(r->nsegs + i));
    }
    for (size_t i = 0; i < r->nboxes; i++) {
        const room_box_t *b = &r->boxes[i];
        put_box(ps, b->x0, b->y0, b->x1, b->y1, (uint32_t)(r->nsegs + r->ncircles + i));
    }
}

int room_index_build(room_t *r)
{
    size_t n = r->nsegs + r->ncircles + r->nboxes;
    r->index = NULL;
    if (n < ROOM_INDEX_MIN || n > UINT32_MAX / 2u || !(r->max_x >= r->min_x) ||
        !(r->max_y >= r->min_y)) {
        return 0; /* a few objects are quicker to look at than an index */
    }
    double w = r->max_x - r->min_x;
    double h = r->max_y - r->min_y;
    double len = 0.0;
    for (size_t i = 0; i < r->nsegs; i++) {
        len += hypot(r->segs[i].x2 - r->segs[i].x1, r->segs[i].y2 - r->segs[i].y1);
    }
    for (size_t i = 0; i < r->ncircles; i++) {
        len += 4.0 * r->circles[i].r;
    }
    for (size_t i = 0; i < r->nboxes; i++) {
        len += (r->boxes[i].x1 - r->boxes[i].x0) + (r->boxes[i].y1 - r->boxes[i].y0);
    }
    /* About one cell per object, and cells long enough that the objects' entries stay a
     * few per object: the index grows with the file, not with the room's area. */
    double dn = (double)n;
    double cell = fmax(sqrt(w * h / dn), len / (2.0 * dn));
    cell = fmax(cell, fmax(w, h) / fmin(2.0 * dn, INDEX_MAX_SIDE));
    cell = fmax(cell, 1e-3);
    room_index_t *ix = calloc(1u, sizeof *ix);
    if (ix == NULL) {
        return -1;
    }
    ix->cell = cell;
    ix->inv = 1.0 / cell;
    ix->x0 = r->min_x - cell * 0.5;
    ix->y0 = r->min_y - cell * 0.5;
    ix->nx = (uint32_t)fmin(ceil((w + cell) * ix->inv) + 1.0, INDEX_MAX_SIDE);
    ix->ny = (uint32_t)fmin(ceil((h + cell) * ix->inv) + 1.0, INDEX_MAX_SIDE);
    size_t ncells = (size_t)ix->nx * ix->ny;
    ix->start = calloc(ncells + 1u, sizeof *ix->start);
    uint32_t *fill = malloc(ncells * sizeof *fill);
    if (ix->start == NULL || fill == NULL) {
        free(fill);
        free(ix->start);
        free(ix);
        return -1;
    }
    pass_t count = {ix, NULL};
    pass(&count, r);
    for (size_t c = 0; c < ncells; c++) {
        ix->start[c + 1u] += ix->start[c];
    }
    ix->nitems = ix->start[ncells];
    ix->items = malloc((ix->nitems + 1u) * sizeof *ix->items);
    if (ix->items == NULL) {
        free(fill);
        free(ix->start);
        free(ix);
        return -1;
    }
    memcpy(fill, ix->start, ncells * sizeof *fill);
    pass_t put_all = {ix, fill};
    pass(&put_all, r);
    free(fill);
    r->index = ix;
    return 0;
}

void room_index_free(room_t *r)
{
    if (r->index != NULL) {
        free(r->index->start);
        free(r->index->items);
        free(r->index);
        r->index = NULL;
    }
}

size_t room_index_entries(const room_t *r)
{
    return r->index != NULL ? r->index->nitems : 0u;
}

void room_index_cells(const room_t *r, double x0, double y0, double x1, double y1,
                      uint32_t *a0, uint32_t *a1, uint32_t *b0, uint32_t *b1)
{
    const room_index_t *ix = r->index;
    span((x0 - ix->x0) * ix->inv, (x1 - ix->x0) * ix->inv, ix->nx, a0, a1);
    span((y0 - ix->y0) * ix->inv, (y1 - ix->y0) * ix->inv, ix->ny, b0, b1);
}

const uint32_t *room_index_cell(const room_t *r, uint32_t a, uint32_t b, size_t *n)
{
    const room_index_t *ix = r->index;
    size_t c = (size_t)b * ix->nx + a;
    *n = ix->start[c + 1u] - ix->start[c];
    examined += *n;
    return &ix->items[ix->start[c]];
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a;
    uint32_t y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

size_t room_index_gather(const room_t *r, double x0, double y0, double x1, double y1,
                         uint32_t *stamp, uint32_t *stamp_now, uint32_t *out)
{
    uint32_t a0;
    uint32_t a1;
    uint32_t b0;
    uint32_t b1;
    room_index_cells(r, x0, y0, x1, y1, &a0, &a1, &b0, &b1);
    if (++*stamp_now == 0u) { /* wrapped: forget every old mark */
        memset(stamp, 0, (r->nsegs + r->ncircles) * sizeof *stamp);
        *stamp_now = 1u;
    }
    size_t n = 0u;
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            size_t m;
            const uint32_t *it = room_index_cell(r, a, b, &m);
            for (size_t k = 0; k < m; k++) {
                uint32_t id = it[k];
                if (id < r->nsegs + r->ncircles && stamp[id] != *stamp_now) {
                    stamp[id] = *stamp_now;
                    out[n++] = id;
                }
            }
        }
    }
    qsort(out, n, sizeof *out, cmp_u32);
    return n;
}

int room_index_near(const room_t *r, double x, double y, double cap, double *circle_d,
                    double *seg_d2)
{
    double cd = HOST_INF;
    double sd2 = HOST_INF;
    const size_t ns = r->nsegs;
    const size_t nc = r->ncircles;
    uint32_t a0;
    uint32_t a1;
    uint32_t b0;
    uint32_t b1;
    /* Inside a box or a circle: only the objects of the point's own cell can hold it. */
    room_index_cells(r, x, y, x, y, &a0, &a1, &b0, &b1);
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            size_t n;
            const uint32_t *it = room_index_cell(r, a, b, &n);
            for (size_t k = 0; k < n; k++) {
                if (it[k] >= ns + nc && room_in_box(&r->boxes[it[k] - ns - nc], x, y)) {
                    return 1;
                }
            }
        }
    }
    room_index_cells(r, x - cap, y - cap, x + cap, y + cap, &a0, &a1, &b0, &b1);
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            size_t n;
            const uint32_t *it = room_index_cell(r, a, b, &n);
            for (size_t k = 0; k < n; k++) {
                uint32_t id = it[k];
                if (id < ns) {
                    double d2 = room_seg_dist2(&r->segs[id], x, y);
                    sd2 = d2 < sd2 ? d2 : sd2;
                } else if (id < ns + nc) {
                    const room_circle_t *c = &r->circles[id - ns];
                    double d = hypot(x - c->cx, y - c->cy) - c->r;
                    cd = d < cd ? d : cd;
                }
            }
        }
    }
    *circle_d = cd;
    *seg_d2 = sd2;
    return 0;
}

/* The ray's walk through the index cells, testing the objects of each until a hit lies
 * within the cells walked. */
double room_index_ray(const room_t *r, double ox, double oy, double dx, double dy,
                      double max_m, double *cosi, uint32_t *id)
{
    const room_index_t *ix = r->index;
    const size_t ns = r->nsegs;
    const size_t nc = r->ncircles;
    double best = HOST_INF;
    room_walk_t w;
    if (!room_walk_start(&w, (ox - ix->x0) * ix->inv, (oy - ix->y0) * ix->inv, dx, dy,
                         max_m * ix->inv, (long)ix->nx, (long)ix->ny)) {
        return HOST_INF;
    }
    for (;;) {
        size_t n;
        const uint32_t *it = room_index_cell(r, (uint32_t)w.ix, (uint32_t)w.iy, &n);
        for (size_t k = 0; k < n && best > 0.0; k++) {
            uint32_t obj = it[k];
            double was = best;
            if (obj < ns) {
                best = room_hit_segment(&r->segs[obj], ox, oy, dx, dy, best, cosi);
            } else if (obj < ns + nc) {
                best = room_hit_circle(&r->circles[obj - ns], ox, oy, dx, dy, best, cosi);
            }
            if (id != NULL && best < was) {
                *id = obj;
            }
        }
        /* A hit within this cell (short of its padding) is the nearest: later cells lie
         * farther along the ray. */
        double t_exit = fmin(w.tmx, w.tmy);
        if (best <= (t_exit - INDEX_EPS) * ix->cell || t_exit > w.t1 || !room_walk_next(&w)) {
            return best;
        }
    }
}
