/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The robot the backend's tests run on: wired to consecutive lines of one GPIO chip, with
 * its PWM channels in a temporary tree.
 *
 * From first_line, in lconf_lines() order: encoder_left_a, encoder_left_b,
 * encoder_right_a, encoder_right_b, sonar_trigger, sonar_echo, motor_left_in1,
 * motor_left_in2, motor_right_in1, motor_right_in2, motor_standby. PWM: the motors on
 * ROOT/pwmchip0/pwm0 and pwm1, the servo on ROOT/pwmchip1/pwm0 (created here); storage in
 * ROOT/store (not created); no telemetry; no real-time priority (the test machine is
 * shared); the background loop is not watched.
 */
#ifndef TEST_WIRING_H
#define TEST_WIRING_H

#include <stdint.h>

#include "lhal/lconf.h"

/** Fill @p c as above and make the PWM tree under @p root. */
void wiring_lconf(lconf_t *c, const char *chip, int32_t first_line, const char *root);

/**
 * The same robot as ROOT/robot.conf for the program, on fakechip0 from line 1, without the
 * standby line, storage in ROOT/maps; the PWM tree is made too. The file opens with
 * @p core (the core's `key = value` lines, or ""), then the [linux] section's 21 lines,
 * then @p extra (more of the section's lines, or "").
 */
void wiring_conf_file(const char *root, const char *core, const char *extra);

#endif /* TEST_WIRING_H */
