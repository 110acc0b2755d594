/* SPDX-License-Identifier: MIT */
/* The simulated robot: motors, wheels and encoders, collisions, the servo and the sonar. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "host/sim.h"
#include "room_internal.h"
#include "sim_rng.h"

#define DEG (HOST_PI / 180.0)
#define DT_S ((double)HAL_TICK_PERIOD_US * 1e-6)

/* Rays cast across the sonar cone, edges included. */
#define SIM_SONAR_RAYS 9
/* Clearance beyond the body looked for at once: the robot moves this far unchecked. */
#define SIM_MARGIN_CAP_M 0.25
/* The body leaves contact once this far from every obstacle (hysteresis). */
#define SIM_CONTACT_RELEASE_M 0.001
/* Bisections of a blocked step: 2^-14 of a 3 mm step is well below a micrometre. */
#define SIM_CONTACT_ITER 14
/* Slip never takes more than this fraction of a wheel's travel. */
#define SIM_SLIP_MAX 0.9

/* Servo angles whose beam rotation is kept (the sweep has 6 stops). */
#define SIM_BEAM_CACHE 16u
/* Resynchronise the heading's unit vector with its angle this often (moves). */
#define SIM_HEADING_RESYNC 256u

static inline double dmin(double a, double b)
{
    return a < b ? a : b;
}

static inline double dmax(double a, double b)
{
    return a > b ? a : b;
}

/*
 * cos and sin of a small angle (|x| <= 0.1 rad: the most a wheel turns the body in a tick
 * at ten times the default top speed) by their series (to x^7 and x^8), within 3e-15 of libm;
 * larger angles go to libm.
 */
static inline void small_sincos(double x, double *c, double *s)
{
    if (fabs(x) > 0.1) {
        *c = cos(x);
        *s = sin(x);
        return;
    }
    double x2 = x * x;
    *c = 1.0 - x2 * (1.0 / 2.0 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0 - x2 * (1.0 / 40320.0))));
    *s = x * (1.0 - x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0))));
}

/* Wrap an angle into (-pi, pi] (one turn at most away, as after a tick). */
static inline double wrap_pi(double a)
{
    if (a > HOST_PI) {
        a -= 2.0 * HOST_PI;
    } else if (a <= -HOST_PI) {
        a += 2.0 * HOST_PI;
    }
    return (a > HOST_PI || a <= -HOST_PI) ? remainder(a, 2.0 * HOST_PI) : a;
}

/* Independent random streams, so changing one error level leaves the others' draws. */
enum { STREAM_WHEELS = 1, STREAM_SONAR = 2, STREAM_FAULTS = 3 };

/* The fault episodes, each with its own stream (STREAM_FAULTS + its number). */
enum { FAULT_ECHO, FAULT_SERVO, FAULT_ENCODER, FAULT_TICK, FAULTS };

/* An episode lasts this long, uniform, s. */
#define SIM_EPISODE_MIN_S 0.5
#define SIM_EPISODE_MAX_S 3.0

struct sim {
    const room_t *room;
    sim_params_t p;
    sim_errors_t e;
    sim_rng_t rng_wheels;
    sim_rng_t rng_sonar;
    sim_rng_t rng_fault[FAULTS];
    uint64_t fault_until_us[FAULTS]; /* the episode under way ends then */
    bool faults;                     /* an episode fault is on: the tick looks at them */
    int stopped_wheel;               /* the encoder that stopped counting */
    uint64_t ticks_missed;

    /* Derived once. */
    double r_nom;            /* nominal wheel radius, m */
    double r_act[2];         /* actual wheel radii (E_d), m */
    double base_act;         /* actual wheel base (E_b), m */
    double counts_per_rad;   /* encoder counts per radian of wheel */
    double decay;            /* exp(-dt/tau): the motor's response over one tick */
    double gain;             /* tau·(1 - decay): weight of the speed error in a tick's travel */
    double servo_step_deg;   /* servo travel per tick */
    double cos_graze;        /* echoes need |cos incidence| >= this */
    double omega_per_duty;   /* wheel rad/s per unit of duty */
    double cone_c, cone_s;   /* cos, sin of half the cone */
    double ray_c, ray_s;     /* cos, sin of the angle between two rays */

    /* The robot. */
    double x, y, th;
    double hc, hs;           /* cos th, sin th, carried along with th */
    uint32_t moves;          /* since hc, hs were last computed from th */
    double omega[2];         /* wheel angular speeds, rad/s */
    double omega_cmd[2];     /* what the duty asks for, rad/s */
    int16_t duty[2];
    double enc[2];           /* wheel rotation the encoders counted, counts */

    /* Collisions: every point within `margin` of the anchor is known to be free. */
    double ax, ay, margin, margin2;
    bool contact;
    uint32_t collisions;

    /* Servo. */
    uint16_t servo_pulse;
    double servo_deg;
    double servo_cmd_deg;
    /* cos, sin of (90° - servo angle) for the last few servo angles pinged at: the
       sweep revisits the same stops. */
    struct {
        double deg, c, s;
    } beam[SIM_BEAM_CACHE];
    unsigned beam_next;      /* the entry to replace next */

    /* Sonar. */
    bool sonar_out;          /* a ping is out and not yet reported */
    bool sonar_echo;         /* it will report an echo (else a timeout) */
    uint64_t sonar_ready_us; /* when its echo or timeout is due */
    uint64_t ring_from_us;   /* the last ping's trigger time */
    uint32_t ring_us;        /* its sound's round trip to the surface it echoed from; 0: none */
    sim_ping_t ping;
    uint32_t *cand;          /* cone candidates: segment indices, then circle indices */
    uint32_t *near;          /* a large room's objects near the cone (room_t.index) */
    uint32_t *stamp;         /* per object: the cone_objects() call that last took it */
    uint32_t stamp_now;

    uint64_t time_us;
    uint64_t ticks;
};

void sim_params_default(sim_params_t *p)
{
    *p = (sim_params_t){
        .wheel_diameter_m = 0.065,
        .wheel_base_m = 0.130,
        .counts_per_rev = 700.0,
        .top_speed_mps = 0.3,
        .motor_tau_s = 0.08,
        .body_radius_m = 0.09,
        .sonar_x_m = 0.05,
        .sonar_y_m = 0.0,
        .servo_s_per_60deg = 0.1,
        .servo_pulse_0_us = 500.0,
        .servo_pulse_180_us = 2500.0,
        .sonar_cone_deg = 15.0,
        .sonar_min_m = 0.02,
        .sonar_max_m = 4.0,
        .sonar_timeout_us = 38000.0,
        .sound_mps = 343.0,
        .sonar_ring_us = 60000.0,
    };
}

/* The systematic errors are an uncalibrated hobby robot's (hal/host/README.md says from
 * what); the firmware's shipped calibration, host_sim/calibration/, is UMBmark's of them. */
void sim_errors_default(sim_errors_t *e)
{
    *e = (sim_errors_t){
        .wheel_ratio_ed = 1.005,
        .wheel_base_eb = 1.03,
        .slip_per_mps2 = 0.3,
        .slip_free_mps2 = 0.5,
        .wheel_noise = 0.01,
        .sonar_noise_m = 0.01,
        .sonar_dropout = 0.03,
        .sonar_ghost = 0.01,
        .grazing_deg = 45.0,
        .echo_stuck_per_s = 0.0,
        .servo_lag = 0.0,
        .servo_stall_per_s = 0.0,
        .tick_miss = 0.0,
        .encoder_stop_per_s = 0.0,
    };
}

void sim_errors_ideal(sim_errors_t *e)
{
    *e = (sim_errors_t){
        .wheel_ratio_ed = 1.0,
        .wheel_base_eb = 1.0,
        .slip_per_mps2 = 0.0,
        .slip_free_mps2 = 0.5,
        .wheel_noise = 0.0,
        .sonar_noise_m = 0.0,
        .sonar_dropout = 0.0,
        .sonar_ghost = 0.0,
        .grazing_deg = 0.0,
    };
}

static bool in(double v, double lo, double hi)
{
    return isfinite(v) && v >= lo && v <= hi;
}

int sim_params_check(const sim_params_t *p, const sim_errors_t *e, const char **field)
{
    const struct {
        bool ok;
        const char *name;
    } checks[] = {
        {in(p->wheel_diameter_m, 1e-3, 10.0), "p.wheel_diameter_m"},
        {in(p->wheel_base_m, 1e-3, 10.0), "p.wheel_base_m"},
        {in(p->counts_per_rev, 1.0, 1e6), "p.counts_per_rev"},
        {in(p->top_speed_mps, 1e-3, 10.0), "p.top_speed_mps"},
        {in(p->motor_tau_s, 1e-4, 10.0), "p.motor_tau_s"},
        {in(p->body_radius_m, 1e-3, 10.0), "p.body_radius_m"},
        {in(p->sonar_x_m, -10.0, 10.0), "p.sonar_x_m"},
        {in(p->sonar_y_m, -10.0, 10.0), "p.sonar_y_m"},
        {in(p->servo_s_per_60deg, 1e-4, 100.0), "p.servo_s_per_60deg"},
        {in(p->servo_pulse_0_us, 0.0, 1e5), "p.servo_pulse_0_us"},
        {in(p->servo_pulse_180_us, 0.0, 1e5) && p->servo_pulse_180_us != p->servo_pulse_0_us,
         "p.servo_pulse_180_us"},
        {in(p->sonar_cone_deg, 0.0, 89.0), "p.sonar_cone_deg"},
        {in(p->sonar_min_m, 0.0, 100.0), "p.sonar_min_m"},
        {in(p->sonar_max_m, p->sonar_min_m + 1e-6, 100.0), "p.sonar_max_m"},
        {in(p->sound_mps, 1.0, 1e5), "p.sound_mps"},
        /* The farthest echo must come back before the timeout. */
        {in(p->sonar_timeout_us, 1.0, 1e7) && isfinite(p->sound_mps) && p->sound_mps > 0.0 &&
             2.0 * p->sonar_max_m / p->sound_mps * 1e6 < p->sonar_timeout_us,
         "p.sonar_timeout_us"},
        {in(p->sonar_ring_us, 0.0, 1e7), "p.sonar_ring_us"},
        {in(e->wheel_ratio_ed, 0.5, 2.0), "e.wheel_ratio_ed"},
        {in(e->wheel_base_eb, 0.5, 2.0), "e.wheel_base_eb"},
        {in(e->slip_per_mps2, 0.0, 1.0), "e.slip_per_mps2"},
        {in(e->slip_free_mps2, 0.0, 100.0), "e.slip_free_mps2"},
        {in(e->wheel_noise, 0.0, 0.5), "e.wheel_noise"},
        {in(e->sonar_noise_m, 0.0, 10.0), "e.sonar_noise_m"},
        {in(e->sonar_dropout, 0.0, 1.0), "e.sonar_dropout"},
        {in(e->sonar_ghost, 0.0, 1.0), "e.sonar_ghost"},
        {in(e->grazing_deg, 0.0, 90.0), "e.grazing_deg"},
        {in(e->echo_stuck_per_s, 0.0, 10.0), "e.echo_stuck_per_s"},
        {in(e->servo_lag, 0.0, 0.95), "e.servo_lag"},
        {in(e->servo_stall_per_s, 0.0, 10.0), "e.servo_stall_per_s"},
        {in(e->tick_miss, 0.0, 0.9), "e.tick_miss"},
        {in(e->encoder_stop_per_s, 0.0, 10.0), "e.encoder_stop_per_s"},
    };
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; i++) {
        if (!checks[i].ok) {
            if (field != NULL) {
                *field = checks[i].name;
            }
            return -1;
        }
    }
    return 0;
}

sim_t *sim_create(const room_t *room, const sim_params_t *p, const sim_errors_t *e,
                  uint64_t seed)
{
    if (room == NULL || sim_params_check(p, e, NULL) != 0 ||
        !room_disc_free(room, room->start_x, room->start_y, p->body_radius_m)) {
        return NULL;
    }
    sim_t *s = calloc(1u, sizeof *s);
    if (s == NULL) {
        return NULL;
    }
    size_t nobj = room->nsegs + room->ncircles + 1u;
    s->cand = malloc(nobj * sizeof *s->cand);
    if (room->index != NULL) {
        s->near = malloc(nobj * sizeof *s->near);
        s->stamp = calloc(nobj, sizeof *s->stamp);
    }
    if (s->cand == NULL || (room->index != NULL && (s->near == NULL || s->stamp == NULL))) {
        sim_destroy(s);
        return NULL;
    }
    s->room = room;
    s->p = *p;
    s->e = *e;
    sim_rng_seed(&s->rng_wheels, seed, STREAM_WHEELS);
    sim_rng_seed(&s->rng_sonar, seed, STREAM_SONAR);
    for (int f = 0; f < FAULTS; f++) {
        sim_rng_seed(&s->rng_fault[f], seed, (uint64_t)(STREAM_FAULTS + f));
    }
    s->faults = e->echo_stuck_per_s > 0.0 || e->servo_stall_per_s > 0.0 ||
                e->encoder_stop_per_s > 0.0;

    /* E_d = D_R / D_L with the mean diameter nominal (Borenstein and Feng). */
    s->r_nom = 0.5 * p->wheel_diameter_m;
    s->r_act[HAL_WHEEL_LEFT] = s->r_nom * 2.0 / (e->wheel_ratio_ed + 1.0);
    s->r_act[HAL_WHEEL_RIGHT] = s->r_nom * 2.0 * e->wheel_ratio_ed / (e->wheel_ratio_ed + 1.0);
    s->base_act = p->wheel_base_m * e->wheel_base_eb;
    s->counts_per_rad = p->counts_per_rev / (2.0 * HOST_PI);
    s->decay = exp(-DT_S / p->motor_tau_s);
    s->gain = p->motor_tau_s * (1.0 - s->decay);
    s->servo_step_deg = 60.0 / p->servo_s_per_60deg * DT_S * (1.0 - e->servo_lag);
    s->cos_graze = e->grazing_deg > 0.0 ? cos(e->grazing_deg * DEG) : 0.0;
    s->omega_per_duty = p->top_speed_mps / HAL_DUTY_MAX / s->r_nom;
    double half = 0.5 * p->sonar_cone_deg * DEG;
    double step = SIM_SONAR_RAYS > 1 ? 2.0 * half / (SIM_SONAR_RAYS - 1) : 0.0;
    s->cone_c = cos(half);
    s->cone_s = sin(half);
    s->ray_c = cos(step);
    s->ray_s = sin(step);
    for (unsigned i = 0; i < SIM_BEAM_CACHE; i++) {
        s->beam[i].deg = (double)NAN; /* matches no angle */
    }

    s->x = room->start_x;
    s->y = room->start_y;
    s->th = remainder(room->start_th, 2.0 * HOST_PI);
    s->hc = cos(s->th);
    s->hs = sin(s->th);
    s->margin = -1.0;
    s->margin2 = -1.0;
    s->servo_deg = 90.0;
    s->servo_cmd_deg = 90.0;
    s->servo_pulse = (uint16_t)lround(0.5 * (p->servo_pulse_0_us + p->servo_pulse_180_us));
    return s;
}

void sim_destroy(sim_t *s)
{
    if (s != NULL) {
        free(s->cand);
        free(s->near);
        free(s->stamp);
        free(s);
    }
}

sim_truth_t sim_truth(const sim_t *s)
{
    return (sim_truth_t){
        .x = s->x,
        .y = s->y,
        .th = s->th,
        .servo_deg = s->servo_deg,
        .wheel_mps = {s->omega[0] * s->r_act[0], s->omega[1] * s->r_act[1]},
        .collisions = s->collisions,
        .ticks_missed = s->ticks_missed,
        .contact = s->contact,
        .time_us = s->time_us,
        .ticks = s->ticks,
    };
}

sim_ping_t sim_last_ping(const sim_t *s)
{
    return s->ping;
}

int sim_place(sim_t *s, double x, double y, double th)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(th) ||
        !room_disc_free(s->room, x, y, s->p.body_radius_m)) {
        return -1;
    }
    s->x = x;
    s->y = y;
    s->th = remainder(th, 2.0 * HOST_PI);
    s->hc = cos(s->th);
    s->hs = sin(s->th);
    s->moves = 0u;
    s->omega[0] = 0.0;
    s->omega[1] = 0.0;
    s->contact = false;
    s->margin = -1.0;
    s->margin2 = -1.0;
    return 0;
}

/* ---- wires ---------------------------------------------------------------------------- */

void sim_motor_set(sim_t *s, hal_wheel_t wheel, int16_t duty)
{
    if (wheel != HAL_WHEEL_LEFT && wheel != HAL_WHEEL_RIGHT) {
        return;
    }
    if (duty > HAL_DUTY_MAX) {
        duty = HAL_DUTY_MAX;
    } else if (duty < -HAL_DUTY_MAX) {
        duty = -HAL_DUTY_MAX;
    }
    s->duty[wheel] = duty;
    s->omega_cmd[wheel] = (double)duty * s->omega_per_duty;
}

int16_t sim_motor_duty(const sim_t *s, hal_wheel_t wheel)
{
    return wheel == HAL_WHEEL_RIGHT ? s->duty[1] : s->duty[0];
}

uint16_t sim_encoder_count(const sim_t *s, hal_wheel_t wheel)
{
    double c = s->enc[wheel == HAL_WHEEL_RIGHT ? 1 : 0];
    /* A quadrature counter counts edges: the floor of the true position, modulo 2^16. */
    int64_t n = (int64_t)c; /* toward zero; |c| stays far below 2^63 */
    if ((double)n > c) {
        n--;
    }
    return (uint16_t)(uint64_t)n;
}

void sim_servo_set_pulse(sim_t *s, uint16_t pulse_us)
{
    pulse_us = pulse_us < 400u ? 400u : (pulse_us > 2600u ? 2600u : pulse_us);
    s->servo_pulse = pulse_us;
    double deg = ((double)pulse_us - s->p.servo_pulse_0_us) /
                 (s->p.servo_pulse_180_us - s->p.servo_pulse_0_us) * 180.0;
    s->servo_cmd_deg = fmin(fmax(deg, 0.0), 180.0); /* the horn's end stops */
}

uint16_t sim_servo_pulse(const sim_t *s)
{
    return s->servo_pulse;
}

/* ---- the sonar ------------------------------------------------------------------------ */

/* The first hit along one ray among the cone's candidates. */
static double cone_ray(const sim_t *s, size_t nseg, size_t ncirc, double ox, double oy,
                       double dx, double dy, double *cosi)
{
    const room_t *r = s->room;
    double best = HOST_INF;
    for (size_t i = 0; i < nseg; i++) {
        best = room_hit_segment(&r->segs[s->cand[i]], ox, oy, dx, dy, best, cosi);
    }
    for (size_t i = 0; i < ncirc; i++) {
        best = room_hit_circle(&r->circles[s->cand[nseg + i]], ox, oy, dx, dy, best, cosi);
    }
    if (r->occ != NULL) {
        double rc = 1.0;
        double d = room_hit_raster(r, ox, oy, dx, dy, dmin(s->p.sonar_max_m, best), &rc);
        if (d < best) {
            best = d;
            *cosi = rc;
        }
    }
    return best;
}

/* The cone of a ping: its apex, the unit vectors of its axis and edges, its reach. */
typedef struct {
    double ox, oy, bx, by, lx, ly, rx, ry, max;
} cone_t;

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
           k->bx * qx + k->by * qy < -c->r ||
           qx * qx + qy * qy > (k->max + c->r) * (k->max + c->r);
}

/* The segments and circles (as nsegs + i) near the cone, in ascending order (the order a
 * small room is looked at in), into s->near; returns how many. */
static size_t cone_objects(sim_t *s, double ox, double oy, double bx, double by, double lx,
                           double ly, double rx, double ry, double max)
{
    const room_t *r = s->room;
    /* The sector lies within the box of its apex, its edges' ends and its axis' end,
       grown by the arc's bulge beyond the chord. */
    double bulge = max * (1.0 - s->cone_c);
    double x0 = fmin(fmin(ox, ox + max * bx), fmin(ox + max * lx, ox + max * rx)) - bulge;
    double x1 = fmax(fmax(ox, ox + max * bx), fmax(ox + max * lx, ox + max * rx)) + bulge;
    double y0 = fmin(fmin(oy, oy + max * by), fmin(oy + max * ly, oy + max * ry)) - bulge;
    double y1 = fmax(fmax(oy, oy + max * by), fmax(oy + max * ly, oy + max * ry)) + bulge;
    return room_index_gather(r, x0, y0, x1, y1, s->stamp, &s->stamp_now, s->near);
}

/*
 * The late echo of the last ping heard by a ping triggered now, µs after the trigger, or
 * infinity. A ping's sound bounces between the sensor and the surface it echoed from and
 * comes back at every multiple of its round trip w, audible until ring_us after its
 * trigger. A trigger sooner than that hears the next return still to come (the first, the
 * echo itself, has come by then unless a ghost or a late echo ended the last reading).
 */
static double late_echo_us(const sim_t *s)
{
    uint64_t since = s->time_us - s->ring_from_us;
    if (s->ring_us == 0u || (double)since >= s->p.sonar_ring_us) {
        return HOST_INF;
    }
    uint64_t k = since / s->ring_us + 1u; /* the first return after now */
    double at = (double)(k * s->ring_us);
    return at < s->p.sonar_ring_us ? at - (double)since : HOST_INF;
}

/*
 * One ping: cast the cone now, decide what comes back and when. Rays go across the cone
 * (edges included) and straight at every round obstacle whose centre is inside it, so a
 * thin post is not missed between two rays. A ray's first hit echoes when it is within
 * range and, unless grazing is off, hit at an incidence of at most grazing_deg; the echo
 * is the nearest of those. Occlusion is the rays': a grazing wall in front hides what is
 * behind it along that ray.
 */
static void sonar_ping(sim_t *s)
{
    const sim_params_t *p = &s->p;
    const room_t *r = s->room;
    double ch = s->hc;
    double sh = s->hs;
    double ox = s->x + p->sonar_x_m * ch - p->sonar_y_m * sh;
    double oy = s->y + p->sonar_x_m * sh + p->sonar_y_m * ch;
    unsigned bi = 0;
    while (bi < SIM_BEAM_CACHE && s->beam[bi].deg != s->servo_deg) {
        bi++;
    }
    if (bi == SIM_BEAM_CACHE) {
        bi = s->beam_next;
        s->beam_next = (s->beam_next + 1u) % SIM_BEAM_CACHE;
        s->beam[bi].deg = s->servo_deg;
        s->beam[bi].c = cos((90.0 - s->servo_deg) * DEG);
        s->beam[bi].s = sin((90.0 - s->servo_deg) * DEG);
    }
    /* Beam axis (Eq. 3) and the cone's edges, by rotating unit vectors. */
    double bx = ch * s->beam[bi].c - sh * s->beam[bi].s;
    double by = sh * s->beam[bi].c + ch * s->beam[bi].s;
    double lx = bx * s->cone_c - by * s->cone_s; /* left edge */
    double ly = by * s->cone_c + bx * s->cone_s;
    double rx = bx * s->cone_c + by * s->cone_s; /* right edge */
    double ry = by * s->cone_c - bx * s->cone_s;
    double max = p->sonar_max_m;

    /* Cull what cannot meet the cone; a large room offers only the objects near it. */
    const cone_t cone = {ox, oy, bx, by, lx, ly, rx, ry, max};
    size_t nseg = 0u;
    size_t ncirc = 0u;
    if (r->index == NULL) {
        for (size_t i = 0; i < r->nsegs; i++) {
            if (!seg_misses(&cone, &r->segs[i])) {
                s->cand[nseg++] = (uint32_t)i;
            }
        }
        for (size_t i = 0; i < r->ncircles; i++) {
            if (!circle_misses(&cone, &r->circles[i])) {
                s->cand[nseg + ncirc++] = (uint32_t)i;
            }
        }
    } else {
        size_t n = cone_objects(s, ox, oy, bx, by, lx, ly, rx, ry, max);
        for (size_t j = 0; j < n; j++) { /* ascending: every segment before any circle */
            uint32_t id = s->near[j];
            if (id < r->nsegs) {
                if (!seg_misses(&cone, &r->segs[id])) {
                    s->cand[nseg++] = id;
                }
            } else if (!circle_misses(&cone, &r->circles[id - r->nsegs])) {
                s->cand[nseg + ncirc++] = (uint32_t)(id - r->nsegs);
            }
        }
    }

    double geo = HOST_INF;  /* nearest surface in the cone */
    double echo = HOST_INF; /* nearest surface that echoes */
    const double cs = s->ray_c;
    const double ss = s->ray_s;
    double dx = rx;
    double dy = ry;
    for (int k = 0; k < SIM_SONAR_RAYS + (int)ncirc; k++) {
        if (k >= SIM_SONAR_RAYS) { /* straight at a post */
            const room_circle_t *c = &r->circles[s->cand[nseg + (size_t)(k - SIM_SONAR_RAYS)]];
            double qx = c->cx - ox;
            double qy = c->cy - oy;
            double n = sqrt(qx * qx + qy * qy);
            if (n <= c->r || lx * qy - ly * qx > 0.0 || rx * qy - ry * qx < 0.0 ||
                bx * qx + by * qy <= 0.0) {
                continue;
            }
            dx = qx / n;
            dy = qy / n;
        }
        double ci = 1.0;
        double d = cone_ray(s, nseg, ncirc, ox, oy, dx, dy, &ci);
        if (d <= max) {
            geo = dmin(geo, d);
            if (ci >= s->cos_graze) {
                echo = dmin(echo, d);
            }
        }
        if (k < SIM_SONAR_RAYS) { /* rotate to the next ray */
            double nx = dx * cs - dy * ss;
            dy = dx * ss + dy * cs;
            dx = nx;
        }
    }

    /* The same draws whatever happens, so one ping's fate never shifts the next one's. */
    double u_drop = sim_rng_unit(&s->rng_sonar);
    double u_ghost = sim_rng_unit(&s->rng_sonar);
    double u_range = sim_rng_unit(&s->rng_sonar);
    double u_g1 = sim_rng_unit(&s->rng_sonar);
    double u_g2 = sim_rng_unit(&s->rng_sonar);

    sim_ping_t *pg = &s->ping;
    *pg = (sim_ping_t){
        .x = s->x,
        .y = s->y,
        .th = s->th,
        .servo_deg = s->servo_deg,
        .bearing = wrap_pi(s->th + (90.0 - s->servo_deg) * DEG),
        .true_range_m = isfinite(geo) ? geo : -1.0,
        .time_us = s->time_us,
    };
    double range = 0.0;
    if (u_drop < s->e.sonar_dropout) {
        pg->kind = SIM_PING_DROPOUT;
    } else if (u_ghost < s->e.sonar_ghost) {
        pg->kind = SIM_PING_GHOST;
        range = p->sonar_min_m + u_range * (max - p->sonar_min_m);
    } else if (isfinite(echo)) {
        pg->kind = SIM_PING_ECHO;
        range = echo;
        if (s->e.sonar_noise_m > 0.0) {
            range += s->e.sonar_noise_m * sim_rng_gauss_from(u_g1, u_g2);
        }
        range = range > p->sonar_min_m ? range : p->sonar_min_m;
    } else {
        pg->kind = isfinite(geo) ? SIM_PING_GRAZING : SIM_PING_NOTHING;
    }
    if (s->faults && s->time_us < s->fault_until_us[FAULT_ECHO]) {
        pg->kind = SIM_PING_STUCK; /* the line is high before the echo could come */
    }
    s->sonar_out = true;
    s->sonar_echo = pg->kind == SIM_PING_ECHO || pg->kind == SIM_PING_GHOST;
    double width = s->sonar_echo ? 2.0 * range / p->sound_mps * 1e6 : HOST_INF;
    double late = late_echo_us(s);
    if (late < width && late < p->sonar_timeout_us) {
        pg->kind = SIM_PING_LATE;
        s->sonar_echo = true;
        width = dmax(late, 2.0 * p->sonar_min_m / p->sound_mps * 1e6);
        range = width * 1e-6 * p->sound_mps / 2.0;
    }
    if (s->sonar_echo) {
        pg->range_m = range;
        pg->echo_us = (uint32_t)lround(dmin(width, p->sonar_timeout_us - 1.0));
        s->sonar_ready_us = s->time_us + pg->echo_us;
    } else {
        s->sonar_ready_us = s->time_us + (uint64_t)llround(p->sonar_timeout_us);
    }
    /* This ping's sound rings from the nearest surface that returns it, whatever the
     * sensor made of it (a dropout loses the echo, not the sound). */
    s->ring_from_us = s->time_us;
    s->ring_us = isfinite(echo) ? (uint32_t)lround(2.0 * echo / p->sound_mps * 1e6) : 0u;
}

int sim_sonar_trigger(sim_t *s)
{
    if (s->sonar_out && s->time_us < s->sonar_ready_us) {
        return HAL_EBUSY;
    }
    /* A finished but unread result is overwritten, as the sensor would. */
    sonar_ping(s);
    return HAL_OK;
}

hal_sonar_status_t sim_sonar_poll(sim_t *s, uint32_t *echo_us)
{
    if (!s->sonar_out) {
        return HAL_SONAR_IDLE;
    }
    if (s->time_us < s->sonar_ready_us) {
        return HAL_SONAR_BUSY;
    }
    s->sonar_out = false;
    if (s->sonar_echo) {
        *echo_us = s->ping.echo_us;
        return HAL_SONAR_ECHO;
    }
    return HAL_SONAR_TIMEOUT;
}

/* ---- motion ----------------------------------------------------------------------------- */

/* Whether the body fits at (x, y); a free answer moves the anchor of the free margin. */
static bool body_fits(sim_t *s, double x, double y)
{
    double ex = x - s->ax;
    double ey = y - s->ay;
    if (ex * ex + ey * ey <= s->margin2) {
        return true;
    }
    double r = s->p.body_radius_m;
    double c = room_clearance(s->room, x, y, r + SIM_MARGIN_CAP_M);
    if (c < r) {
        return false;
    }
    s->ax = x;
    s->ay = y;
    s->margin = c - r;
    s->margin2 = s->margin * s->margin;
    return true;
}

/*
 * Move the body by du along the mean heading and turn it by dth. The body is a disc about
 * the axle centre, so turning never collides; a translation that would touch an obstacle
 * stops where the body meets it (bisection). Steps are cut to half the body radius, so
 * not even a thin wall can be jumped over.
 */
static double sim_move(sim_t *s, double du, double dth)
{
    const double r = s->p.body_radius_m;
    double done = 0.0; /* the share of the translation the body made */
    int n = 1;
    if (fabs(du) > 0.5 * r) {
        n = (int)ceil(fabs(du) / (0.5 * r));
    }
    du /= n;
    dth /= n;
    bool blocked = false;
    double hc = 1.0; /* the turn of one step, and of half a step */
    double hs = 0.0;
    double qc = 1.0;
    double qs = 0.0;
    if (dth != 0.0) {
        small_sincos(0.5 * dth, &qc, &qs);
        hc = qc * qc - qs * qs; /* the double angle */
        hs = 2.0 * qc * qs;
    }
    for (int i = 0; i < n; i++) {
        /* Along the mean heading of the step (the paper's Eq. 10-11 midpoint rule). */
        double mx = du * (s->hc * qc - s->hs * qs);
        double my = du * (s->hs * qc + s->hc * qs);
        double nx = s->x + mx;
        double ny = s->y + my;
        if (du != 0.0 && !body_fits(s, nx, ny)) {
            double lo = 0.0;
            double hi = 1.0;
            for (int k = 0; k < SIM_CONTACT_ITER; k++) {
                double mid = 0.5 * (lo + hi);
                if (room_clearance(s->room, s->x + mid * mx, s->y + mid * my, r) >= r) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            nx = s->x + lo * mx;
            ny = s->y + lo * my;
            s->ax = nx;
            s->ay = ny;
            s->margin = 0.0;
            s->margin2 = 0.0;
            blocked = true;
            done += lo;
        } else {
            done += 1.0;
        }
        s->x = nx;
        s->y = ny;
        if (dth != 0.0) {
            double c = s->hc * hc - s->hs * hs;
            s->hs = s->hs * hc + s->hc * hs;
            s->hc = c;
            s->th = wrap_pi(s->th + dth);
            /* Rounding would slowly part the vector from the angle: start it afresh. */
            if (++s->moves >= SIM_HEADING_RESYNC) {
                s->moves = 0u;
                s->hc = cos(s->th);
                s->hs = sin(s->th);
            }
        }
    }
    if (blocked) {
        if (!s->contact) {
            s->contact = true;
            s->collisions++;
        }
    } else if (s->contact && du != 0.0 && s->margin > SIM_CONTACT_RELEASE_M) {
        s->contact = false;
    }
    return done / n;
}

/* Perhaps begin an episode of fault f, which comes at @p rate a second. */
static bool begin_episode(sim_t *s, int f, double rate)
{
    if (rate <= 0.0 || s->time_us < s->fault_until_us[f] ||
        sim_rng_unit(&s->rng_fault[f]) >= rate * DT_S) {
        return false;
    }
    double len = SIM_EPISODE_MIN_S +
                 (SIM_EPISODE_MAX_S - SIM_EPISODE_MIN_S) * sim_rng_unit(&s->rng_fault[f]);
    s->fault_until_us[f] = s->time_us + (uint64_t)llround(len * 1e6);
    return true;
}

/* The episodes of the faults in this tick: a stopped encoder did not count the turn it
 * was given, a stalled servo did not move; and new episodes begin. */
static void faults_step(sim_t *s, const double turns[2], double common, double servo_before)
{
    if (s->time_us < s->fault_until_us[FAULT_ENCODER]) {
        int w = s->stopped_wheel;
        s->enc[w] -= (turns[w] - common) * s->counts_per_rad;
    }
    if (s->time_us < s->fault_until_us[FAULT_SERVO]) {
        s->servo_deg = servo_before;
    }
    const double rates[3] = {s->e.echo_stuck_per_s, s->e.servo_stall_per_s,
                             s->e.encoder_stop_per_s};
    for (int f = 0; f < 3; f++) {
        if (begin_episode(s, f, rates[f]) && f == FAULT_ENCODER) {
            s->stopped_wheel = sim_rng_unit(&s->rng_fault[f]) < 0.5 ? 0 : 1;
        }
    }
}

bool sim_ticks_lost(const sim_t *s)
{
    return s->e.tick_miss > 0.0;
}

bool sim_tick_lost(sim_t *s)
{
    if (s->e.tick_miss <= 0.0 || sim_rng_unit(&s->rng_fault[FAULT_TICK]) >= s->e.tick_miss) {
        return false;
    }
    s->ticks_missed++;
    return true;
}

void sim_step(sim_t *s)
{
    double d[2];
    double turns[2];
    for (int w = 0; w < 2; w++) {
        double om0 = s->omega[w];
        double omt = s->omega_cmd[w];
        double turn; /* wheel rotation this tick, rad */
        double accel = 0.0;
        if (om0 == omt) {
            turn = omt * DT_S;
        } else {
            /* The exact first-order response over the tick, and its integral. */
            double om1 = omt + (om0 - omt) * s->decay;
            if (fabs(om1 - omt) < 1e-9) {
                om1 = omt;
            }
            turn = omt * DT_S + (om0 - omt) * s->gain;
            accel = (om1 - om0) * s->r_act[w] / DT_S;
            s->omega[w] = om1;
        }
        turns[w] = turn;
        double travel = turn * s->r_act[w];
        double hard = fabs(accel) - s->e.slip_free_mps2;
        if (hard > 0.0 && s->e.slip_per_mps2 > 0.0) {
            travel *= 1.0 - dmin(s->e.slip_per_mps2 * hard, SIM_SLIP_MAX);
        }
        if (travel != 0.0 && s->e.wheel_noise > 0.0) {
            travel *= 1.0 + s->e.wheel_noise * sim_rng_gauss4(&s->rng_wheels);
        }
        d[w] = travel;
    }
    double made = 1.0;
    if (d[0] != 0.0 || d[1] != 0.0) {
        made = sim_move(s, 0.5 * (d[0] + d[1]), (d[1] - d[0]) / s->base_act);
    }
    /* Against an obstacle the wheels stall: they turn only as far as the body moves (the
     * common part of their rotation is cut to what was made; turning in place goes on). */
    double common = 0.5 * (turns[0] + turns[1]) * (1.0 - made);
    for (int w = 0; w < 2; w++) {
        s->enc[w] += (turns[w] - common) * s->counts_per_rad;
    }

    double servo_before = s->servo_deg;
    double diff = s->servo_cmd_deg - s->servo_deg;
    if (fabs(diff) <= s->servo_step_deg) {
        s->servo_deg = s->servo_cmd_deg;
    } else {
        s->servo_deg += diff > 0.0 ? s->servo_step_deg : -s->servo_step_deg;
    }
    if (s->faults) {
        faults_step(s, turns, common, servo_before);
    }
    s->time_us += HAL_TICK_PERIOD_US;
    s->ticks++;
}
