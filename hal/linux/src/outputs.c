/* SPDX-License-Identifier: MIT */
/* The Linux backend's outputs: the output thread writes what the tick posted; the kill stops the
 * motors without a lock. */
#define _GNU_SOURCE
#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "lx.h"

#define LX_SERVO_PERIOD_NS 20000000u /* 50 Hz */
#define LX_TRIGGER_NS 12000u         /* the HC-SR04 wants >= 10 µs */

static void lx_line_low(gpio_line_t *line)
{
    if (line != NULL) {
        (void)gpio_line_set(line, 0);
    }
}

void lx_lines_low(void)
{
    if (!atomic_load(&lx.lines_live)) {
        return;
    }
    for (unsigned w = 0u; w < 2u; w++) {
        lx_line_low(LX_IN1(w));
        lx_line_low(LX_IN2(w));
    }
    lx_line_low(LX_STANDBY);
}

void lx_kill(void)
{
    atomic_store(&lx.killed, true);
    /* The lines first: they stop a bridge whatever its PWM input does, and they are on the
     * GPIO chip, so a PWM chip that hangs (an I2C one) cannot keep them up. */
    lx_lines_low();
    int rc = pwm_kill(&lx.motor[HAL_WHEEL_LEFT]);
    int rc2 = pwm_kill(&lx.motor[HAL_WHEEL_RIGHT]);
    atomic_store(&lx.pwm_failed, rc != 0 || rc2 != 0);
    if (rc == 0 && rc2 == 0) {
        atomic_store(&lx.pwm_dead, true);
    }
}

void lx_fault(lhal_fault_t code, const char *fmt, ...)
{
    lx_kill();
    if (atomic_flag_test_and_set(&lx.fault_claimed)) {
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(lx.fault_msg, sizeof lx.fault_msg, fmt, ap);
    va_end(ap);
    atomic_store(&lx.fault, (int)code);
}

void lx_wake(int fd)
{
    if (fd >= 0) {
        uint64_t one = 1u;
        (void)!write(fd, &one, sizeof one);
    }
}

void lx_post(void)
{
    atomic_fetch_add(&lx.posted, 1u);
    lx_wake(lx.out_fd);
}

/* ---- hal.h: the outputs, posted ------------------------------------------------------ */

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    if (lx.up && wheel <= HAL_WHEEL_RIGHT && atomic_exchange(&lx.want_duty[wheel], duty) != duty) {
        lx_post();
    }
}

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo >= lx.servos) {
        return HAL_EINVAL;
    }
    if (lx.up && atomic_exchange(&lx.want_servo_us[servo], pulse_us) != pulse_us) {
        lx_post();
    }
    return HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar >= lx.sonars) {
        return HAL_EINVAL;
    }
    if (!lx.up) {
        return HAL_EIO;
    }
    /* Armed before the pulse, so the rising edge that follows it is taken as the echo. */
    pthread_mutex_lock(&lx_sonar_lock);
    int rc = echo_trigger(&lx.echo[sonar], lx_now());
    pthread_mutex_unlock(&lx_sonar_lock);
    if (rc == HAL_OK) {
        atomic_fetch_add(&lx.want_triggers[sonar], 1u);
        lx_post();
    }
    return rc;
}

/* ---- the output thread ----------------------------------------------------------------- */

/* STBY of a TB6612-style driver: high while a motor runs, low otherwise. */
static int lx_standby_update(void)
{
    bool on = !atomic_load(&lx.killed) &&
              (lx.motor_out[0].duty_ns != 0u || lx.motor_out[1].duty_ns != 0u);
    if (LX_STANDBY == NULL || on == lx.standby_on) {
        return 0;
    }
    lx.standby_on = on;
    return gpio_line_set(LX_STANDBY, on) == 0 ? 0 : -errno;
}

static int lx_motor_write(unsigned w, int32_t duty)
{
    motor_out_t want = motor_plan((int16_t)duty, lx.cfg.motor_invert[w], lx.cfg.motor_period_ns);
    motor_out_t *have = &lx.motor_out[w];
    int rc = 0;
    if (!motor_same_direction(*have, want)) {
        /* Never drive the new direction at the old duty: stop, turn, then go. */
        rc = pwm_set_duty(&lx.motor[w], 0u);
        if (rc == 0 && gpio_line_set(LX_IN1(w), want.in1) != 0) {
            rc = -errno;
        }
        if (rc == 0 && LX_IN2(w) != NULL && gpio_line_set(LX_IN2(w), want.in2) != 0) {
            rc = -errno;
        }
    }
    rc = rc == 0 ? pwm_set_duty(&lx.motor[w], want.duty_ns) : rc;
    if (rc == 0) {
        *have = want;
    }
    return rc;
}

static int lx_servo_write(unsigned i, uint32_t us)
{
    int rc;
    if (lx.servo_started[i]) {
        rc = pwm_set_duty(&lx.servo[i], us * LX_NS_PER_US);
    } else {
        rc = pwm_start(&lx.servo[i], LX_SERVO_PERIOD_NS, us * LX_NS_PER_US);
        lx.servo_started[i] = rc == 0;
    }
    return rc;
}

static int lx_trigger_pulse(unsigned sonar)
{
    if (gpio_line_set(LX_TRIGGER(sonar), 1) != 0) {
        return -errno;
    }
    uint64_t t = lx_mono_ns();
    while (lx_mono_ns() - t < LX_TRIGGER_NS) {
        /* 12 µs: shorter than any sleep's wake-up latency, so spin. */
    }
    return gpio_line_set(LX_TRIGGER(sonar), 0) == 0 ? 0 : -errno;
}

/* Writes what was posted, motors first: a servo or trigger that hangs must not keep a new
 * duty (a stop, most of all) from the motors. */
static void lx_apply(void)
{
    uint32_t seq = atomic_load(&lx.posted);
    for (unsigned w = 0u; w < 2u; w++) {
        atomic_store(&lx.doing, w == 0u ? "motor_left" : "motor_right");
        int32_t duty = atomic_load(&lx.killed) ? 0 : atomic_load(&lx.want_duty[w]);
        int rc = lx_motor_write(w, duty);
        rc = rc == 0 ? lx_standby_update() : rc;
        if (rc != 0) {
            lx_fault(LHAL_FAULT_IO, "motor_%s: %s", lx_wheel_name[w], strerror(-rc));
        }
    }
    static const char *const servo_key[LCONF_SERVOS] = {"servo_pwm", "servo1_pwm"};
    for (unsigned i = 0u; i < lx.servos; i++) {
        uint32_t us = atomic_load(&lx.want_servo_us[i]);
        if (us != 0u && us != lx.servo_us[i]) {
            atomic_store(&lx.doing, servo_key[i]);
            uint32_t clamped = us < LX_SERVO_MIN_US ? LX_SERVO_MIN_US
                                                    : (us > LX_SERVO_MAX_US ? LX_SERVO_MAX_US : us);
            int rc = lx_servo_write(i, clamped);
            lx.servo_us[i] = rc == 0 ? us : 0u;
            if (rc != 0) {
                lx_fault(LHAL_FAULT_IO, "%s: writing %s failed: %s", servo_key[i], lx.servo[i].dir,
                         strerror(-rc));
            }
        }
    }
    static const char *const trigger_key[LCONF_SONARS] = {"sonar_trigger", "sonar1_trigger"};
    for (unsigned i = 0u; i < lx.sonars; i++) {
        uint32_t triggers = atomic_load(&lx.want_triggers[i]);
        if (triggers != lx.triggers[i]) {
            atomic_store(&lx.doing, trigger_key[i]);
            lx.triggers[i] = triggers;
            int rc = lx_trigger_pulse(i);
            if (rc != 0) {
                lx_fault(LHAL_FAULT_IO, "%s: %s", trigger_key[i], strerror(-rc));
            }
        }
    }
    atomic_store(&lx.doing, NULL);
    if (atomic_load(&lx.killed)) {
        /* A stop may have come while a write was under way: make it hold. */
        lx_kill();
    }
    atomic_store(&lx.applied, seq);
}

void *lx_output_main(void *arg)
{
    (void)arg;
    struct pollfd pfd[2] = {{.fd = lx.out_fd, .events = POLLIN},
                            {.fd = lx.stop_fd, .events = POLLIN}};
    while (!atomic_load(&lx.stop)) {
        atomic_store(&lx.output.beat_ns, lx_now());
        atomic_fetch_add(&lx.output.rounds, 1u);
        int r = poll(pfd, 2u, LX_BEAT_MS);
        if (r < 0 && errno != EINTR) {
            lx_fault(LHAL_FAULT_IO, "the output thread stopped: poll: %s", strerror(errno));
            break;
        }
        if (r > 0 && (pfd[1].revents & POLLIN)) {
            break;
        }
        if (r > 0 && (pfd[0].revents & POLLIN)) {
            uint64_t n;
            (void)!read(lx.out_fd, &n, sizeof n);
        }
        if (atomic_load(&lx.applied) != atomic_load(&lx.posted)) {
            lx_apply();
        }
    }
    return NULL;
}
