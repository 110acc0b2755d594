/* SPDX-License-Identifier: MIT */
/* The simulated robot's parameters and error levels: the defaults, the ideal robot, the checks. */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "host/sim.h"

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
        .servos = 1u,
        .extra_sonars = 0u,
        .extra_sonar = {{.x_m = 0.0, .y_m = 0.06, .yaw_deg = 90.0, .servo = -1}},
        .bumps = 0u,
        .bump = {{0.0, 90.0}, {-90.0, 0.0}, {90.0, 180.0}, {-180.0, -90.0}},
    };
}

/*
 * The sonar's levels; hal/host/README.md ("The sonar's levels") names the source of every
 * knot and the figure taken from it. The limits are on one ray's incidence: a source gives
 * the turn of a flat target from the beam's axis (or the edge of the beam for a target
 * facing the sensor) up to which the sensor reads it right, and the ray of the 15° cone
 * nearest the target's normal meets it half a cone less obliquely, so a knot is the
 * figure less 7.5°. None is below 1°: a surface facing the sensor answers at every range
 * (the rated 4 m is for one), and with 9 rays over 15° one always meets it within 0.94°.
 * The optimistic level is the model before issue 28, kept to reproduce old figures.
 */
static const struct {
    const char *name;
    double grazing_deg;
    sim_grazing_curve_t curve;
    uint32_t multipath;
} sonar_levels[SIM_SONAR_LEVELS] = {
    [SIM_SONAR_OPTIMISTIC] = {"optimistic", 45.0, {0u, {0.0}, {0.0}}, 0u},
    [SIM_SONAR_TYPICAL] = {"typical",
                           0.0,
                           {8u,
                            {0.02, 0.04, 0.06, 0.10, 0.30, 0.61, 1.66, 3.00},
                            {20.5, 18.5, 7.5, 8.5, 17.5, 17.5, 12.5, 1.0}},
                           2u},
    [SIM_SONAR_PESSIMISTIC] = {"pessimistic",
                               0.0,
                               {8u,
                                {0.02, 0.04, 0.06, 0.10, 0.15, 0.45, 1.45, 1.55},
                                {20.5, 8.5, 6.5, 7.5, 12.5, 1.5, 1.5, 1.0}},
                               2u},
};

void sim_errors_sonar(sim_errors_t *e, sim_sonar_level_t level)
{
    unsigned l = (unsigned)level < SIM_SONAR_LEVELS ? (unsigned)level : SIM_SONAR_DEFAULT;
    e->grazing_deg = sonar_levels[l].grazing_deg;
    e->grazing_curve = sonar_levels[l].curve;
    e->multipath = sonar_levels[l].multipath;
}

const char *sim_sonar_level_name(sim_sonar_level_t level)
{
    return (unsigned)level < SIM_SONAR_LEVELS ? sonar_levels[level].name : NULL;
}

int sim_sonar_level_of(const char *name)
{
    for (int l = 0; l < (int)SIM_SONAR_LEVELS; l++) {
        if (name != NULL && strcmp(name, sonar_levels[l].name) == 0) {
            return l;
        }
    }
    return -1;
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
        .echo_stuck_per_s = 0.0,
        .servo_lag = 0.0,
        .servo_stall_per_s = 0.0,
        .tick_miss = 0.0,
        .encoder_stop_per_s = 0.0,
    };
    sim_errors_sonar(e, SIM_SONAR_DEFAULT);
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

/* Knots within the reach of any sonar, ranges ascending, limits within (0, 90]. */
static bool curve_ok(const sim_grazing_curve_t *c)
{
    if (c->n > SIM_GRAZING_KNOTS) {
        return false;
    }
    for (uint32_t i = 0; i < c->n; i++) {
        if (!in(c->range_m[i], 0.0, 100.0) || !in(c->deg[i], 1e-6, 90.0) ||
            (i > 0u && !(c->range_m[i] > c->range_m[i - 1u]))) {
            return false;
        }
    }
    return true;
}

/* The fitted rows of the instance tables: mounts near the robot, servos it has, arcs. */
static bool mounts_ok(const sim_params_t *p)
{
    if (p->extra_sonars > SIM_SONARS_MAX - 1u) {
        return false;
    }
    for (uint32_t i = 0; i < p->extra_sonars; i++) {
        const sim_sonar_mount_t *m = &p->extra_sonar[i];
        if (!in(m->x_m, -10.0, 10.0) || !in(m->y_m, -10.0, 10.0) ||
            !in(m->yaw_deg, -360.0, 360.0) || m->servo < -1 ||
            (m->servo >= 0 && (uint32_t)m->servo >= p->servos)) {
            return false;
        }
    }
    return true;
}

static bool bumps_ok(const sim_params_t *p)
{
    if (p->bumps > SIM_BUMPS_MAX) {
        return false;
    }
    for (uint32_t i = 0; i < p->bumps; i++) {
        const sim_bump_t *b = &p->bump[i];
        if (!in(b->from_deg, -360.0, 360.0) || !in(b->to_deg, -360.0, 360.0) ||
            !(b->from_deg < b->to_deg)) {
            return false;
        }
    }
    return true;
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
        {p->servos >= 1u && p->servos <= SIM_SERVOS_MAX, "p.servos"},
        {mounts_ok(p), "p.extra_sonar"},
        {bumps_ok(p), "p.bump"},
        {in(e->wheel_ratio_ed, 0.5, 2.0), "e.wheel_ratio_ed"},
        {in(e->wheel_base_eb, 0.5, 2.0), "e.wheel_base_eb"},
        {in(e->slip_per_mps2, 0.0, 1.0), "e.slip_per_mps2"},
        {in(e->slip_free_mps2, 0.0, 100.0), "e.slip_free_mps2"},
        {in(e->wheel_noise, 0.0, 0.5), "e.wheel_noise"},
        {in(e->sonar_noise_m, 0.0, 10.0), "e.sonar_noise_m"},
        {in(e->sonar_dropout, 0.0, 1.0), "e.sonar_dropout"},
        {in(e->sonar_ghost, 0.0, 1.0), "e.sonar_ghost"},
        {in(e->grazing_deg, 0.0, 90.0), "e.grazing_deg"},
        {curve_ok(&e->grazing_curve), "e.grazing_curve"},
        {e->multipath <= 8u, "e.multipath"},
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
