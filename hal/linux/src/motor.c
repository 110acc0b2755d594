/* SPDX-License-Identifier: MIT */
/* Signed motor duty to H-bridge direction levels and a PWM high time. */
#include "lhal/motor.h"

#include "hal/hal.h"

motor_out_t motor_plan(int16_t duty, bool invert, uint32_t period_ns)
{
    int32_t d = duty;
    if (d > HAL_DUTY_MAX) {
        d = HAL_DUTY_MAX;
    } else if (d < -HAL_DUTY_MAX) {
        d = -HAL_DUTY_MAX;
    }
    if (invert) {
        d = -d;
    }
    uint32_t mag = (uint32_t)(d < 0 ? -d : d);
    motor_out_t out = {
        .in1 = d > 0,
        .in2 = d < 0,
        .duty_ns = (uint32_t)((uint64_t)period_ns * mag / HAL_DUTY_MAX),
    };
    return out;
}

bool motor_same_direction(motor_out_t a, motor_out_t b)
{
    return a.in1 == b.in1 && a.in2 == b.in2;
}
