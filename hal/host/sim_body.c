/* SPDX-License-Identifier: MIT */
/* The simulated differential drive: motors, wheels with slip and noise, encoders, collisions. */
#include <math.h>

#include "sim_internal.h"

/* Clearance beyond the body looked for at once: the robot moves this far unchecked. */
#define SIM_MARGIN_CAP_M 0.25
/* The body leaves contact once this far from every obstacle (hysteresis). */
#define SIM_CONTACT_RELEASE_M 0.001
/* Bisections of a blocked step: 2^-14 of a 3 mm step is well below a micrometre. */
#define SIM_CONTACT_ITER 14
/* Slip never takes more than this fraction of a wheel's travel. */
#define SIM_SLIP_MAX 0.9
/* Resynchronise the heading's unit vector with its angle this often (moves). */
#define SIM_HEADING_RESYNC 256u

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

void sim_body_init(sim_t *s, double x, double y, double th, uint64_t seed)
{
    const sim_params_t *p = &s->p;
    const sim_errors_t *e = &s->e;
    sim_body_t *b = &s->body;
    sim_rng_seed(&b->rng, seed, SIM_STREAM_WHEELS);
    /* E_d = D_R / D_L with the mean diameter nominal (Borenstein and Feng). */
    b->r_nom = 0.5 * p->wheel_diameter_m;
    b->r_act[HAL_WHEEL_LEFT] = b->r_nom * 2.0 / (e->wheel_ratio_ed + 1.0);
    b->r_act[HAL_WHEEL_RIGHT] = b->r_nom * 2.0 * e->wheel_ratio_ed / (e->wheel_ratio_ed + 1.0);
    b->base_act = p->wheel_base_m * e->wheel_base_eb;
    b->counts_per_rad = p->counts_per_rev / (2.0 * HOST_PI);
    b->decay = exp(-SIM_DT_S / p->motor_tau_s);
    b->gain = p->motor_tau_s * (1.0 - b->decay);
    b->omega_per_duty = p->top_speed_mps / HAL_DUTY_MAX / b->r_nom;
    sim_body_place(s, x, y, th);
}

void sim_body_place(sim_t *s, double x, double y, double th)
{
    sim_body_t *b = &s->body;
    b->x = x;
    b->y = y;
    b->th = remainder(th, 2.0 * HOST_PI);
    b->hc = cos(b->th);
    b->hs = sin(b->th);
    b->moves = 0u;
    b->omega[0] = 0.0;
    b->omega[1] = 0.0;
    b->contact = false;
    b->margin = -1.0;
    b->margin2 = -1.0;
}

/* ---- the wires: motors and encoders ------------------------------------------------------ */

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
    s->body.duty[wheel] = duty;
    s->body.omega_cmd[wheel] = (double)duty * s->body.omega_per_duty;
}

int16_t sim_motor_duty(const sim_t *s, hal_wheel_t wheel)
{
    return wheel == HAL_WHEEL_RIGHT ? s->body.duty[1] : s->body.duty[0];
}

uint16_t sim_encoder_count(const sim_t *s, hal_wheel_t wheel)
{
    double c = s->body.enc[wheel == HAL_WHEEL_RIGHT ? 1 : 0];
    /* A quadrature counter counts edges: the floor of the true position, modulo 2^16. */
    int64_t n = (int64_t)c; /* toward zero; |c| stays far below 2^63 */
    if ((double)n > c) {
        n--;
    }
    return (uint16_t)(uint64_t)n;
}

/* ---- the move ------------------------------------------------------------------------------ */

/* Whether the body fits at (x, y); a free answer moves the anchor of the free margin. */
static bool body_fits(sim_t *s, double x, double y)
{
    sim_body_t *b = &s->body;
    double ex = x - b->ax;
    double ey = y - b->ay;
    if (ex * ex + ey * ey <= b->margin2) {
        return true;
    }
    double r = s->p.body_radius_m;
    double c = room_clearance(s->room, x, y, r + SIM_MARGIN_CAP_M);
    if (c < r) {
        return false;
    }
    b->ax = x;
    b->ay = y;
    b->margin = c - r;
    b->margin2 = b->margin * b->margin;
    return true;
}

/*
 * Move the body by du along the mean heading and turn it by dth. The body is a disc about
 * the axle centre, so turning never collides; a translation that would touch an obstacle
 * stops where the body meets it (bisection). Steps are cut to half the body radius, so
 * not even a thin wall can be jumped over.
 */
static double body_move(sim_t *s, double du, double dth)
{
    sim_body_t *b = &s->body;
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
        double mx = du * (b->hc * qc - b->hs * qs);
        double my = du * (b->hs * qc + b->hc * qs);
        double nx = b->x + mx;
        double ny = b->y + my;
        if (du != 0.0 && !body_fits(s, nx, ny)) {
            double lo = 0.0;
            double hi = 1.0;
            for (int k = 0; k < SIM_CONTACT_ITER; k++) {
                double mid = 0.5 * (lo + hi);
                if (room_clearance(s->room, b->x + mid * mx, b->y + mid * my, r) >= r) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            nx = b->x + lo * mx;
            ny = b->y + lo * my;
            b->ax = nx;
            b->ay = ny;
            b->margin = 0.0;
            b->margin2 = 0.0;
            blocked = true;
            done += lo;
        } else {
            done += 1.0;
        }
        b->x = nx;
        b->y = ny;
        if (dth != 0.0) {
            double c = b->hc * hc - b->hs * hs;
            b->hs = b->hs * hc + b->hc * hs;
            b->hc = c;
            b->th = sim_wrap_pi(b->th + dth);
            /* Rounding would slowly part the vector from the angle: start it afresh. */
            if (++b->moves >= SIM_HEADING_RESYNC) {
                b->moves = 0u;
                b->hc = cos(b->th);
                b->hs = sin(b->th);
            }
        }
    }
    if (blocked) {
        if (!b->contact) {
            b->contact = true;
            b->collisions++;
        }
    } else if (b->contact && du != 0.0 && b->margin > SIM_CONTACT_RELEASE_M) {
        b->contact = false;
    }
    return done / n;
}

/* ---- one period ---------------------------------------------------------------------------- */

double sim_body_step(sim_t *s, double turns[2])
{
    sim_body_t *b = &s->body;
    double d[2];
    for (int w = 0; w < 2; w++) {
        double om0 = b->omega[w];
        double omt = b->omega_cmd[w];
        double turn; /* wheel rotation this tick, rad */
        double accel = 0.0;
        if (om0 == omt) {
            turn = omt * SIM_DT_S;
        } else {
            /* The exact first-order response over the tick, and its integral. */
            double om1 = omt + (om0 - omt) * b->decay;
            if (fabs(om1 - omt) < 1e-9) {
                om1 = omt;
            }
            turn = omt * SIM_DT_S + (om0 - omt) * b->gain;
            accel = (om1 - om0) * b->r_act[w] / SIM_DT_S;
            b->omega[w] = om1;
        }
        turns[w] = turn;
        double travel = turn * b->r_act[w];
        double hard = fabs(accel) - s->e.slip_free_mps2;
        if (hard > 0.0 && s->e.slip_per_mps2 > 0.0) {
            travel *= 1.0 - sim_dmin(s->e.slip_per_mps2 * hard, SIM_SLIP_MAX);
        }
        if (travel != 0.0 && s->e.wheel_noise > 0.0) {
            travel *= 1.0 + s->e.wheel_noise * sim_rng_gauss4(&b->rng);
        }
        d[w] = travel;
    }
    double made = 1.0;
    if (d[0] != 0.0 || d[1] != 0.0) {
        made = body_move(s, 0.5 * (d[0] + d[1]), (d[1] - d[0]) / b->base_act);
    }
    /* Against an obstacle the wheels stall: they turn only as far as the body moves (the
     * common part of their rotation is cut to what was made; turning in place goes on). */
    double common = 0.5 * (turns[0] + turns[1]) * (1.0 - made);
    for (int w = 0; w < 2; w++) {
        b->enc[w] += (turns[w] - common) * b->counts_per_rad;
    }
    return common;
}
