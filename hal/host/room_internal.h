/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Ray tests against single obstacles, shared by the room geometry and the sonar's cone,
 * which runs them on the few obstacles it has not culled. Private to hal/host.
 *
 * Rays are (ox, oy) + t·(dx, dy) with a unit direction; t is in metres. Each test returns
 * the nearer of its hit and @p best, and sets *cosi (|cos| of the incidence) only when its
 * hit is the nearer one.
 */
#ifndef HOST_ROOM_INTERNAL_H
#define HOST_ROOM_INTERNAL_H

#include <math.h>
#include <stdbool.h>

#include "host/sim.h"

/** π, which strict C11 does not define. */
#define HOST_PI 3.14159265358979323846

/** +∞ as a double (INFINITY is a float). */
#define HOST_INF ((double)INFINITY)

/** A ray parallel to a segment within this (|sin| of the angle) never hits it. */
#define ROOM_PARALLEL_EPS 1e-12

static inline double room_hit_segment(const room_segment_t *sg, double ox, double oy, double dx,
                                      double dy, double best, double *cosi)
{
    double ex = sg->x2 - sg->x1;
    double ey = sg->y2 - sg->y1;
    double denom = dx * ey - dy * ex; /* |e|·sin(angle between ray and segment) */
    double len2 = ex * ex + ey * ey;
    if (denom * denom <= (ROOM_PARALLEL_EPS * ROOM_PARALLEL_EPS) * len2) {
        return best;
    }
    double wx = sg->x1 - ox;
    double wy = sg->y1 - oy;
    double nt = wx * ey - wy * ex; /* t = nt / denom along the ray */
    double nu = wx * dy - wy * dx; /* u = nu / denom along the segment */
    if (denom < 0.0) {
        denom = -denom;
        nt = -nt;
        nu = -nu;
    }
    if (nt < 0.0 || nu < 0.0 || nu > denom) {
        return best;
    }
    /* Compared as returned: nt >= best · denom rounds otherwise than nt / denom >= best,
     * and two walls through one point (a box's side on a wall) would then give a nearest
     * hit that depends on the order they are tried in, the index's or the list's. */
    double t = nt / denom;
    if (t >= best) {
        return best;
    }
    *cosi = denom / sqrt(len2);
    return t;
}

static inline double room_hit_circle(const room_circle_t *c, double ox, double oy, double dx,
                                     double dy, double best, double *cosi)
{
    double fx = ox - c->cx;
    double fy = oy - c->cy;
    double b = fx * dx + fy * dy;
    double cc = fx * fx + fy * fy - c->r * c->r;
    if (cc <= 0.0) { /* the ray starts inside the solid circle */
        *cosi = 1.0;
        return 0.0;
    }
    double disc = b * b - cc;
    if (b >= 0.0 || disc < 0.0) { /* moving away, or passing by */
        return best;
    }
    double t = -b - sqrt(disc);
    if (t >= best) {
        return best;
    }
    double nx = (fx + t * dx) / c->r;
    double ny = (fy + t * dy) / c->r;
    *cosi = fabs(nx * dx + ny * dy);
    return t;
}

/** Squared distance from a point to a segment. */
static inline double room_seg_dist2(const room_segment_t *s, double x, double y)
{
    double ex = s->x2 - s->x1;
    double ey = s->y2 - s->y1;
    double wx = x - s->x1;
    double wy = y - s->y1;
    double len2 = ex * ex + ey * ey;
    double t = len2 > 0.0 ? (wx * ex + wy * ey) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double ddx = wx - t * ex;
    double ddy = wy - t * ey;
    return ddx * ddx + ddy * ddy;
}

/** Whether a point lies inside a solid box (its boundary included). */
static inline int room_in_box(const room_box_t *b, double x, double y)
{
    return x >= b->x0 && x <= b->x1 && y >= b->y0 && y <= b->y1;
}

/** A walk through the cells of a grid along a ray (grid DDA); t is in cell sides. */
typedef struct {
    long ix, iy;     /**< the cell the walk is in */
    long nx, ny;     /**< the grid's cells along x and y */
    long sx, sy;     /**< the step along each axis, ±1 */
    double tdx, tdy; /**< t between two cell edges across x (y) */
    double tmx, tmy; /**< t of the next cell edge across x (y) */
    double t;        /**< t where the walk entered the cell */
    double t1;       /**< t where it leaves the grid or reaches its end */
    int axis;        /**< the edge it entered through: 0 across x, 1 across y, -1 none */
} room_walk_t;

/**
 * Start a walk from (gx, gy) in cell units along the unit vector (dx, dy), no further
 * than tmax, clipped to the grid [0, nx] × [0, ny] (slabs).
 * @return false when the ray misses the grid
 */
static inline bool room_walk_start(room_walk_t *w, double gx, double gy, double dx, double dy,
                                   double tmax, long nx, long ny)
{
    const double fw = (double)nx;
    const double fh = (double)ny;
    double t0 = 0.0;
    double t1 = tmax;
    w->axis = -1;
    if (fabs(dx) < 1e-300) {
        if (gx < 0.0 || gx >= fw) {
            return false;
        }
    } else {
        double ta = -gx / dx;
        double tb = (fw - gx) / dx;
        double lo = fmin(ta, tb);
        if (lo > t0) {
            t0 = lo;
            w->axis = 0;
        }
        t1 = fmin(t1, fmax(ta, tb));
    }
    if (fabs(dy) < 1e-300) {
        if (gy < 0.0 || gy >= fh) {
            return false;
        }
    } else {
        double ta = -gy / dy;
        double tb = (fh - gy) / dy;
        double lo = fmin(ta, tb);
        if (lo > t0) {
            t0 = lo;
            w->axis = 1;
        }
        t1 = fmin(t1, fmax(ta, tb));
    }
    if (t0 > t1) {
        return false;
    }
    double px = gx + t0 * dx;
    double py = gy + t0 * dy;
    long ix = (long)floor(px);
    long iy = (long)floor(py);
    w->ix = ix < 0 ? 0 : (ix >= nx ? nx - 1 : ix);
    w->iy = iy < 0 ? 0 : (iy >= ny ? ny - 1 : iy);
    w->nx = nx;
    w->ny = ny;
    w->sx = dx > 0.0 ? 1 : -1;
    w->sy = dy > 0.0 ? 1 : -1;
    w->tdx = fabs(dx) < 1e-300 ? HOST_INF : 1.0 / fabs(dx);
    w->tdy = fabs(dy) < 1e-300 ? HOST_INF : 1.0 / fabs(dy);
    w->tmx = fabs(dx) < 1e-300
                 ? HOST_INF
                 : t0 + (dx > 0.0 ? ((double)w->ix + 1.0 - px) : (px - (double)w->ix)) * w->tdx;
    w->tmy = fabs(dy) < 1e-300
                 ? HOST_INF
                 : t0 + (dy > 0.0 ? ((double)w->iy + 1.0 - py) : (py - (double)w->iy)) * w->tdy;
    w->t = t0;
    w->t1 = t1;
    return true;
}

/** Step into the next cell; false when the walk leaves the grid or passes its end. */
static inline bool room_walk_next(room_walk_t *w)
{
    if (w->tmx < w->tmy) {
        w->t = w->tmx;
        w->tmx += w->tdx;
        w->ix += w->sx;
        w->axis = 0;
        if (w->ix < 0 || w->ix >= w->nx) {
            return false;
        }
    } else {
        w->t = w->tmy;
        w->tmy += w->tdy;
        w->iy += w->sy;
        w->axis = 1;
        if (w->iy < 0 || w->iy >= w->ny) {
            return false;
        }
    }
    return w->t <= w->t1;
}

/**
 * A ray through the raster (grid DDA); INFINITY when nothing is hit within max_m.
 * @param normal  out (may be NULL): the surface's unit normal at the hit (either side), as
 *                *cosi takes it; two doubles
 */
double room_hit_raster(const room_t *r, double ox, double oy, double dx, double dy, double max_m,
                       double *cosi, double *normal);

/* ---- the spatial index of a room's objects (room_index.c) ----------------------------- */

/** Rooms with fewer objects (segments, circles, boxes) than this get no index. */
#define ROOM_INDEX_MIN 64u

/**
 * A uniform grid over the room's bounding box; each cell lists the objects that pass
 * through it or within a hair of it: segment i as i, circle i as nsegs + i, box i as
 * nsegs + ncircles + i. Its size grows with the number of objects and their length, not
 * with the room's area.
 */
typedef struct room_index {
    double x0, y0;    /**< lower-left corner of cell (0, 0), m */
    double cell, inv; /**< cell side, m, and its inverse */
    uint32_t nx, ny;  /**< cells along x and y */
    uint32_t *start;  /**< the items of cell (a, b) are items[start[c] .. start[c + 1]),
                           c = b·nx + a */
    uint32_t *items;
    size_t nitems;
    /* A bounding-box tree over the segments and circles, for the nearest of them: a
     * uniform grid sized for the file holds every object of a dense crowd of long walls in
     * each cell, and one sized for tiny objects makes a clearance look at thousands of
     * empty cells; the tree costs a few boxes and objects per query either way. */
    struct room_bvh_node *nodes; /**< node 0 the root; NULL when there are no segments or circles */
    uint32_t *leaf_ids;          /**< the objects of the leaves, in tree order */
} room_index_t;

/** Build r->index when the room has ROOM_INDEX_MIN objects or more (else NULL); -1: no memory. */
int room_index_build(room_t *r);

/** Free r->index. */
void room_index_free(room_t *r);

/** Entries of the index (0 without one): for tests of its size. */
size_t room_index_entries(const room_t *r);

/** Objects indexed queries have looked at since the program started: for tests of cost. */
uint64_t room_index_examined(void);

/** The range of index cells that covers [x0, x1] × [y0, y1], clamped to the grid. */
void room_index_cells(const room_t *r, double x0, double y0, double x1, double y1, uint32_t *a0,
                      uint32_t *a1, uint32_t *b0, uint32_t *b1);

/** The objects of index cell (a, b): *n of them. */
const uint32_t *room_index_cell(const room_t *r, uint32_t a, uint32_t b, size_t *n);

/**
 * The segments and circles (circle i as nsegs + i) in the index cells that cover
 * [x0, x1] × [y0, y1], each once, in ascending order, into @p out.
 * @param stamp      one mark per segment and circle, owned by the caller (zeroed at first)
 * @param stamp_now  the caller's count of gathers
 * @return how many
 */
size_t room_index_gather(const room_t *r, double x0, double y0, double x1, double y1,
                         uint32_t *stamp, uint32_t *stamp_now, uint32_t *out);

/**
 * The nearest circle (signed distance to its outline, < 0 inside) and segment (squared
 * distance) near (x, y), for room_clearance(): what it makes of them, min(cap, circle,
 * √segment), is that of a look at every object. An object that cannot come nearer than
 * that (farther than cap, or than a nearer one) may be left out of either figure, each
 * INFINITY when none is found; with cap 0 only the box test is made.
 * @return 1 when the point lies in a solid box (nothing else is set), else 0
 */
int room_index_near(const room_t *r, double x, double y, double cap, double *circle_d,
                    double *seg_d2);

/**
 * Whether a segment other than segment @p self passes nearer than √d2 to (x, y): the same
 * answer as a look at every segment (room_seg_dist2() < d2), from the index's tree.
 */
bool room_index_seg_near(const room_t *r, double x, double y, double d2, uint32_t self);

/**
 * room_ray()'s segments and circles through the index: the nearest hit, or INFINITY.
 * @param id  out (may be NULL): the object hit, as the index numbers it (segment i as i,
 *            circle i as nsegs + i); set only with a hit
 */
double room_index_ray(const room_t *r, double ox, double oy, double dx, double dy, double max_m,
                      double *cosi, uint32_t *id);

#endif /* HOST_ROOM_INTERNAL_H */
