/* SPDX-License-Identifier: MIT */
/* A scriptable HAL for unit tests: scripted inputs, recorded outputs, counted calls. */
#include "fake_hal.h"

#include <assert.h>
#include <string.h>

fake_hal_t fake_hal;

void fake_hal_reset(void)
{
    memset(&fake_hal, 0, sizeof fake_hal);
    memset(fake_hal.storage, 0xFF, sizeof fake_hal.storage); /* never written: erased */
    fake_hal.sonar_next = HAL_SONAR_BUSY;
    fake_hal.servos = 1u;
    fake_hal.sonars = 1u;
    fake_hal.storage_size = FAKE_HAL_STORAGE_SIZE;
    fake_hal.storage_cut_after = -1;
}

void fake_hal_power_on(void)
{
    fake_hal.storage_powered_off = false;
    fake_hal.storage_cut_after = -1;
    fake_hal.storage_erase_cut = 0u;
}

int hal_init(void)
{
    return HAL_OK;
}

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    (void)ctx;
    return fn == NULL ? HAL_EINVAL : HAL_OK;
}

uint32_t hal_time_us(void)
{
    return fake_hal.time_us;
}

uint32_t hal_tick_overruns(void)
{
    return 0u;
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    fake_hal.calls_encoder++;
    return fake_hal.encoder[wheel];
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    fake_hal.calls_motor++;
    fake_hal.motor[wheel] = duty;
}

uint8_t hal_servo_count(void)
{
    return fake_hal.servos;
}

uint8_t hal_sonar_count(void)
{
    return fake_hal.sonars;
}

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo >= fake_hal.servos || servo > 8u) {
        fake_hal.calls_bad_instance++;
        return HAL_EINVAL;
    }
    if (servo != HAL_SERVO_SWEEP) {
        fake_hal.calls_other_instance++;
        fake_hal.servo_pulse_other_us[servo - 1u] = pulse_us;
        return HAL_OK;
    }
    fake_hal.calls_servo++;
    fake_hal.servo_pulse_us = pulse_us;
    return HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar >= fake_hal.sonars) {
        fake_hal.calls_bad_instance++;
        return HAL_EINVAL;
    }
    if (sonar != HAL_SONAR_SWEPT) {
        fake_hal.calls_other_instance++;
        fake_hal.calls_trigger1 += sonar == 1u ? 1u : 0u;
        return HAL_OK;
    }
    fake_hal.calls_trigger++;
    return fake_hal.trigger_result;
}

/* A scripted sonar's answer: its echo's width with HAL_SONAR_ECHO, and ECHO or TIMEOUT
 * reported once. */
static int scripted_poll(hal_sonar_status_t *next, uint32_t width_us, uint32_t *echo_us)
{
    hal_sonar_status_t s = *next;
    if (s == HAL_SONAR_ECHO) {
        *echo_us = width_us;
    }
    if (s == HAL_SONAR_ECHO || s == HAL_SONAR_TIMEOUT) {
        *next = HAL_SONAR_IDLE;
    }
    return (int)s;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar >= fake_hal.sonars) {
        fake_hal.calls_bad_instance++;
        return HAL_EINVAL;
    }
    if (sonar != HAL_SONAR_SWEPT) {
        fake_hal.calls_other_instance++;
        if (sonar != 1u) {
            return HAL_SONAR_IDLE;
        }
        fake_hal.calls_poll1++;
        return scripted_poll(&fake_hal.sonar1_next, fake_hal.sonar1_echo_us, echo_us);
    }
    fake_hal.calls_poll++;
    return scripted_poll(&fake_hal.sonar_next, fake_hal.sonar_echo_us, echo_us);
}

uint8_t hal_bump_count(void)
{
    return fake_hal.bumps;
}

int hal_bump_read(uint8_t bump, bool *pressed)
{
    fake_hal.calls_bump++;
    if (fake_hal.bumps == 0u) {
        return HAL_ENOSYS;
    }
    if (bump >= fake_hal.bumps || bump >= 8u || pressed == NULL) {
        fake_hal.calls_bad_instance++;
        return HAL_EINVAL;
    }
    *pressed = fake_hal.bump_pressed[bump];
    return HAL_OK;
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    size_t n = fake_hal.uart_room != 0u && len > fake_hal.uart_room ? fake_hal.uart_room : len;
    if (n > FAKE_HAL_UART_SIZE - fake_hal.uart_len) {
        n = FAKE_HAL_UART_SIZE - fake_hal.uart_len;
    }
    memcpy(fake_hal.uart + fake_hal.uart_len, data, n);
    fake_hal.uart_len += n;
    return n;
}

bool hal_uart_has_reader(void)
{
    return !fake_hal.uart_no_reader;
}

size_t hal_uart_read(uint8_t *data, size_t len)
{
    size_t n = fake_hal.rx_len - fake_hal.rx_pos;
    n = n < len ? n : len;
    memcpy(data, fake_hal.rx + fake_hal.rx_pos, n);
    fake_hal.rx_pos += n;
    return n;
}

void fake_hal_receive(const uint8_t *data, size_t len)
{
    assert(len <= sizeof fake_hal.rx - fake_hal.rx_len);
    memcpy(fake_hal.rx + fake_hal.rx_len, data, len);
    fake_hal.rx_len += len;
}

size_t hal_storage_size(void)
{
    return fake_hal.storage_size;
}

int hal_storage_begin(uint8_t slot)
{
    fake_hal.calls_storage_begin++;
    fake_hal.storage_begin_moving += fake_hal.motor[0] != 0 || fake_hal.motor[1] != 0;
    if (fake_hal.storage_powered_off) {
        return HAL_EIO;
    }
    if (slot >= HAL_STORAGE_SLOTS) {
        return HAL_EINVAL;
    }
    fake_hal.storage_committed[slot] = false;
    if (fake_hal.calls_storage_begin == fake_hal.storage_erase_cut) {
        /* The erase stops part-way: the start is erased, the rest as it was, or half-erased
         * (bits that flipped to 1 at random). */
        uint32_t done = fake_hal.storage_erase_done;
        done = done > FAKE_HAL_STORAGE_SIZE ? FAKE_HAL_STORAGE_SIZE : done;
        memset(fake_hal.storage[slot], 0xFF, done);
        uint32_t x = 0x12345678u;
        for (uint32_t i = done; fake_hal.storage_erase_noise && i < FAKE_HAL_STORAGE_SIZE; i++) {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            fake_hal.storage[slot][i] |= (uint8_t)(x & (x >> 8));
        }
        fake_hal.storage_powered_off = true;
        return HAL_EIO;
    }
    memset(fake_hal.storage[slot], 0xFF, FAKE_HAL_STORAGE_SIZE);
    return HAL_OK;
}

static bool storage_range_ok(uint8_t slot, uint32_t offset, size_t len)
{
    return slot < HAL_STORAGE_SLOTS && offset <= FAKE_HAL_STORAGE_SIZE &&
           len <= FAKE_HAL_STORAGE_SIZE - offset;
}

/* Programs bytes: copies them, or on NOR flash clears only the bits that are 0 in them. */
static void program(uint8_t *dst, const uint8_t *src, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        dst[i] = fake_hal.storage_nor ? (uint8_t)(dst[i] & src[i]) : src[i];
    }
}

int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    fake_hal.calls_storage_write++;
    if (fake_hal.storage_powered_off ||
        (int)fake_hal.calls_storage_write == fake_hal.storage_fail_at) {
        return HAL_EIO;
    }
    if (!storage_range_ok(slot, offset, len)) {
        return HAL_EINVAL;
    }
    uint8_t *dst = &fake_hal.storage[slot][offset];
    if (fake_hal.storage_cut_after >= 0 && (size_t)fake_hal.storage_cut_after < len) {
        /* The power fails in this write: a part lands, one byte half-programmed. */
        size_t landed = (size_t)fake_hal.storage_cut_after;
        program(dst, data, landed);
        uint8_t target = ((const uint8_t *)data)[landed];
        uint8_t cleared = (uint8_t)(~target & fake_hal.storage_cut_bits);
        dst[landed] = (uint8_t)(dst[landed] & ~cleared);
        fake_hal.storage_powered_off = true;
        return HAL_EIO;
    }
    if (fake_hal.storage_cut_after >= 0) {
        fake_hal.storage_cut_after -= (long)len;
    }
    program(dst, data, len);
    return HAL_OK;
}

int hal_storage_commit(uint8_t slot)
{
    if (fake_hal.storage_powered_off) {
        return HAL_EIO;
    }
    if (slot >= HAL_STORAGE_SLOTS) {
        return HAL_EINVAL;
    }
    fake_hal.calls_storage_commit++;
    fake_hal.storage_committed[slot] = true;
    return HAL_OK;
}

int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    if (fake_hal.storage_powered_off) {
        return HAL_EIO;
    }
    if (!storage_range_ok(slot, offset, len)) {
        return HAL_EINVAL;
    }
    memcpy(data, &fake_hal.storage[slot][offset], len);
    return HAL_OK;
}

hal_irq_state_t hal_critical_enter(void)
{
    return 0u;
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
}

void hal_watchdog_kick(void)
{
    fake_hal.calls_watchdog++;
}
