/* SPDX-License-Identifier: MIT */
/* The simulated hobby servo: the pulse it is sent and the angle it is sent to. */
#include <math.h>

#include "sim_internal.h"

void sim_servo_init(sim_t *s)
{
    const sim_params_t *p = &s->p;
    sim_servo_t *v = &s->servo;
    /* A lagging servo loses that share of its speed: it reaches each stop late. */
    v->step_deg = 60.0 / p->servo_s_per_60deg * SIM_DT_S * (1.0 - s->e.servo_lag);
    v->deg = 90.0;
    v->cmd_deg = 90.0;
    v->pulse = (uint16_t)lround(0.5 * (p->servo_pulse_0_us + p->servo_pulse_180_us));
}

void sim_servo_set_pulse(sim_t *s, uint16_t pulse_us)
{
    sim_servo_t *v = &s->servo;
    pulse_us = pulse_us < 400u ? 400u : (pulse_us > 2600u ? 2600u : pulse_us);
    v->pulse = pulse_us;
    double deg = ((double)pulse_us - s->p.servo_pulse_0_us) /
                 (s->p.servo_pulse_180_us - s->p.servo_pulse_0_us) * 180.0;
    v->cmd_deg = fmin(fmax(deg, 0.0), 180.0); /* the horn's end stops */
}

uint16_t sim_servo_pulse(const sim_t *s)
{
    return s->servo.pulse;
}
