/* SPDX-License-Identifier: MIT */
/*
 * The template port: every HAL function, compiling, doing nothing. A new board starts as
 * a copy of this file (see README, "Porting to a new board"); each function says what the
 * real one must do. Calls that cannot work yet answer HAL_ENOSYS rather than pretend.
 *
 * Map storage (hal_storage_*), hal_uart_read(), hal_uart_has_reader(), the instance
 * counts (hal_servo_count(), hal_sonar_count()) and the bump switches (hal_bump_*) are
 * optional: link hal_unsupported (hal/defaults) and a board without them answers "no
 * storage", "nothing received", "a listener may be there", "the paper's servo and sonar
 * only" and "no switches".
 * A board that has them defines them here, and its definitions replace the defaults.
 */
#include "hal/hal.h"

int hal_init(void)
{
    /* Clocks, then every peripheral below in a safe state: motors off, servo idle. */
    return HAL_OK;
}

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    /* A timer interrupt every HAL_TICK_PERIOD_US that calls fn(ctx). */
    (void)fn;
    (void)ctx;
    return HAL_ENOSYS;
}

uint32_t hal_time_us(void)
{
    /* A free-running microsecond counter. */
    return 0u;
}

uint32_t hal_tick_overruns(void)
{
    return 0u;
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    /* The wheel's 16-bit quadrature counter, counting up when it rolls forward. */
    (void)wheel;
    return 0u;
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    /* PWM duty |duty| / HAL_DUTY_MAX, direction from the sign. */
    (void)wheel;
    (void)duty;
}

/* Instance 0 sweeps the paper's sonar; hal_unsupported's hal_servo_count() and
 * hal_sonar_count() answer 1. A board with more sensors lists them in a table and defines
 * both counts. */

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    /* 50 Hz servo PWM with this high time. */
    (void)pulse_us;
    return servo < hal_servo_count() ? HAL_OK : HAL_EINVAL;
}

int hal_sonar_trigger(uint8_t sonar)
{
    /* A 10 µs trigger pulse; the echo's width is captured by hardware or an edge ISR. */
    return sonar < hal_sonar_count() ? HAL_ENOSYS : HAL_EINVAL;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    (void)echo_us;
    return sonar < hal_sonar_count() ? HAL_SONAR_IDLE : HAL_EINVAL;
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    /* Queue into a ring that the UART interrupt drains; never block. */
    (void)data;
    (void)len;
    return 0u;
}

hal_irq_state_t hal_critical_enter(void)
{
    /* Save the interrupt mask and disable the tick's interrupt. */
    return 0u;
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
}

void hal_watchdog_kick(void)
{
}
