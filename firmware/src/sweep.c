/* SPDX-License-Identifier: MIT */
/* The servo sweep state machine: move, settle, ping, wait, one reading per stop. */
#include "slam/sweep.h"

#include <string.h>

SLAM_START_UP void sweep_init(sweep_t *s, const slam_config_t *cfg)
{
    memset(s, 0, sizeof *s);
    s->stops = cfg->sweep_stops;
    s->settle_ticks = cfg->settle_ticks;
    s->echo_timeout_ticks = cfg->echo_timeout_ticks;
    s->ping_interval_ticks = cfg->ping_interval_ticks;
    s->since_ping = UINT8_MAX; /* no ping yet: the first may go at once */

    int32_t span_mdeg = cfg->sweep_last_mdeg - cfg->sweep_first_mdeg;
    int32_t pulse_span_us = (int32_t)cfg->servo_pulse_180deg_us - cfg->servo_pulse_0deg_us;
    for (uint8_t i = 0; i < s->stops; i++) {
        int32_t mdeg = cfg->sweep_first_mdeg;
        if (s->stops > 1u) {
            mdeg += span_mdeg * i / (int32_t)(s->stops - 1u);
        }
        s->stop_mdeg[i] = mdeg;
        s->stop_bam[i] = fix_bam_from_mdeg(mdeg);
        /* Servo pulse linear in the angle between the 0° and 180° pulses, rounded. */
        int32_t pulse = cfg->servo_pulse_0deg_us + (pulse_span_us * mdeg + 90000) / 180000;
        s->stop_pulse_us[i] = (uint16_t)pulse;
    }
    s->phase = SWEEP_BEGIN;
}

bool sweep_waiting(const sweep_t *s)
{
    return s->phase == SWEEP_WAIT;
}

uint8_t sweep_stop_at(const sweep_t *s, uint8_t seq)
{
    return seq < s->stops ? seq : (uint8_t)(2u * s->stops - 1u - seq);
}

static void begin_stop(sweep_t *s, sweep_out_t *out)
{
    out->servo_cmd = true;
    out->servo_pulse_us = s->stop_pulse_us[sweep_stop_at(s, s->seq)];
    s->phase = SWEEP_SETTLE;
    s->ticks = 0u;
}

static void finish_stop(sweep_t *s, bool echo, uint32_t echo_us, sweep_out_t *out)
{
    uint8_t stop = sweep_stop_at(s, s->seq);
    out->reading_ready = true;
    out->reading = (sweep_reading_t){
        .stop = stop,
        .echo = echo,
        .servo_mdeg = s->stop_mdeg[stop],
        .servo = s->stop_bam[stop],
        .echo_us = echo ? echo_us : 0u,
    };
    if (echo) {
        s->echoes++;
    } else {
        s->timeouts++;
    }
    s->seq = (uint8_t)((s->seq + 1u) % (2u * s->stops));
    begin_stop(s, out);
}

void sweep_step(sweep_t *s, sweep_echo_t echo, uint32_t echo_us, sweep_out_t *out)
{
    memset(out, 0, sizeof *out);
    if (s->since_ping < UINT8_MAX) {
        s->since_ping++;
    }
    switch (s->phase) {
    case SWEEP_BEGIN:
        begin_stop(s, out);
        break;
    case SWEEP_SETTLE:
        if (s->ticks < s->settle_ticks) {
            s->ticks++;
        }
        /* The servo settles while the last ping's sound dies away: the stop costs the
         * longer of the two, not their sum. */
        if (s->ticks >= s->settle_ticks && s->since_ping >= s->ping_interval_ticks) {
            out->trigger = true;
            s->pings++;
            s->phase = SWEEP_WAIT;
            s->ticks = 0u;
            s->since_ping = 0u;
        }
        break;
    case SWEEP_WAIT:
    default:
        if (echo == SWEEP_ECHO_DONE) {
            finish_stop(s, true, echo_us, out);
        } else if (echo == SWEEP_ECHO_TIMEOUT || ++s->ticks >= s->echo_timeout_ticks) {
            finish_stop(s, false, 0u, out);
        }
        break;
    }
}
