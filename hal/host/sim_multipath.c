/* SPDX-License-Identifier: MIT */
/* The simulated HC-SR04's multipath: the sound of a ray a surface does not answer, reflected on. */
#include <math.h>
#include <stdlib.h>

#include "sim_internal.h"

/*
 * A surface met beyond the incidence it answers at still reflects the sound, as a mirror
 * does (beyond its limit a turned target mostly reads a long, wrong range: the UNIVPM
 * series of hal/host/README.md). The reflected ray goes on until
 *   - it meets a surface that answers it (its incidence within the limit at the path's
 *     length so far): that surface sends the sound back the way it came, and the mirrors
 *     return it to the sensor (a path is the same both ways); the echo reads the one-way
 *     path, half the round trip;
 *   - or, after a reflection, it comes back past the sensor from within the cone, nearer
 *     than its own spread (catch_tan of the path): the receiver hears it, and the echo
 *     reads half the path to there. Two walls at a right angle return every ray this way
 *     (a corner reflector), and a corner reads about its own distance, as real ones do;
 *   - or it has reflected e.multipath times, or would read beyond the sensor's reach (an
 *     answer farther than sonar_max_m, a round trip longer than twice it): the sound is
 *     lost (a timeout, as the data's no-echo readings).
 * No random draw is taken: the path follows from the geometry alone.
 */

/* A segment as a line: unit normal n and n·p on it, unit tangent t and t·p from its first
 * end to its second. A ray meets it in a division and two dot products. */
struct sim_line {
    double nx, ny, c;
    double tx, ty, u0, u1;
};

int sim_multipath_init(const sim_t *s, sim_sonar_t *so)
{
    const room_t *r = s->room;
    if (s->e.multipath == 0u || r->index != NULL || r->nsegs == 0u) {
        return 0;
    }
    struct sim_line *l = malloc(r->nsegs * sizeof *l);
    if (l == NULL) {
        return -1;
    }
    for (size_t i = 0; i < r->nsegs; i++) {
        const room_segment_t *g = &r->segs[i];
        double ex = g->x2 - g->x1;
        double ey = g->y2 - g->y1;
        double n = sqrt(ex * ex + ey * ey);
        l[i] = (struct sim_line){-ey / n, ex / n, 0.0, ex / n, ey / n, 0.0, 0.0};
        l[i].c = l[i].nx * g->x1 + l[i].ny * g->y1;
        l[i].u0 = l[i].tx * g->x1 + l[i].ty * g->y1;
        l[i].u1 = l[i].tx * g->x2 + l[i].ty * g->y2;
    }
    so->lines = l;
    return 0;
}

/* The distance along a ray to line @p l when it meets it nearer than @p best (and |cos|
 * of the incidence into *cosi), else best. */
static inline double line_hit(const struct sim_line *l, double ox, double oy, double dx, double dy,
                              double best, double *cosi)
{
    double dn = l->nx * dx + l->ny * dy;
    double t = (l->c - l->nx * ox - l->ny * oy) / dn; /* parallel: ±inf or NaN, refused */
    if (!(t >= 0.0 && t < best)) {
        return best;
    }
    double u = l->tx * (ox + t * dx) + l->ty * (oy + t * dy);
    if (u < l->u0 || u > l->u1) {
        return best;
    }
    *cosi = fabs(dn);
    return t;
}

sim_surface_t sim_surface(const sim_t *s, const sim_sonar_t *so, double ox, double oy, double dx,
                          double dy, double max_m, bool cone, size_t nseg, size_t ncirc)
{
    const room_t *r = s->room;
    const uint32_t *cand = so->cand;
    const struct sim_line *lines = so->lines;
    sim_surface_t h = {HOST_INF, 1.0, UINT32_MAX, 0.0, 0.0};
    double t = HOST_INF;
    if (cone) {
        for (size_t i = 0; i < nseg; i++) {
            double u = lines != NULL
                           ? line_hit(&lines[cand[i]], ox, oy, dx, dy, t, &h.cosi)
                           : room_hit_segment(&r->segs[cand[i]], ox, oy, dx, dy, t, &h.cosi);
            h.id = u < t ? cand[i] : h.id;
            t = u;
        }
        for (size_t i = 0; i < ncirc; i++) {
            uint32_t k = cand[nseg + i];
            double u = room_hit_circle(&r->circles[k], ox, oy, dx, dy, t, &h.cosi);
            h.id = u < t ? (uint32_t)r->nsegs + k : h.id;
            t = u;
        }
    } else if (r->index != NULL) {
        t = room_index_ray(r, ox, oy, dx, dy, max_m, &h.cosi, &h.id);
    } else { /* a mirror path in a small room: every object */
        for (uint32_t i = 0; i < (uint32_t)r->nsegs; i++) {
            double u = lines != NULL ? line_hit(&lines[i], ox, oy, dx, dy, t, &h.cosi)
                                     : room_hit_segment(&r->segs[i], ox, oy, dx, dy, t, &h.cosi);
            h.id = u < t ? i : h.id;
            t = u;
        }
        for (uint32_t i = 0; i < (uint32_t)r->ncircles; i++) {
            double u = room_hit_circle(&r->circles[i], ox, oy, dx, dy, t, &h.cosi);
            h.id = u < t ? (uint32_t)r->nsegs + i : h.id;
            t = u;
        }
    }
    if (r->occ != NULL) {
        double c = 1.0;
        double n[2] = {dx, dy};
        double u = room_hit_raster(r, ox, oy, dx, dy, sim_dmin(max_m, t), &c, n);
        if (u < t) {
            return (sim_surface_t){u, c, UINT32_MAX, n[0], n[1]};
        }
    }
    h.t = t <= max_m ? t : HOST_INF;
    return h;
}

/* The unit normal (either side) of the surface @p h met at (x, y). */
static void surface_normal(const room_t *r, const struct sim_line *lines, const sim_surface_t *h,
                           double x, double y, double *nx, double *ny)
{
    if (h->id == UINT32_MAX) {
        *nx = h->nx;
        *ny = h->ny;
    } else if (h->id < r->nsegs && lines != NULL) {
        *nx = lines[h->id].nx;
        *ny = lines[h->id].ny;
    } else if (h->id < r->nsegs) {
        const room_segment_t *g = &r->segs[h->id];
        double ex = g->x2 - g->x1;
        double ey = g->y2 - g->y1;
        double n = sqrt(ex * ex + ey * ey);
        *nx = -ey / n;
        *ny = ex / n;
    } else {
        const room_circle_t *c = &r->circles[h->id - r->nsegs];
        *nx = (x - c->cx) / c->r;
        *ny = (y - c->cy) / c->r;
    }
}

/*
 * Where along a leg from (ox, oy) in direction (dx, dy) the receiver hears it: the leg
 * comes back within the cone and passes the sensor (sx, sy) nearer than its own spread at
 * the path's length there; -1 when it does not. @p path: the path before the leg.
 */
static double heard_at(const sim_sonar_t *so, double sx, double sy, double bx, double by, double ox,
                       double oy, double dx, double dy, double path, double max)
{
    double vx = sx - ox;
    double vy = sy - oy;
    double along = vx * dx + vy * dy;
    double miss = vx * dy - vy * dx;
    double spread = (path + along) * so->catch_tan;
    return along > 0.0 && path + along <= 2.0 * max && -(dx * bx + dy * by) >= so->cone_c &&
                   miss * miss <= spread * spread
               ? along
               : -1.0;
}

double sim_multipath(const sim_t *s, const sim_sonar_t *so, double sx, double sy, double bx,
                     double by, double dx, double dy, const sim_surface_t *first)
{
    const double max = s->p.sonar_max_m;
    double ox = sx;
    double oy = sy;
    double path = 0.0; /* from the sensor to (ox, oy) */
    sim_surface_t h = *first;
    for (uint32_t bounce = 0;; bounce++) {
        if (!(h.t < 2.0 * max - path)) {
            return HOST_INF; /* nothing more within the reach: lost */
        }
        path += h.t;
        if (path <= max && h.cosi >= sim_sonar_limit(so, path)) {
            return path; /* answered: back the same way */
        }
        if (bounce == s->e.multipath) {
            return HOST_INF;
        }
        /* Reflect, from a hair before the surface (back along the ray, in free space). */
        double hx = ox + h.t * dx;
        double hy = oy + h.t * dy;
        double nx;
        double ny;
        surface_normal(s->room, so->lines, &h, hx, hy, &nx, &ny);
        double dn = dx * nx + dy * ny;
        ox = hx - 1e-6 * dx;
        oy = hy - 1e-6 * dy;
        dx -= 2.0 * dn * nx;
        dy -= 2.0 * dn * ny;
        double heard = heard_at(so, sx, sy, bx, by, ox, oy, dx, dy, path, max);
        if (heard < 0.0 && path >= max && bounce + 1u == s->e.multipath) {
            return HOST_INF; /* the last leg can neither be answered nor heard */
        }
        h = sim_surface(s, so, ox, oy, dx, dy, 2.0 * max - path, false, 0u, 0u);
        if (heard >= 0.0 && heard <= h.t) {
            return 0.5 * (path + heard); /* passes the receiver before the next surface */
        }
    }
}
