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

/* ---- the tree for nearest-object queries --------------------------------------------------- */

#define BVH_LEAF 4u       /* objects a leaf holds at most */
#define BVH_MAX_DEPTH 64u /* beyond, splits halve the count: the depth stays below 96 */
#define BVH_STACK 128u

/* A node: its box, and either its objects (count > 0: leaf_ids[first ..]) or its children
 * (count 0: the left one right after it, the right one at `first`). */
typedef struct room_bvh_node {
    double x0, y0, x1, y1;
    uint32_t first, count;
} room_bvh_node_t;

static inline double dmin(double a, double b)
{
    return b < a ? b : a; /* fmin() without its call: no NaN reaches the tree */
}

static inline double dmax(double a, double b)
{
    return b > a ? b : a;
}

/* The box of segment or circle id. */
static void object_box(const room_t *r, uint32_t id, double b[4])
{
    if (id < r->nsegs) {
        const room_segment_t *s = &r->segs[id];
        b[0] = dmin(s->x1, s->x2);
        b[1] = dmin(s->y1, s->y2);
        b[2] = dmax(s->x1, s->x2);
        b[3] = dmax(s->y1, s->y2);
    } else {
        const room_circle_t *c = &r->circles[id - r->nsegs];
        b[0] = c->cx - c->r;
        b[1] = c->cy - c->r;
        b[2] = c->cx + c->r;
        b[3] = c->cy + c->r;
    }
}

typedef struct {
    const double (*box)[4]; /* every object's box, by id */
    uint32_t *ids;
    room_bvh_node_t *nodes;
    uint32_t used;
} bvh_build_t;

/* The subtree of ids[lo, hi) at node `at`: split at the middle of the objects' centres
 * along their wider spread (linear work a level, whatever the input), or in halves by
 * count when that leaves a side empty (equal centres) or the tree grows too deep. */
static void bvh_node(bvh_build_t *b, uint32_t at, uint32_t lo, uint32_t hi, unsigned depth)
{
    room_bvh_node_t *n = &b->nodes[at];
    double c0[2] = {HOST_INF, HOST_INF};
    double c1[2] = {-HOST_INF, -HOST_INF};
    double x0 = HOST_INF;
    double y0 = HOST_INF;
    double x1 = -HOST_INF;
    double y1 = -HOST_INF;
    for (uint32_t i = lo; i < hi; i++) {
        const double *bx = b->box[b->ids[i]];
        x0 = dmin(x0, bx[0]);
        y0 = dmin(y0, bx[1]);
        x1 = dmax(x1, bx[2]);
        y1 = dmax(y1, bx[3]);
        for (int k = 0; k < 2; k++) {
            double c = bx[k] + bx[k + 2]; /* twice the centre: halving changes no order */
            c0[k] = dmin(c0[k], c);
            c1[k] = dmax(c1[k], c);
        }
    }
    *n = (room_bvh_node_t){x0, y0, x1, y1, lo, hi - lo};
    if (hi - lo <= BVH_LEAF) {
        return;
    }
    int axis = c1[1] - c0[1] > c1[0] - c0[0] ? 1 : 0;
    double mid = 0.5 * (c0[axis] + c1[axis]);
    uint32_t split = lo;
    if (depth < BVH_MAX_DEPTH && c1[axis] > c0[axis]) {
        uint32_t i = lo;
        uint32_t j = hi;
        while (i < j) { /* those whose centre is below mid first */
            const double *bx = b->box[b->ids[i]];
            if (bx[axis] + bx[axis + 2] < mid) {
                i++;
            } else {
                uint32_t t = b->ids[i];
                b->ids[i] = b->ids[--j];
                b->ids[j] = t;
            }
        }
        split = i;
    }
    if (split == lo || split == hi) {
        split = lo + (hi - lo) / 2u;
    }
    uint32_t left = b->used + 1u; /* the two children side by side */
    b->used += 2u;
    n->first = left;
    n->count = 0u;
    bvh_node(b, left, lo, split, depth + 1u);
    bvh_node(b, left + 1u, split, hi, depth + 1u);
}

/* The tree over every segment and circle; 0, or -1 when out of memory. */
static int bvh_build(const room_t *r, room_index_t *ix)
{
    size_t n = r->nsegs + r->ncircles;
    ix->nodes = NULL;
    ix->leaf_ids = NULL;
    if (n == 0u) {
        return 0;
    }
    double(*box)[4] = malloc(n * sizeof *box);
    ix->leaf_ids = malloc(n * sizeof *ix->leaf_ids);
    /* A full binary tree with leaves of at least one object has fewer than 2n nodes. */
    ix->nodes = malloc(2u * n * sizeof *ix->nodes);
    if (box == NULL || ix->leaf_ids == NULL || ix->nodes == NULL) {
        free(box);
        free(ix->leaf_ids);
        free(ix->nodes);
        ix->leaf_ids = NULL;
        ix->nodes = NULL;
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        ix->leaf_ids[i] = (uint32_t)i;
        object_box(r, (uint32_t)i, box[i]);
    }
    bvh_build_t b = {(const double(*)[4])box, ix->leaf_ids, ix->nodes, 0u};
    bvh_node(&b, 0u, 0u, (uint32_t)n, 0u);
    free(box);
    return 0;
}

/* Squared distance from (x, y) to a node's box (0 inside it). */
static inline double box_dist2(const room_bvh_node_t *n, double x, double y)
{
    double dx = dmax(dmax(n->x0 - x, x - n->x1), 0.0);
    double dy = dmax(dmax(n->y0 - y, y - n->y1), 0.0);
    return dx * dx + dy * dy;
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
    if (bvh_build(r, ix) != 0) {
        free(ix->start);
        free(ix->items);
        free(ix);
        return -1;
    }
    r->index = ix;
    return 0;
}

void room_index_free(room_t *r)
{
    if (r->index != NULL) {
        free(r->index->start);
        free(r->index->items);
        free(r->index->nodes);
        free(r->index->leaf_ids);
        free(r->index);
        r->index = NULL;
    }
}

size_t room_index_entries(const room_t *r)
{
    return r->index != NULL ? r->index->nitems : 0u;
}

void room_index_cells(const room_t *r, double x0, double y0, double x1, double y1, uint32_t *a0,
                      uint32_t *a1, uint32_t *b0, uint32_t *b1)
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
    uint32_t lo = UINT32_MAX;
    uint32_t hi = 0u;
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            size_t m;
            const uint32_t *it = room_index_cell(r, a, b, &m);
            for (size_t k = 0; k < m; k++) {
                uint32_t id = it[k];
                if (id < r->nsegs + r->ncircles && stamp[id] != *stamp_now) {
                    stamp[id] = *stamp_now;
                    out[n++] = id;
                    lo = id < lo ? id : lo;
                    hi = id > hi ? id : hi;
                }
            }
        }
    }
    /* Ascending: a sort of a few, or for many (a crowd of objects under a long cone) a
     * pass over the marks of the ids they span, linear rather than n log n. */
    if (n > 64u && (double)(hi - lo) < (double)n * 8.0) {
        size_t k = 0u;
        for (uint32_t id = lo; k < n; id++) {
            if (stamp[id] == *stamp_now) {
                out[k++] = id;
            }
        }
    } else {
        qsort(out, n, sizeof *out, cmp_u32);
    }
    return n;
}

int room_index_near(const room_t *r, double x, double y, double cap, double *circle_d,
                    double *seg_d2)
{
    const room_index_t *ix = r->index;
    const size_t ns = r->nsegs;
    const size_t nc = r->ncircles;
    uint32_t a0;
    uint32_t a1;
    uint32_t b0;
    uint32_t b1;
    /* Inside a box: only the boxes of the point's own cell can hold it. A cell lists its
     * objects in ascending order, so its boxes come last: a crowd of walls in the cell is
     * never looked at for them. */
    room_index_cells(r, x, y, x, y, &a0, &a1, &b0, &b1);
    for (uint32_t b = b0; b <= b1; b++) {
        for (uint32_t a = a0; a <= a1; a++) {
            size_t c = (size_t)b * ix->nx + a;
            for (size_t k = ix->start[c + 1u]; k > ix->start[c] && ix->items[k - 1u] >= ns + nc;
                 k--) {
                examined++;
                if (room_in_box(&r->boxes[ix->items[k - 1u] - ns - nc], x, y)) {
                    return 1;
                }
            }
        }
    }
    double cd = HOST_INF;
    double sd2 = HOST_INF;
    /* The nearest segment and circle through the tree, nearer child first. A subtree is
     * left out only when its box lies beyond what the caller makes of the best so far,
     * min(cap, circle, √segment), by a margin far above any rounding: what room_clearance()
     * returns is then exactly that of a look at every object. */
    double best = cap;
    uint32_t stack[BVH_STACK];
    unsigned top = 0u;
    if (cap > 0.0 && ix->nodes != NULL) {
        stack[top++] = 0u;
    }
    uint64_t looked = 0u;
    while (top > 0u && best > 0.0) {
        const room_bvh_node_t *n = &ix->nodes[stack[--top]];
        if (box_dist2(n, x, y) > best * best * (1.0 + 1e-9)) {
            continue;
        }
        if (n->count == 0u) {
            const room_bvh_node_t *l = &ix->nodes[n->first];
            const room_bvh_node_t *rt = &ix->nodes[n->first + 1u];
            bool left_first = box_dist2(l, x, y) <= box_dist2(rt, x, y);
            stack[top++] = left_first ? n->first + 1u : n->first; /* the farther, later */
            stack[top++] = left_first ? n->first : n->first + 1u;
            continue;
        }
        for (uint32_t k = 0; k < n->count; k++) {
            uint32_t id = ix->leaf_ids[n->first + k];
            if (id < ns) {
                double d2 = room_seg_dist2(&r->segs[id], x, y);
                if (d2 < sd2) {
                    sd2 = d2;
                    best = fmin(best, sqrt(d2));
                }
            } else {
                const room_circle_t *c = &r->circles[id - ns];
                double d = hypot(x - c->cx, y - c->cy) - c->r;
                if (d < cd) {
                    cd = d;
                    best = fmin(best, d);
                }
            }
        }
        looked += n->count;
    }
    examined += looked;
    *circle_d = cd;
    *seg_d2 = sd2;
    return 0;
}

bool room_index_seg_near(const room_t *r, double x, double y, double d2, uint32_t self)
{
    const room_index_t *ix = r->index;
    uint32_t stack[BVH_STACK];
    unsigned top = 0u;
    if (ix->nodes != NULL) {
        stack[top++] = 0u;
    }
    while (top > 0u) {
        const room_bvh_node_t *n = &ix->nodes[stack[--top]];
        /* A box is left out only beyond d2 by a margin far above any rounding. */
        if (box_dist2(n, x, y) > d2 * (1.0 + 1e-9)) {
            continue;
        }
        if (n->count == 0u) {
            stack[top++] = n->first;
            stack[top++] = n->first + 1u;
            continue;
        }
        for (uint32_t k = 0; k < n->count; k++) {
            uint32_t id = ix->leaf_ids[n->first + k];
            examined++;
            if (id < r->nsegs && id != self && room_seg_dist2(&r->segs[id], x, y) < d2) {
                return true;
            }
        }
    }
    return false;
}

/* The ray's walk through the index cells, testing the objects of each until a hit lies
 * within the cells walked. */
double room_index_ray(const room_t *r, double ox, double oy, double dx, double dy, double max_m,
                      double *cosi, uint32_t *id)
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
