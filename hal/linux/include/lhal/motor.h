/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What a signed motor duty means for an H-bridge with a PWM input and direction lines
 * (L298N ENA/IN1/IN2, TB6612FNG PWMA/AIN1/AIN2, or a driver with one DIR line).
 *
 * Forward drives IN1 high and IN2 low, reverse the opposite, zero drives both low (the
 * bridge lets the motor coast) with a zero duty. An inverted motor (wired or mounted the
 * other way) swaps forward and reverse, so a positive duty always rolls the robot forward.
 */
#ifndef LHAL_MOTOR_H
#define LHAL_MOTOR_H

#include <stdbool.h>
#include <stdint.h>

/** The outputs for one motor. */
typedef struct {
    bool in1;         /**< IN1 (or DIR) level */
    bool in2;         /**< IN2 level */
    uint32_t duty_ns; /**< PWM high time */
} motor_out_t;

/**
 * The outputs for a duty.
 * @param duty       -HAL_DUTY_MAX .. HAL_DUTY_MAX; clamped
 * @param invert     swap forward and reverse
 * @param period_ns  the PWM period
 */
motor_out_t motor_plan(int16_t duty, bool invert, uint32_t period_ns);

/** Whether two plans drive the lines the same way (only the duty may differ). */
bool motor_same_direction(motor_out_t a, motor_out_t b);

#endif /* LHAL_MOTOR_H */
