/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The stall test of the software watchdog: has the tick, or the background loop, stopped?
 *
 * The tick thread stamps the time after every tick; robot_idle() calls hal_watchdog_kick()
 * only while ticks progress, which stamps the time too. The watchdog thread asks, about
 * every 10 ms, whether either stamp is older than its limit, and stops the motors if so.
 * Times are ns of one monotonic clock, injected by the caller; a stamp newer than "now"
 * (taken just before it was read) counts as fresh.
 */
#ifndef LHAL_WDOG_H
#define LHAL_WDOG_H

#include <stdint.h>

/** The tick limit of the issue: motors stop when no tick completed for longer than this. */
#define WDOG_TICK_LIMIT_NS 100000000u

/** What the watchdog concludes. */
typedef enum {
    WDOG_OK = 0,     /**< both stamps are fresh */
    WDOG_TICK_STALL, /**< no tick completed within tick_limit_ns */
    WDOG_IDLE_STALL, /**< no kick within idle_limit_ns (the background loop is stuck) */
} wdog_verdict_t;

/** Limits. */
typedef struct {
    uint64_t tick_limit_ns; /**< WDOG_TICK_LIMIT_NS */
    uint64_t idle_limit_ns; /**< 0: the kicks are not watched */
} wdog_t;

/**
 * Judge the stamps. A stamp exactly at the limit is still fresh.
 * @param age_ns  out: the age of the stale stamp (or of the tick stamp when all is well)
 */
wdog_verdict_t wdog_check(const wdog_t *w, uint64_t now_ns, uint64_t last_tick_ns,
                          uint64_t last_kick_ns, uint64_t *age_ns);

#endif /* LHAL_WDOG_H */
