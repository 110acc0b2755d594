/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What the simulated robot's model files share: `struct sim`, one sub-struct per model
 * (body, servo, sonar, faults), each model's entry points for sim.c, and the small helpers
 * of their arithmetic. Private to hal/host; host/sim.h is the public API.
 *
 * sim.c owns the lifetime and the step that ties the models together; every model reads
 * the others' state (the sonar pings from the body's pose and the servo's angle, a fault
 * holds an encoder or the servo back) but writes only its own, except the faults, whose
 * whole job is to undo what a wire would have done.
 */
#ifndef HOST_SIM_INTERNAL_H
#define HOST_SIM_INTERNAL_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "host/sim.h"
#include "room_internal.h"
#include "sim_rng.h"

#define SIM_DEG (HOST_PI / 180.0)
#define SIM_DT_S ((double)HAL_TICK_PERIOD_US * 1e-6) /* the control period, s */

/* Independent random streams, so changing one error level leaves the others' draws.
 * Sonar 0 draws from SIM_STREAM_SONAR, sonar i > 0 from SIM_STREAM_SONARS + i. */
enum { SIM_STREAM_WHEELS = 1, SIM_STREAM_SONAR = 2, SIM_STREAM_FAULTS = 3, SIM_STREAM_SONARS = 16 };

/* The fault episodes, each with its own stream (SIM_STREAM_FAULTS + its number). */
enum { SIM_FAULT_ECHO, SIM_FAULT_SERVO, SIM_FAULT_ENCODER, SIM_FAULT_TICK, SIM_FAULTS };

/* Servo angles whose beam rotation the sonar keeps (the sweep has 6 stops). */
#define SIM_BEAM_CACHE 16u

/* Rays cast across the sonar cone, edges included. */
#define SIM_SONAR_RAYS 9

/* The incidence limit is looked up in this many steps of the sonar's reach. */
#define SIM_LIMIT_BINS 4096u

/* The differential drive (sim_body.c): pose, wheels, encoders, collisions. */
typedef struct {
    /* Derived once. */
    double r_nom;          /* nominal wheel radius, m */
    double r_act[2];       /* actual wheel radii (E_d), m */
    double base_act;       /* actual wheel base (E_b), m */
    double counts_per_rad; /* encoder counts per radian of wheel */
    double decay;          /* exp(-dt/tau): the motor's response over one tick */
    double gain;           /* tau·(1 - decay): weight of the speed error in a tick's travel */
    double omega_per_duty; /* wheel rad/s per unit of duty */
    sim_rng_t rng;         /* wheel noise */

    /* The pose of the axle centre. */
    double x, y, th;
    double hc, hs;  /* cos th, sin th, carried along with th */
    uint32_t moves; /* since hc, hs were last computed from th */

    /* Motors, wheels, encoders. */
    double omega[2];     /* wheel angular speeds, rad/s */
    double omega_cmd[2]; /* what the duty asks for, rad/s */
    int16_t duty[2];
    double enc[2]; /* wheel rotation the encoders counted, counts */

    /* Collisions: every point within `margin` of the anchor is known to be free. */
    double ax, ay, margin, margin2;
    bool contact;
    uint32_t collisions;
} sim_body_t;

/* The hobby servo (sim_servo.c). */
typedef struct {
    double step_deg; /* travel per tick (servo_lag taken off), deg */
    uint16_t pulse;  /* the pulse in force, µs */
    double deg;      /* where the horn is */
    double cmd_deg;  /* where the pulse sends it */
} sim_servo_t;

/*
 * One HC-SR04 (sim_sonar.c): its mount, what the model derives from its parameters, the
 * ping under way, and the scratch space of the cone. Everything a sonar needs is here, so
 * a robot with several is an array of these.
 */
typedef struct {
    /* The mount: sonar 0 on servo 0 at (sonar_x_m, sonar_y_m); the others a row of
       sim_params_t.extra_sonar. */
    unsigned index; /* the instance */
    double mx, my;  /* the sensor (a servo's axis) ahead of and left of the axle, m */
    int servo;      /* the servo it turns on, or -1: fixed */
    double yaw_deg; /* its beam from the heading with the servo at 90°, deg */
    bool turned;    /* yaw_deg is not 0: the beam turns by yc, ys too */
    double yc, ys;  /* cos, sin of yaw_deg */

    /* Derived once from sim_params_t and sim_errors_t (sim_sonar_init()). */
    double cos_limit[SIM_LIMIT_BINS + 1u]; /* a surface answers when |cos incidence| is at
                                              least this, by the path (sim_sonar_limit()) */
    double limit_per_m;                    /* bins of cos_limit a metre */
    bool limit_flat;                       /* the same limit at every range: cos_limit[0] */
    double cone_c, cone_s;                 /* cos, sin of half the cone */
    double ray_c, ray_s;                   /* cos, sin of the angle between two rays */
    double catch_tan; /* a ray coming back passes the receiver within this share of its
                         path (sim_multipath.c) */
    sim_rng_t rng;    /* dropouts, ghosts, range noise */

    /* cos, sin of (90° - servo angle) for the last few servo angles pinged at: the
       sweep revisits the same stops. */
    struct {
        double deg, c, s;
    } beam[SIM_BEAM_CACHE];
    unsigned beam_next; /* the entry to replace next */

    /* The ping under way. */
    bool out;              /* a ping is out and not yet reported */
    bool echo;             /* it will report an echo (else a timeout) */
    uint64_t ready_us;     /* when its echo or timeout is due */
    uint64_t ring_from_us; /* the last ping's trigger time */
    uint32_t ring_us;      /* its sound's round trip to the surface it echoed from; 0: none */
    sim_ping_t ping;
    uint32_t counts[SIM_PING_KINDS]; /* pings by kind */

    /* The segments as lines, for the mirror paths of a small room (sim_multipath.c);
       NULL without multipath or with the room's index. */
    struct sim_line *lines;

    /* Scratch of the cone. */
    uint32_t *cand;  /* cone candidates: segment indices, then circle indices */
    uint32_t *near;  /* a large room's objects near the cone (room_t.index) */
    uint32_t *stamp; /* per object: the cone_objects() call that last took it */
    uint32_t stamp_now;
} sim_sonar_t;

/* The fault episodes and lost ticks (sim_faults.c). */
typedef struct {
    sim_rng_t rng[SIM_FAULTS];
    uint64_t until_us[SIM_FAULTS]; /* the episode under way ends then */
    bool episodes;                 /* an episode fault is on: the step looks at them */
    int stopped_wheel;             /* the encoder that stopped counting */
    uint64_t ticks_missed;
} sim_faults_t;

struct sim {
    const room_t *room;
    sim_params_t p;
    sim_errors_t e;
    sim_body_t body;
    sim_servo_t servo[SIM_SERVOS_MAX]; /* p.servos of them */
    sim_sonar_t sonar[SIM_SONARS_MAX]; /* nsonars of them */
    unsigned nsonars;                  /* 1 + p.extra_sonars */
    sim_faults_t faults;
    uint64_t time_us;
    uint64_t ticks;
};

/* ---- the models' entry points (each file's own) ----------------------------------------- */

/* sim_body.c: the robot at rest at (x, y, th); the wheels' derived values and stream. */
void sim_body_init(sim_t *s, double x, double y, double th, uint64_t seed);

/* Set the body down at (x, y, th), wheels stopped, contact cleared, encoders kept. */
void sim_body_place(sim_t *s, double x, double y, double th);

/*
 * One period of the drive: motors, slip, wheel noise, the move with its collisions, the
 * encoders. @p turns gets each wheel's rotation (rad); returns the common part of it the
 * stalled wheels did not make (rad), for the encoder fault.
 */
double sim_body_step(sim_t *s, double turns[2]);

/* sim_servo.c: every servo at 90°, its pulse in the middle. */
void sim_servo_init(sim_t *s);

/* sim_sonar.c: every sonar's mount, derived values, stream and scratch; -1 when out of
 * memory (free them anyway). */
int sim_sonar_init(sim_t *s, uint64_t seed);
void sim_sonar_free(sim_t *s);

/* A ray's first surface (sim_multipath.c). */
typedef struct {
    double t;      /* its distance, m; infinity for none */
    double cosi;   /* |cos| of the incidence */
    uint32_t id;   /* the object, as the room's index numbers them (segment i as i, circle
                      i as nsegs + i); UINT32_MAX for the raster's pixels */
    double nx, ny; /* a raster surface's unit normal (either side) */
} sim_surface_t;

/* sim_multipath.c: a sonar's lines of a small room's segments when multipath is on; -1
 * when out of memory (sim_sonar_free() frees them). */
int sim_multipath_init(const sim_t *s, sim_sonar_t *so);

/*
 * The first surface along a ray within max_m: among sonar @p so's cone candidates
 * (so->cand, nseg segments then ncirc circles) when @p cone, else among every object
 * (through the index of a large room); and the raster's pixels.
 */
sim_surface_t sim_surface(const sim_t *s, const sim_sonar_t *so, double ox, double oy, double dx,
                          double dy, double max_m, bool cone, size_t nseg, size_t ncirc);

/*
 * The echo of a ray of sonar @p so's cone from the sensor (sx, sy) along (dx, dy) whose
 * first surface @p first it met beyond the incidence it answers at: the range the echo
 * stands for (half its path), or infinity when the sound is lost. @p bx, by: the beam's
 * axis.
 */
double sim_multipath(const sim_t *s, const sim_sonar_t *so, double sx, double sy, double bx,
                     double by, double dx, double dy, const sim_surface_t *first);

/* sim_faults.c: the fault streams. */
void sim_faults_init(sim_t *s, uint64_t seed);

/*
 * The episodes of the faults in this period: a stopped encoder takes back the turn it was
 * given, a stalled servo 0 goes back to @p servo_before; then new episodes may begin.
 */
void sim_faults_step(sim_t *s, const double turns[2], double common, double servo_before);

/* ---- inline: the per-period paths ---------------------------------------------------- */

/* The servo slews toward its command at its rate: one period. */
static inline void sim_servo_step(sim_servo_t *v)
{
    double diff = v->cmd_deg - v->deg;
    if (fabs(diff) <= v->step_deg) {
        v->deg = v->cmd_deg;
    } else {
        v->deg += diff > 0.0 ? v->step_deg : -v->step_deg;
    }
}

/* The least |cos| of the incidence a surface answers at, the sound having come @p path_m. */
static inline double sim_sonar_limit(const sim_sonar_t *so, double path_m)
{
    double b = path_m * so->limit_per_m;
    return so->cos_limit[b < (double)SIM_LIMIT_BINS ? (size_t)b : SIM_LIMIT_BINS];
}

/* Whether an episode of fault f is under way now. */
static inline bool sim_fault_on(const sim_t *s, int f)
{
    return s->faults.episodes && s->time_us < s->faults.until_us[f];
}

static inline double sim_dmin(double a, double b)
{
    return a < b ? a : b;
}

static inline double sim_dmax(double a, double b)
{
    return a > b ? a : b;
}

/* Wrap an angle into (-pi, pi] (one turn at most away, as after a tick). */
static inline double sim_wrap_pi(double a)
{
    if (a > HOST_PI) {
        a -= 2.0 * HOST_PI;
    } else if (a <= -HOST_PI) {
        a += 2.0 * HOST_PI;
    }
    return (a > HOST_PI || a <= -HOST_PI) ? remainder(a, 2.0 * HOST_PI) : a;
}

#endif /* HOST_SIM_INTERNAL_H */
