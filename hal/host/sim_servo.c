/* SPDX-License-Identifier: MIT */
/* The simulated hobby servos: the pulse each is sent and the angle it is sent to. */
#include <math.h>

#include "sim_internal.h"

void sim_servo_init(sim_t *s)
{
    const sim_params_t *p = &s->p;
    for (uint32_t i = 0; i < p->servos; i++) {
        sim_servo_t *v = &s->servo[i];
        /* A lagging servo loses that share of its speed: it reaches each stop late. */
        v->step_deg = 60.0 / p->servo_s_per_60deg * SIM_DT_S * (1.0 - s->e.servo_lag);
        v->deg = 90.0;
        v->cmd_deg = 90.0;
        v->pulse = (uint16_t)lround(0.5 * (p->servo_pulse_0_us + p->servo_pulse_180_us));
    }
}

uint8_t sim_servo_count(const sim_t *s)
{
    return (uint8_t)s->p.servos;
}

int sim_servo_set_pulse_on(sim_t *s, uint8_t servo, uint16_t pulse_us)
{
    if (servo >= s->p.servos) {
        return HAL_EINVAL;
    }
    sim_servo_t *v = &s->servo[servo];
    pulse_us = pulse_us < 400u ? 400u : (pulse_us > 2600u ? 2600u : pulse_us);
    v->pulse = pulse_us;
    double deg = ((double)pulse_us - s->p.servo_pulse_0_us) /
                 (s->p.servo_pulse_180_us - s->p.servo_pulse_0_us) * 180.0;
    v->cmd_deg = fmin(fmax(deg, 0.0), 180.0); /* the horn's end stops */
    return HAL_OK;
}

uint16_t sim_servo_pulse_on(const sim_t *s, uint8_t servo)
{
    return servo < s->p.servos ? s->servo[servo].pulse : 0u;
}

void sim_servo_set_pulse(sim_t *s, uint16_t pulse_us)
{
    (void)sim_servo_set_pulse_on(s, 0u, pulse_us);
}

uint16_t sim_servo_pulse(const sim_t *s)
{
    return sim_servo_pulse_on(s, 0u);
}
