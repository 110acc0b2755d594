/* SPDX-License-Identifier: MIT */
/* The replay HAL: a recorded scenario answers the firmware's HAL calls and checks its outputs. */
#include "hal_replay.h"

#include "hal/hal.h"

static const char poll_codes[] = {'-', 'i', 'b', 'e', 't'};
static const char trig_codes[] = {'-', 'o', 'b'};

#define HDR_POLL_MASK 0x07u
#define HDR_TRIG_SHIFT 3u
#define HDR_TRIG_MASK 0x03u
#define HDR_CHANGED 0x20u
#define HDR_RESERVED 0xC0u
#define CHG_DUTY_L 0x01u
#define CHG_DUTY_R 0x02u
#define CHG_SERVO 0x04u

static struct replay_state {
    const replay_scenario_t *sc;
    size_t pos;       /* next byte of the stream */
    bool in_tick;     /* a tick is decoded and robot_tick() may call */
    trace_tick_t rec; /* the record of the current tick; all 0 before the first */
    uint8_t polls;    /* hal_sonar_poll() calls in this tick */
    uint8_t triggers; /* hal_sonar_trigger() calls in this tick */
    int16_t duty[2];  /* outputs as the firmware set them */
    uint16_t servo_us;
    replay_status_t st;
} rp;

void replay_start(const replay_scenario_t *sc)
{
    rp = (struct replay_state){0};
    rp.sc = sc;
}

static bool get_byte(uint8_t *b)
{
    if (rp.pos >= rp.sc->stream_len) {
        return false;
    }
    *b = rp.sc->stream[rp.pos++];
    return true;
}

static bool get_varint(uint32_t *v)
{
    uint32_t value = 0u;
    for (unsigned shift = 0; shift < 35u; shift += 7u) {
        uint8_t b;
        if (!get_byte(&b) || (shift == 28u && (b & 0x70u) != 0u)) {
            return false; /* truncated, or more than 32 bits */
        }
        value |= (uint32_t)(b & 0x7Fu) << shift;
        if ((b & 0x80u) == 0u) {
            *v = value;
            return true;
        }
    }
    return false;
}

static bool get_zigzag(int32_t *v)
{
    uint32_t u;
    if (!get_varint(&u)) {
        return false;
    }
    *v = (u & 1u) ? -(int32_t)(u >> 1) - 1 : (int32_t)(u >> 1);
    return true;
}

static bool get_i16(int32_t *v)
{
    return get_zigzag(v) && *v >= INT16_MIN && *v <= INT16_MAX;
}

static int corrupt(void)
{
    rp.st.corrupt = true;
    rp.in_tick = false;
    return -2;
}

int replay_next(trace_tick_t *out)
{
    rp.in_tick = false;
    if (rp.sc == NULL || rp.st.corrupt) {
        return -2;
    }
    if (rp.st.ticks == rp.sc->ticks) {
        return rp.pos == rp.sc->stream_len ? -1 : corrupt();
    }
    uint8_t hdr;
    int32_t d[2];
    if (!get_byte(&hdr) || (hdr & HDR_RESERVED) != 0u ||
        (hdr & HDR_POLL_MASK) >= sizeof poll_codes ||
        ((hdr >> HDR_TRIG_SHIFT) & HDR_TRIG_MASK) >= sizeof trig_codes || !get_i16(&d[0]) ||
        !get_i16(&d[1])) {
        return corrupt();
    }
    trace_tick_t *t = &rp.rec;
    t->poll = poll_codes[hdr & HDR_POLL_MASK];
    t->trig = trig_codes[(hdr >> HDR_TRIG_SHIFT) & HDR_TRIG_MASK];
    t->enc[0] = (uint16_t)(t->enc[0] + (uint16_t)d[0]);
    t->enc[1] = (uint16_t)(t->enc[1] + (uint16_t)d[1]);
    t->echo_us = 0u;
    if (t->poll == 'e' && !get_varint(&t->echo_us)) {
        return corrupt();
    }
    if ((hdr & HDR_CHANGED) != 0u) {
        uint8_t chg;
        int32_t v;
        uint32_t u;
        if (!get_byte(&chg) || chg == 0u || (chg & ~(CHG_DUTY_L | CHG_DUTY_R | CHG_SERVO)) != 0u) {
            return corrupt();
        }
        if ((chg & CHG_DUTY_L) != 0u) {
            if (!get_i16(&v)) {
                return corrupt();
            }
            t->duty[0] = (int16_t)v;
        }
        if ((chg & CHG_DUTY_R) != 0u) {
            if (!get_i16(&v)) {
                return corrupt();
            }
            t->duty[1] = (int16_t)v;
        }
        if ((chg & CHG_SERVO) != 0u) {
            if (!get_varint(&u) || u > UINT16_MAX) {
                return corrupt();
            }
            t->servo_us = (uint16_t)u;
        }
    }
    rp.polls = 0u;
    rp.triggers = 0u;
    rp.in_tick = true;
    rp.st.ticks++;
    if (out != NULL) {
        *out = *t;
    }
    return 0;
}

static void mismatch(replay_mismatch_t what, int32_t expected, int32_t got)
{
    if (rp.st.mismatches == 0u) {
        rp.st.first_tick = rp.st.ticks - 1u;
        rp.st.first = what;
        rp.st.first_expected = expected;
        rp.st.first_got = got;
    }
    if (rp.st.mismatches != UINT32_MAX) {
        rp.st.mismatches++;
    }
}

void replay_check(void)
{
    if (!rp.in_tick) {
        return;
    }
    const trace_tick_t *t = &rp.rec;
    if (rp.polls != (t->poll != '-' ? 1u : 0u)) {
        mismatch(REPLAY_MISMATCH_POLL, t->poll != '-', rp.polls);
    }
    if (rp.triggers != (t->trig != '-' ? 1u : 0u)) {
        mismatch(REPLAY_MISMATCH_TRIGGER, t->trig != '-', rp.triggers);
    }
    if (rp.duty[0] != t->duty[0]) {
        mismatch(REPLAY_MISMATCH_DUTY_L, t->duty[0], rp.duty[0]);
    }
    if (rp.duty[1] != t->duty[1]) {
        mismatch(REPLAY_MISMATCH_DUTY_R, t->duty[1], rp.duty[1]);
    }
    if (rp.servo_us != t->servo_us) {
        mismatch(REPLAY_MISMATCH_SERVO, t->servo_us, rp.servo_us);
    }
    rp.in_tick = false;
}

replay_status_t replay_status(void)
{
    return rp.st;
}

/* ---- the HAL calls robot_tick() makes -------------------------------------------------- */

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    return rp.rec.enc[wheel == HAL_WHEEL_RIGHT ? 1 : 0];
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    rp.duty[wheel == HAL_WHEEL_RIGHT ? 1 : 0] = duty;
}

/* A trace records the paper's servo and sonar (instance 0) only: the replay has no other
 * (hal_servo_count() and hal_sonar_count() are hal_unsupported's 1). */

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo != HAL_SERVO_SWEEP) {
        return HAL_EINVAL;
    }
    rp.servo_us = pulse_us;
    return HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar != HAL_SONAR_SWEPT) {
        return HAL_EINVAL;
    }
    if (rp.triggers < UINT8_MAX) {
        rp.triggers++;
    }
    /* A call the record does not have answers as a busy sensor would, and is counted. */
    return rp.in_tick && rp.rec.trig == 'o' && rp.triggers == 1u ? HAL_OK : HAL_EBUSY;
}

uint32_t hal_time_us(void)
{
    /* Replay time: the start of the current tick, as a clock read in the tick would see it. */
    uint32_t ticks = rp.st.ticks == 0u ? 0u : rp.st.ticks - 1u;
    return ticks * HAL_TICK_PERIOD_US;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar != HAL_SONAR_SWEPT) {
        return HAL_EINVAL;
    }
    if (rp.polls < UINT8_MAX) {
        rp.polls++;
    }
    if (!rp.in_tick || rp.polls != 1u) {
        return HAL_SONAR_IDLE;
    }
    switch (rp.rec.poll) {
    case 'b':
        return HAL_SONAR_BUSY;
    case 'e':
        *echo_us = rp.rec.echo_us;
        return HAL_SONAR_ECHO;
    case 't':
        return HAL_SONAR_TIMEOUT;
    default:
        return HAL_SONAR_IDLE;
    }
}

/* ---- the rest of the HAL, the same on every machine ----------------------------------- */

/* hal_uart_read(), map storage and the bump switches are hal/defaults' (nothing received,
 * HAL_ENOSYS, none). */

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    uint32_t crc = ~rp.st.uart_crc32;
    for (size_t i = 0; i < len; i++) {
        crc ^= data[i];
        for (unsigned k = 0; k < 8u; k++) {
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
        }
    }
    rp.st.uart_crc32 = ~crc;
    rp.st.uart_bytes += (uint32_t)len;
    return len;
}
