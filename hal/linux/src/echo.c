/* SPDX-License-Identifier: MIT */
/* HC-SR04 echo timing from edge timestamps: widths, timeouts and a stuck-high line. */
#include "lhal/echo.h"

void echo_init(echo_t *e, uint32_t timeout_us, bool line_high)
{
    *e = (echo_t){0};
    e->timeout_us = timeout_us;
    e->line_high = line_high;
    e->phase = ECHO_IDLE;
}

static uint64_t echo_deadline_ns(const echo_t *e)
{
    return ((uint64_t)e->timeout_us + ECHO_RISE_MAX_US) * 1000u;
}

static bool echo_waiting(const echo_t *e)
{
    return e->phase == ECHO_WAIT_RISE || e->phase == ECHO_WAIT_FALL;
}

static void echo_finish(echo_t *e, hal_sonar_status_t result, uint32_t width_us)
{
    e->phase = ECHO_DONE;
    e->result = (uint8_t)result;
    e->width_us = width_us;
}

/* Ends a ping whose deadline has passed, counting why. Returns whether it did. */
static bool echo_expire(echo_t *e, uint64_t now_ns)
{
    if (!echo_waiting(e) || now_ns - e->trigger_ns < echo_deadline_ns(e)) {
        return false;
    }
    if (e->phase == ECHO_WAIT_RISE) {
        e->no_response++;
    } else {
        e->long_echo++;
    }
    echo_finish(e, HAL_SONAR_TIMEOUT, 0u);
    return true;
}

int echo_trigger(echo_t *e, uint64_t now_ns)
{
    if (echo_waiting(e) && !echo_expire(e, now_ns)) {
        return HAL_EBUSY;
    }
    e->pings++;
    e->trigger_ns = now_ns;
    if (e->line_high) {
        /* A line that is high before the sensor could answer is stuck: say so now. */
        e->stuck_high++;
        echo_finish(e, HAL_SONAR_TIMEOUT, 0u);
    } else {
        e->phase = ECHO_WAIT_RISE;
    }
    return HAL_OK;
}

void echo_edge(echo_t *e, uint64_t ts_ns, bool rising)
{
    if (rising == e->line_high) {
        e->lost++;
    }
    e->line_high = rising;

    if (e->phase == ECHO_WAIT_RISE && rising) {
        e->rise_ns = ts_ns;
        e->phase = ECHO_WAIT_FALL;
    } else if (e->phase == ECHO_WAIT_FALL && rising) {
        e->rise_ns = ts_ns; /* the falling edge was lost: time from the latest rise */
    } else if (e->phase == ECHO_WAIT_FALL) {
        uint64_t ns = ts_ns > e->rise_ns ? ts_ns - e->rise_ns : 0u;
        uint64_t us = (ns + 500u) / 1000u;
        if (us >= e->timeout_us) {
            e->out_of_range++;
            echo_finish(e, HAL_SONAR_TIMEOUT, 0u);
        } else {
            e->echoes++;
            echo_finish(e, HAL_SONAR_ECHO, (uint32_t)us);
        }
    } else {
        e->stray++;
    }
}

hal_sonar_status_t echo_poll(echo_t *e, uint64_t now_ns, uint32_t *width_us)
{
    echo_expire(e, now_ns);
    switch (e->phase) {
    case ECHO_WAIT_RISE:
    case ECHO_WAIT_FALL:
        return HAL_SONAR_BUSY;
    case ECHO_DONE:
        e->phase = ECHO_IDLE;
        if (e->result == HAL_SONAR_ECHO) {
            *width_us = e->width_us;
        }
        return (hal_sonar_status_t)e->result;
    default:
        return HAL_SONAR_IDLE;
    }
}
