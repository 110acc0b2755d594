/* SPDX-License-Identifier: MIT */
/* The simulated HC-SR04s: each one's cone cast into the room, what comes back and when. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

/*
 * The model's parameters: sim_params_t's sonar_* (mount, cone, range limits, timeout),
 * sound_mps and sonar_ring_us; sim_errors_t's sonar_noise_m, sonar_dropout, sonar_ghost,
 * the incidence limit (grazing_deg or grazing_curve) and multipath (the echo_stuck fault
 * is sim_faults.c's, the mirror paths sim_multipath.c's). What the model derives from
 * them lives in sim_sonar_t (sim_internal.h), set by sim_sonar_init(). Sonar 0 is the
 * paper's, on servo 0 at (sonar_x_m, sonar_y_m); the others sit where the rows of
 * sim_params_t.extra_sonar put them, each with a random stream and a ping of its own.
 */

/* Every this many rays of the cone (the edges among them) follow their mirror path when
 * they meet a surface beyond its limit: neighbouring rays take nearly the same path. */
#define SIM_MULTIPATH_STRIDE 4

/* The cone of a ping: its apex, the unit vectors of its axis and edges, its reach. */
typedef struct {
    double ox, oy, bx, by, lx, ly, rx, ry, max;
} cone_t;

/* The uniforms one ping draws, whatever becomes of it. */
typedef struct {
    double drop, ghost, range, g1, g2;
} ping_draws_t;

/* The curve's limit at a range, deg: straight lines between knots, flat beyond the ends. */
static double curve_deg(const sim_grazing_curve_t *c, double range_m)
{
    if (range_m <= c->range_m[0]) {
        return c->deg[0];
    }
    for (uint32_t i = 1; i < c->n; i++) {
        if (range_m <= c->range_m[i]) {
            double f = (range_m - c->range_m[i - 1u]) / (c->range_m[i] - c->range_m[i - 1u]);
            return c->deg[i - 1u] + f * (c->deg[i] - c->deg[i - 1u]);
        }
    }
    return c->deg[c->n - 1u];
}

/* The limit as |cos| of the incidence, by bins of the sonar's reach: one cosine per bin,
 * at its middle, so a hit costs a look-up. A flat limit is the same cosine everywhere; no
 * limit is 0, which every |cos| passes. */
static void limit_table(sim_sonar_t *so, const sim_errors_t *e, double max_m)
{
    const sim_grazing_curve_t *c = &e->grazing_curve;
    double flat = e->grazing_deg > 0.0 ? cos(e->grazing_deg * SIM_DEG) : 0.0;
    so->limit_per_m = (double)SIM_LIMIT_BINS / max_m;
    so->limit_flat = c->n == 0u;
    for (unsigned i = 0; i <= SIM_LIMIT_BINS; i++) {
        so->cos_limit[i] =
            c->n > 0u ? cos(curve_deg(c, ((double)i + 0.5) / so->limit_per_m) * SIM_DEG) : flat;
    }
}

/* Sonar i's mount: the paper's, or a row of the instance table. */
static void sonar_mount(const sim_params_t *p, unsigned i, sim_sonar_t *so)
{
    so->index = i;
    if (i == 0u) {
        so->mx = p->sonar_x_m;
        so->my = p->sonar_y_m;
        so->servo = 0;
        so->yaw_deg = 0.0;
    } else {
        const sim_sonar_mount_t *m = &p->extra_sonar[i - 1u];
        so->mx = m->x_m;
        so->my = m->y_m;
        so->servo = (int)m->servo;
        so->yaw_deg = m->yaw_deg;
    }
    so->turned = so->yaw_deg != 0.0;
    so->yc = cos(so->yaw_deg * SIM_DEG);
    so->ys = sin(so->yaw_deg * SIM_DEG);
}

static int sonar_init(sim_t *s, sim_sonar_t *so, unsigned i, uint64_t seed)
{
    const sim_params_t *p = &s->p;
    const room_t *room = s->room;
    sonar_mount(p, i, so);
    size_t nobj = room->nsegs + room->ncircles + 1u;
    so->cand = malloc(nobj * sizeof *so->cand);
    if (room->index != NULL) {
        so->near = malloc(nobj * sizeof *so->near);
        so->stamp = calloc(nobj, sizeof *so->stamp);
    }
    if (so->cand == NULL || (room->index != NULL && (so->near == NULL || so->stamp == NULL)) ||
        sim_multipath_init(s, so) != 0) {
        return -1;
    }
    sim_rng_seed(&so->rng, seed, i == 0u ? SIM_STREAM_SONAR : SIM_STREAM_SONARS + (uint64_t)i);
    limit_table(so, &s->e, p->sonar_max_m);
    double half = 0.5 * p->sonar_cone_deg * SIM_DEG;
    double step = SIM_SONAR_RAYS > 1 ? 2.0 * half / (SIM_SONAR_RAYS - 1) : 0.0;
    so->cone_c = cos(half);
    so->cone_s = sin(half);
    so->ray_c = cos(step);
    so->ray_s = sin(step);
    /* The sound of one traced ray stands for its share of the cone, and comes back as
       wide: half the angle between two traced rays either side. */
    so->catch_tan = tan(0.5 * SIM_MULTIPATH_STRIDE * step);
    for (unsigned k = 0; k < SIM_BEAM_CACHE; k++) {
        so->beam[k].deg = (double)NAN; /* matches no angle */
    }
    return 0;
}

int sim_sonar_init(sim_t *s, uint64_t seed)
{
    s->nsonars = 1u + s->p.extra_sonars;
    for (unsigned i = 0; i < s->nsonars; i++) {
        if (sonar_init(s, &s->sonar[i], i, seed) != 0) {
            return -1;
        }
    }
    return 0;
}

void sim_sonar_free(sim_t *s)
{
    for (unsigned i = 0; i < SIM_SONARS_MAX; i++) {
        free(s->sonar[i].cand);
        free(s->sonar[i].near);
        free(s->sonar[i].stamp);
        free(s->sonar[i].lines);
    }
}

uint8_t sim_sonar_count(const sim_t *s)
{
    return (uint8_t)s->nsonars;
}

sim_ping_t sim_last_ping(const sim_t *s)
{
    return s->sonar[0].ping;
}

sim_ping_t sim_last_ping_on(const sim_t *s, uint8_t sonar)
{
    return sonar < s->nsonars ? s->sonar[sonar].ping : (sim_ping_t){.kind = SIM_PING_NONE};
}

void sim_ping_counts(const sim_t *s, uint32_t counts[SIM_PING_KINDS])
{
    memcpy(counts, s->sonar[0].counts, sizeof s->sonar[0].counts);
}

/* ---- the cone ------------------------------------------------------------------------------ */

/* The beam's rotation from the robot's heading at a servo angle, cached: the entry to use. */
static unsigned beam_at(sim_sonar_t *so, double servo_deg)
{
    unsigned bi = 0;
    while (bi < SIM_BEAM_CACHE && so->beam[bi].deg != servo_deg) {
        bi++;
    }
    if (bi == SIM_BEAM_CACHE) {
        bi = so->beam_next;
        so->beam_next = (so->beam_next + 1u) % SIM_BEAM_CACHE;
        so->beam[bi].deg = servo_deg;
        so->beam[bi].c = cos((90.0 - servo_deg) * SIM_DEG);
        so->beam[bi].s = sin((90.0 - servo_deg) * SIM_DEG);
    }
    return bi;
}

/* The cone now: from the sensor on its mount, along the beam of its servo's actual angle
 * (turned by its yaw), or of its yaw alone when it is fixed. */
static cone_t cone_now(sim_t *s, sim_sonar_t *so)
{
    const sim_params_t *p = &s->p;
    double ch = s->body.hc;
    double sh = s->body.hs;
    double ox = s->body.x + so->mx * ch - so->my * sh;
    double oy = s->body.y + so->mx * sh + so->my * ch;
    double c = so->yc; /* the beam's rotation from the heading */
    double sn = so->ys;
    if (so->servo >= 0) {
        unsigned bi = beam_at(so, s->servo[so->servo].deg);
        c = so->beam[bi].c;
        sn = so->beam[bi].s;
        if (so->turned) {
            double tc = c * so->yc - sn * so->ys;
            sn = sn * so->yc + c * so->ys;
            c = tc;
        }
    }
    /* Beam axis (Eq. 3) and the cone's edges, by rotating unit vectors. */
    double bx = ch * c - sh * sn;
    double by = sh * c + ch * sn;
    double lx = bx * so->cone_c - by * so->cone_s; /* left edge */
    double ly = by * so->cone_c + bx * so->cone_s;
    double rx = bx * so->cone_c + by * so->cone_s; /* right edge */
    double ry = by * so->cone_c - bx * so->cone_s;
    return (cone_t){ox, oy, bx, by, lx, ly, rx, ry, p->sonar_max_m};
}

/* A segment wholly left of the cone's left edge, right of its right edge, or behind the
 * sensor cannot meet it. */
static inline bool seg_misses(const cone_t *k, const room_segment_t *g)
{
    double q1x = g->x1 - k->ox;
    double q1y = g->y1 - k->oy;
    double q2x = g->x2 - k->ox;
    double q2y = g->y2 - k->oy;
    return (k->lx * q1y - k->ly * q1x > 0.0 && k->lx * q2y - k->ly * q2x > 0.0) ||
           (k->rx * q1y - k->ry * q1x < 0.0 && k->rx * q2y - k->ry * q2x < 0.0) ||
           (k->bx * q1x + k->by * q1y < 0.0 && k->bx * q2x + k->by * q2y < 0.0);
}

/* The same for a circle, and one beyond the reach. */
static inline bool circle_misses(const cone_t *k, const room_circle_t *c)
{
    double qx = c->cx - k->ox;
    double qy = c->cy - k->oy;
    return k->lx * qy - k->ly * qx > c->r || k->rx * qy - k->ry * qx < -c->r ||
           k->bx * qx + k->by * qy < -c->r || qx * qx + qy * qy > (k->max + c->r) * (k->max + c->r);
}

/* The segments and circles (as nsegs + i) near the cone, in ascending order (the order a
 * small room is looked at in), into so->near; returns how many. */
static size_t cone_objects(const room_t *r, sim_sonar_t *so, const cone_t *k)
{
    double ox = k->ox;
    double oy = k->oy;
    double max = k->max;
    /* The sector lies within the box of its apex, its edges' ends and its axis' end,
       grown by the arc's bulge beyond the chord. */
    double bulge = max * (1.0 - so->cone_c);
    double x0 = fmin(fmin(ox, ox + max * k->bx), fmin(ox + max * k->lx, ox + max * k->rx)) - bulge;
    double x1 = fmax(fmax(ox, ox + max * k->bx), fmax(ox + max * k->lx, ox + max * k->rx)) + bulge;
    double y0 = fmin(fmin(oy, oy + max * k->by), fmin(oy + max * k->ly, oy + max * k->ry)) - bulge;
    double y1 = fmax(fmax(oy, oy + max * k->by), fmax(oy + max * k->ly, oy + max * k->ry)) + bulge;
    return room_index_gather(r, x0, y0, x1, y1, so->stamp, &so->stamp_now, so->near);
}

/* Cull what cannot meet the cone into so->cand: *nseg segments, then *ncirc circles. A
 * large room offers only the objects near it. */
static void cone_candidates(const room_t *r, sim_sonar_t *so, const cone_t *k, size_t *nseg,
                            size_t *ncirc)
{
    size_t ns = 0u;
    size_t nc = 0u;
    if (r->index == NULL) {
        for (size_t i = 0; i < r->nsegs; i++) {
            if (!seg_misses(k, &r->segs[i])) {
                so->cand[ns++] = (uint32_t)i;
            }
        }
        for (size_t i = 0; i < r->ncircles; i++) {
            if (!circle_misses(k, &r->circles[i])) {
                so->cand[ns + nc++] = (uint32_t)i;
            }
        }
    } else {
        size_t n = cone_objects(r, so, k);
        for (size_t j = 0; j < n; j++) { /* ascending: every segment before any circle */
            uint32_t id = so->near[j];
            if (id < r->nsegs) {
                if (!seg_misses(k, &r->segs[id])) {
                    so->cand[ns++] = id;
                }
            } else if (!circle_misses(k, &r->circles[id - r->nsegs])) {
                so->cand[ns + nc++] = (uint32_t)(id - r->nsegs);
            }
        }
    }
    *nseg = ns;
    *ncirc = nc;
}

/* The first hit along one ray among the cone's candidates. */
static double cone_ray(const sim_t *s, const sim_sonar_t *so, size_t nseg, size_t ncirc, double ox,
                       double oy, double dx, double dy, double *cosi)
{
    const room_t *r = s->room;
    const uint32_t *cand = so->cand;
    double best = HOST_INF;
    for (size_t i = 0; i < nseg; i++) {
        best = room_hit_segment(&r->segs[cand[i]], ox, oy, dx, dy, best, cosi);
    }
    for (size_t i = 0; i < ncirc; i++) {
        best = room_hit_circle(&r->circles[cand[nseg + i]], ox, oy, dx, dy, best, cosi);
    }
    if (r->occ != NULL) {
        double rc = 1.0;
        double d = room_hit_raster(r, ox, oy, dx, dy, sim_dmin(s->p.sonar_max_m, best), &rc, NULL);
        if (d < best) {
            best = d;
            *cosi = rc;
        }
    }
    return best;
}

/* A ray of the cone whose first surface it met beyond the incidence it answers at. */
typedef struct {
    double dx, dy;
    sim_surface_t first;
} graze_t;

/*
 * The echoes of the rays that met a surface beyond its limit: each follows its mirror path,
 * the nearest first; one whose first hit is no nearer than the best echo so far cannot
 * come back sooner (a mirror path is at least as long as its first leg, up to a miss of
 * the receiver's width) and is not followed. Returns the nearest such echo's range, or
 * infinity.
 */
static double graze_echoes(const sim_t *s, const sim_sonar_t *so, const cone_t *k, graze_t *gz,
                           int n, double best)
{
    double mp = HOST_INF;
    for (int i = 1; i < n; i++) { /* nearest first: a handful, insertion sort */
        graze_t g = gz[i];
        int j = i;
        for (; j > 0 && gz[j - 1].first.t > g.first.t; j--) {
            gz[j] = gz[j - 1];
        }
        gz[j] = g;
    }
    for (int i = 0; i < n && gz[i].first.t < sim_dmin(best, mp); i++) {
        mp = sim_dmin(
            mp, sim_multipath(s, so, k->ox, k->oy, k->bx, k->by, gz[i].dx, gz[i].dy, &gz[i].first));
    }
    return mp;
}

/*
 * Cast the cone's rays: across it (edges included) and straight at every round obstacle
 * whose centre is inside it, so a thin post is not missed between two rays. A ray's first
 * hit echoes when it is within range and hit at an incidence the surface answers at, at
 * that range (sim_sonar_limit()). Occlusion is the rays': a grazing wall in front hides
 * what is behind it along that ray; with multipath on, the sound of a ray that meets a
 * surface beyond its limit reflects on (graze_echoes()), every SIM_MULTIPATH_STRIDE-th.
 * @param geo   out: the nearest surface in the cone, m; infinity for none in range
 * @param echo  out: the nearest surface that echoes, or the nearest mirror path's range,
 *              m; infinity for none
 * @return whether the echo came by a mirror path
 */
static bool cone_cast(const sim_t *s, const sim_sonar_t *so, const cone_t *k, size_t nseg,
                      size_t ncirc, double *geo, double *echo)
{
    const room_t *r = s->room;
    const double ox = k->ox;
    const double oy = k->oy;
    const double max = k->max;
    double g = HOST_INF;
    double e = HOST_INF;
    const double cs = so->ray_c;
    const double ss = so->ray_s;
    double dx = k->rx;
    double dy = k->ry;
    const bool mirror = s->e.multipath > 0u;
    graze_t gz[SIM_SONAR_RAYS];
    int ngz = 0;
    for (int i = 0; i < SIM_SONAR_RAYS + (int)ncirc; i++) {
        if (i >= SIM_SONAR_RAYS) { /* straight at a post */
            const room_circle_t *c = &r->circles[so->cand[nseg + (size_t)(i - SIM_SONAR_RAYS)]];
            double qx = c->cx - ox;
            double qy = c->cy - oy;
            double n = sqrt(qx * qx + qy * qy);
            if (n <= c->r || k->lx * qy - k->ly * qx > 0.0 || k->rx * qy - k->ry * qx < 0.0 ||
                k->bx * qx + k->by * qy <= 0.0) {
                continue;
            }
            dx = qx / n;
            dy = qy / n;
        }
        bool traced = mirror && i < SIM_SONAR_RAYS && i % SIM_MULTIPATH_STRIDE == 0;
        double ci = 1.0;
        double d;
        if (traced) { /* the surface too, for its mirror */
            gz[ngz].first = sim_surface(s, so, ox, oy, dx, dy, max, true, nseg, ncirc);
            d = gz[ngz].first.t;
            ci = gz[ngz].first.cosi;
        } else {
            d = cone_ray(s, so, nseg, ncirc, ox, oy, dx, dy, &ci);
        }
        if (d <= max) {
            g = sim_dmin(g, d);
            if (ci >= (so->limit_flat ? so->cos_limit[0] : sim_sonar_limit(so, d))) {
                e = sim_dmin(e, d);
            } else if (traced) {
                gz[ngz].dx = dx;
                gz[ngz++].dy = dy;
            }
        }
        if (i < SIM_SONAR_RAYS) { /* rotate to the next ray */
            double nx = dx * cs - dy * ss;
            dy = dx * ss + dy * cs;
            dx = nx;
        }
    }
    double mp = ngz > 0 ? graze_echoes(s, so, k, gz, ngz, e) : HOST_INF;
    *geo = g;
    *echo = sim_dmin(e, mp);
    return mp < e;
}

/* ---- what comes back ------------------------------------------------------------------------ */

/* The same draws whatever happens, so one ping's fate never shifts the next one's. */
static ping_draws_t ping_draws(sim_sonar_t *so)
{
    ping_draws_t u;
    u.drop = sim_rng_unit(&so->rng);
    u.ghost = sim_rng_unit(&so->rng);
    u.range = sim_rng_unit(&so->rng);
    u.g1 = sim_rng_unit(&so->rng);
    u.g2 = sim_rng_unit(&so->rng);
    return u;
}

/*
 * What the sensor makes of the cone: a dropout, a ghost at a random range, the nearest
 * echo (a surface's, or a mirror path's when @p mirrored) with range noise, or a timeout
 * (grazing, or nothing in range); a stuck echo line (sonar 0's: the fault's) times out
 * whatever came. Sets ping->kind; returns the range the echo stands for, m (0 without one).
 */
static double ping_fate(const sim_t *s, const sim_sonar_t *so, sim_ping_t *pg, double geo,
                        double echo, bool mirrored, const ping_draws_t *u)
{
    const sim_params_t *p = &s->p;
    double max = p->sonar_max_m;
    double range = 0.0;
    if (u->drop < s->e.sonar_dropout) {
        pg->kind = SIM_PING_DROPOUT;
    } else if (u->ghost < s->e.sonar_ghost) {
        pg->kind = SIM_PING_GHOST;
        range = p->sonar_min_m + u->range * (max - p->sonar_min_m);
    } else if (isfinite(echo)) {
        pg->kind = mirrored ? SIM_PING_MULTIPATH : SIM_PING_ECHO;
        range = echo;
        if (s->e.sonar_noise_m > 0.0) {
            range += s->e.sonar_noise_m * sim_rng_gauss_from(u->g1, u->g2);
        }
        range = range > p->sonar_min_m ? range : p->sonar_min_m;
    } else {
        pg->kind = isfinite(geo) ? SIM_PING_GRAZING : SIM_PING_NOTHING;
    }
    if (so->index == 0u && sim_fault_on(s, SIM_FAULT_ECHO)) {
        pg->kind = SIM_PING_STUCK; /* the line is high before the echo could come */
    }
    return range;
}

/*
 * The late echo of the last ping heard by a ping triggered now, µs after the trigger, or
 * infinity. A ping's sound bounces between the sensor and the surface it echoed from and
 * comes back at every multiple of its round trip w, audible until ring_us after its
 * trigger. A trigger sooner than that hears the next return still to come (the first, the
 * echo itself, has come by then unless a ghost or a late echo ended the last reading).
 */
static double late_echo_us(const sim_t *s, const sim_sonar_t *so)
{
    uint64_t since = s->time_us - so->ring_from_us;
    if (so->ring_us == 0u || (double)since >= s->p.sonar_ring_us) {
        return HOST_INF;
    }
    uint64_t k = since / so->ring_us + 1u; /* the first return after now */
    double at = (double)(k * so->ring_us);
    return at < s->p.sonar_ring_us ? at - (double)since : HOST_INF;
}

/*
 * When the ping's result is due, and what it reports: its own echo after the time of
 * flight, the last ping's late echo if that comes sooner, or the timeout. Then this ping's
 * sound starts ringing from the nearest surface that returns it, whatever the sensor made
 * of it (a dropout loses the echo, not the sound).
 */
static void ping_schedule(sim_t *s, sim_sonar_t *so, sim_ping_t *pg, double echo, double range)
{
    const sim_params_t *p = &s->p;
    so->out = true;
    so->echo =
        pg->kind == SIM_PING_ECHO || pg->kind == SIM_PING_MULTIPATH || pg->kind == SIM_PING_GHOST;
    double width = so->echo ? 2.0 * range / p->sound_mps * 1e6 : HOST_INF;
    double late = late_echo_us(s, so);
    if (late < width && late < p->sonar_timeout_us) {
        pg->kind = SIM_PING_LATE;
        so->echo = true;
        width = sim_dmax(late, 2.0 * p->sonar_min_m / p->sound_mps * 1e6);
        range = width * 1e-6 * p->sound_mps / 2.0;
    }
    if (so->echo) {
        pg->range_m = range;
        pg->echo_us = (uint32_t)lround(sim_dmin(width, p->sonar_timeout_us - 1.0));
        so->ready_us = s->time_us + pg->echo_us;
    } else {
        so->ready_us = s->time_us + (uint64_t)llround(p->sonar_timeout_us);
    }
    so->ring_from_us = s->time_us;
    so->ring_us = isfinite(echo) ? (uint32_t)lround(2.0 * echo / p->sound_mps * 1e6) : 0u;
}

/* The servo angle of a ping: its servo's, or the one that would point a fixed sonar so. */
static double ping_servo_deg(const sim_t *s, const sim_sonar_t *so)
{
    return so->servo >= 0 ? s->servo[so->servo].deg : 90.0 - so->yaw_deg;
}

/* The beam's world direction at a ping, rad (Eq. 3, turned by the mount's yaw). */
static double ping_bearing(const sim_t *s, const sim_sonar_t *so)
{
    double rel_deg = 90.0 - ping_servo_deg(s, so);
    if (so->turned && so->servo >= 0) {
        rel_deg += so->yaw_deg;
    }
    return sim_wrap_pi(s->body.th + rel_deg * SIM_DEG);
}

/* One ping: cast the cone now, decide what comes back and when. */
static void sonar_ping(sim_t *s, sim_sonar_t *so)
{
    const cone_t cone = cone_now(s, so);
    size_t nseg = 0u;
    size_t ncirc = 0u;
    cone_candidates(s->room, so, &cone, &nseg, &ncirc);
    double geo = HOST_INF;
    double echo = HOST_INF;
    bool mirrored = cone_cast(s, so, &cone, nseg, ncirc, &geo, &echo);
    const ping_draws_t u = ping_draws(so);

    sim_ping_t *pg = &so->ping;
    *pg = (sim_ping_t){
        .x = s->body.x,
        .y = s->body.y,
        .th = s->body.th,
        .servo_deg = ping_servo_deg(s, so),
        .bearing = ping_bearing(s, so),
        .true_range_m = isfinite(geo) ? geo : -1.0,
        .time_us = s->time_us,
    };
    double range = ping_fate(s, so, pg, geo, echo, mirrored, &u);
    ping_schedule(s, so, pg, echo, range);
    so->counts[pg->kind]++;
}

/* ---- the wire: trigger and echo ------------------------------------------------------------- */

int sim_sonar_trigger_on(sim_t *s, uint8_t sonar)
{
    if (sonar >= s->nsonars) {
        return HAL_EINVAL;
    }
    sim_sonar_t *so = &s->sonar[sonar];
    if (so->out && s->time_us < so->ready_us) {
        return HAL_EBUSY;
    }
    /* A finished but unread result is overwritten, as the sensor would. */
    sonar_ping(s, so);
    return HAL_OK;
}

int sim_sonar_poll_on(sim_t *s, uint8_t sonar, uint32_t *echo_us)
{
    if (sonar >= s->nsonars) {
        return HAL_EINVAL;
    }
    sim_sonar_t *so = &s->sonar[sonar];
    if (!so->out) {
        return HAL_SONAR_IDLE;
    }
    if (s->time_us < so->ready_us) {
        return HAL_SONAR_BUSY;
    }
    so->out = false;
    if (so->echo) {
        *echo_us = so->ping.echo_us;
        return HAL_SONAR_ECHO;
    }
    return HAL_SONAR_TIMEOUT;
}

int sim_sonar_trigger(sim_t *s)
{
    return sim_sonar_trigger_on(s, 0u);
}

hal_sonar_status_t sim_sonar_poll(sim_t *s, uint32_t *echo_us)
{
    return (hal_sonar_status_t)sim_sonar_poll_on(s, 0u, echo_us);
}
