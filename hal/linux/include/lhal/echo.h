/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The HC-SR04's echo, timed from edge events: a trigger, then the echo line's rising and
 * falling edges with kernel timestamps give the pulse width in µs.
 *
 * The sensor raises its echo line a few hundred µs after the trigger pulse and holds it
 * high for the sound's round trip (about 38 ms when nothing answers). A ping ends
 *   - with an echo: the falling edge came and the width is below timeout_us;
 *   - with a timeout: the width reached timeout_us (nothing within range), or the ping's
 *     deadline (trigger + timeout_us + ECHO_RISE_MAX_US) passed without a falling edge;
 *   - at once with a timeout when the echo line is already high at the trigger: a line
 *     stuck high is reported (stuck_high counts it), never waited on.
 *
 * Two clocks meet here and are never compared: the width is the difference of two kernel
 * edge timestamps; the deadline is measured on the caller's clock (now_ns, monotonic),
 * from the trigger. Edges outside a ping are counted as stray and only track the level.
 * No locking: the caller serialises calls (the backend holds a mutex).
 */
#ifndef LHAL_ECHO_H
#define LHAL_ECHO_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal.h"

/** How long after the trigger the echo may take to rise, on top of timeout_us. */
#define ECHO_RISE_MAX_US 5000u

/** Where a ping is. */
typedef enum {
    ECHO_IDLE = 0,  /**< no ping, or its result was reported */
    ECHO_WAIT_RISE, /**< triggered, the echo has not risen yet */
    ECHO_WAIT_FALL, /**< the echo is high */
    ECHO_DONE,      /**< a result waits to be reported */
} echo_phase_t;

/** Echo timing state and counters. */
typedef struct {
    uint32_t timeout_us;   /**< a width at or beyond this is out of range */
    uint8_t phase;         /**< an echo_phase_t */
    bool line_high;        /**< the echo line's level as the edges tell it */
    uint64_t trigger_ns;   /**< caller's clock at the trigger */
    uint64_t rise_ns;      /**< kernel timestamp of the rising edge */
    uint8_t result;        /**< HAL_SONAR_ECHO or HAL_SONAR_TIMEOUT, with ECHO_DONE */
    uint32_t width_us;     /**< the width, with HAL_SONAR_ECHO */
    uint32_t pings;        /**< triggers accepted */
    uint32_t echoes;       /**< pings that ended with an echo */
    uint32_t out_of_range; /**< pings whose echo reached timeout_us */
    uint32_t no_response;  /**< pings whose echo never rose */
    uint32_t long_echo;    /**< pings whose echo was still high at the deadline */
    uint32_t stuck_high;   /**< pings refused because the line was high at the trigger */
    uint32_t stray;        /**< edges outside a ping */
    uint32_t lost;         /**< edges that repeated the line's level (one was lost) */
} echo_t;

/**
 * Start idle.
 * @param timeout_us  widths at or beyond this are timeouts, > 0
 * @param line_high   the echo line's level now
 */
void echo_init(echo_t *e, uint32_t timeout_us, bool line_high);

/**
 * A ping is being triggered now. A result that was never polled is dropped.
 * @param now_ns  the caller's monotonic clock
 * @retval HAL_OK     the caller sends the trigger pulse (with a stuck-high line the
 *                    result is already a timeout)
 * @retval HAL_EBUSY  the previous ping is still within its deadline
 */
int echo_trigger(echo_t *e, uint64_t now_ns);

/** An edge of the echo line. @param ts_ns  its kernel timestamp */
void echo_edge(echo_t *e, uint64_t ts_ns, bool rising);

/**
 * The ping's state, as hal_sonar_poll() reports it: ECHO and TIMEOUT once, then IDLE.
 * @param now_ns    the caller's monotonic clock (for the deadline)
 * @param width_us  out: the pulse width, set with HAL_SONAR_ECHO
 */
hal_sonar_status_t echo_poll(echo_t *e, uint64_t now_ns, uint32_t *width_us);

#endif /* LHAL_ECHO_H */
