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

#include "host/sim.h"

/** π, which strict C11 does not define. */
#define HOST_PI 3.14159265358979323846

/** +∞ as a double (INFINITY is a float). */
#define HOST_INF ((double)INFINITY)

/** A ray parallel to a segment within this (|sin| of the angle) never hits it. */
#define ROOM_PARALLEL_EPS 1e-12

static inline double room_hit_segment(const room_segment_t *sg, double ox, double oy,
                                      double dx, double dy, double best, double *cosi)
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
    /* Divide only for a hit that beats the best so far. */
    if (nt < 0.0 || nu < 0.0 || nu > denom || nt >= best * denom) {
        return best;
    }
    *cosi = denom / sqrt(len2);
    return nt / denom;
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

/** Whether a point lies inside a solid box (its boundary included). */
static inline int room_in_box(const room_box_t *b, double x, double y)
{
    return x >= b->x0 && x <= b->x1 && y >= b->y0 && y <= b->y1;
}

/** A ray through the raster (grid DDA); INFINITY when nothing is hit within max_m. */
double room_hit_raster(const room_t *r, double ox, double oy, double dx, double dy,
                       double max_m, double *cosi);

#endif /* HOST_ROOM_INTERNAL_H */
