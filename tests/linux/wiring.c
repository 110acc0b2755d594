/* SPDX-License-Identifier: MIT */
/* The robot configuration the backend's tests share: consecutive lines, a temporary PWM tree. */
#include "wiring.h"

#include <stdio.h>

#include "tmptree.h"

void wiring_lconf(lconf_t *c, const char *chip, int32_t first_line, const char *root)
{
    lconf_default(c);
    snprintf(c->gpio_chip, sizeof c->gpio_chip, "%s", chip);
    c->enc_a[0] = first_line + LCONF_ENC_LEFT_A;
    c->enc_b[0] = first_line + LCONF_ENC_LEFT_B;
    c->enc_a[1] = first_line + LCONF_ENC_RIGHT_A;
    c->enc_b[1] = first_line + LCONF_ENC_RIGHT_B;
    c->sonar_trigger = first_line + LCONF_SONAR_TRIGGER;
    c->sonar_echo = first_line + LCONF_SONAR_ECHO;
    c->motor_in1[0] = first_line + LCONF_MOTOR_LEFT_IN1;
    c->motor_in2[0] = first_line + LCONF_MOTOR_LEFT_IN2;
    c->motor_in1[1] = first_line + LCONF_MOTOR_RIGHT_IN1;
    c->motor_in2[1] = first_line + LCONF_MOTOR_RIGHT_IN2;
    c->motor_standby = first_line + LCONF_MOTOR_STANDBY;

    tmptree_pwm_channel(root, 0u, 0u);
    tmptree_pwm_channel(root, 0u, 1u);
    tmptree_pwm_channel(root, 1u, 0u);
    c->motor_pwm[0] = (lconf_pwm_t){0, 0};
    c->motor_pwm[1] = (lconf_pwm_t){0, 1};
    c->servo_pwm = (lconf_pwm_t){1, 0};
    snprintf(c->pwm_root, sizeof c->pwm_root, "%s", root);
    snprintf(c->storage_dir, sizeof c->storage_dir, "%s/store", root);
    c->tick_priority = 0u;
    c->watchdog_idle_ms = 0u;
}

void wiring_conf_file(const char *root, const char *core, const char *extra)
{
    tmptree_pwm_channel(root, 0u, 0u);
    tmptree_pwm_channel(root, 0u, 1u);
    tmptree_pwm_channel(root, 1u, 0u);
    char text[2048];
    snprintf(text, sizeof text,
             "%s"
             "[linux]\n"
             "# the fake chip's lines\n"
             "gpio_chip = fakechip0\n"
             "encoder_left_a = 1\nencoder_left_b = 2\nencoder_right_a = 3\nencoder_right_b = 4\n"
             "sonar_trigger = 5\nsonar_echo = 6\n"
             "motor_left_in1 = 7\nmotor_left_in2 = 8\nmotor_right_in1 = 9\nmotor_right_in2 = 10\n"
             "pwm_root = %s\n"
             "servo_pwm_chip = 1\nservo_pwm_channel = 0\n"
             "motor_left_pwm_chip = 0\nmotor_left_pwm_channel = 0\n"
             "motor_right_pwm_chip = 0\nmotor_right_pwm_channel = 1\n"
             "storage_dir = %s/maps\n"
             "tick_priority = 0\n"
             "%s",
             core, root, root, extra);
    tmptree_file(root, "robot.conf", text);
}
