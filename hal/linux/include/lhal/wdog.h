/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The stall test of the software watchdog: has a thread, or the background loop, stopped?
 *
 * Each thread of the backend stamps the time as it goes round: the tick after every tick,
 * the events and output threads at least every LX_BEAT (they wait with a timeout), and
 * robot_idle() through hal_watchdog_kick() only while ticks progress. A thread stuck in a
 * call that never returns (a PWM write on a hung I2C bus) or dead stamps no more. The
 * watchdog thread asks, about every 10 ms, whether any stamp is older than its limit, and
 * stops the motors if so. Times are ns of one monotonic clock, injected by the caller; a
 * stamp newer than "now" (taken just before it was read) counts as fresh.
 */
#ifndef LHAL_WDOG_H
#define LHAL_WDOG_H

#include <stdint.h>

/** The limit of the issue: motors stop when no tick completed for longer than this. The
 *  events and output threads get the same. */
#define WDOG_TICK_LIMIT_NS 100000000u

/** What the watchdog concludes, the first stale stamp in this order. */
typedef enum {
    WDOG_OK = 0,       /**< every stamp is fresh */
    WDOG_TICK_STALL,   /**< no tick completed within tick_limit_ns */
    WDOG_EVENTS_STALL, /**< the events thread did not go round within tick_limit_ns */
    WDOG_OUTPUT_STALL, /**< the output thread did not go round (a write hangs) */
    WDOG_IDLE_STALL,   /**< no kick within idle_limit_ns (the background loop is stuck) */
} wdog_verdict_t;

/** Limits. */
typedef struct {
    uint64_t tick_limit_ns; /**< WDOG_TICK_LIMIT_NS, for the tick, events and output threads */
    uint64_t idle_limit_ns; /**< 0: the kicks are not watched */
} wdog_t;

/** When each thread last showed that it runs. */
typedef struct {
    uint64_t tick_ns;   /**< a tick completed */
    uint64_t events_ns; /**< the events thread went round */
    uint64_t output_ns; /**< the output thread went round */
    uint64_t kick_ns;   /**< robot_idle() kicked */
} wdog_stamps_t;

/**
 * Judge the stamps. A stamp exactly at its limit is still fresh.
 * @param age_ns  out: the age of the stale stamp (or of the tick stamp when all is well)
 */
wdog_verdict_t wdog_check(const wdog_t *w, uint64_t now_ns, const wdog_stamps_t *s,
                          uint64_t *age_ns);

#endif /* LHAL_WDOG_H */
