/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Accounting of the periodic tick: which ticks started late, overran, or never ran.
 *
 * The tick thread waits on a periodic timerfd whose k-th expiry is due at
 * first_ns + k·period. Each wake-up reports how many expiries passed since the last read:
 * more than one means ticks were missed (the callback runs once, not once per missed
 * period: the encoders are counters, nothing is lost but time). A tick is late when it
 * starts more than late_ns after it was due, and overruns when it finishes after the next
 * tick was due. All times are ns of one monotonic clock, injected by the caller.
 */
#ifndef LHAL_TICKSTAT_H
#define LHAL_TICKSTAT_H

#include <stdint.h>

/** Tick accounting. */
typedef struct {
    uint64_t period_ns;      /**< the tick period */
    uint64_t late_ns;        /**< start latency beyond which a tick is late */
    uint64_t due_ns;         /**< when the tick now running (or next) was due */
    uint64_t ticks;          /**< callbacks run */
    uint32_t late;           /**< ticks that started late */
    uint32_t overruns;       /**< ticks that finished after the next was due */
    uint32_t missed;         /**< expiries that passed without a callback */
    uint64_t max_latency_ns; /**< worst start latency */
    uint64_t max_run_ns;     /**< longest callback */
} tickstat_t;

/** Start counting; @p first_due_ns is when the first expiry is due. */
void tickstat_init(tickstat_t *t, uint64_t period_ns, uint64_t late_ns, uint64_t first_due_ns);

/**
 * The tick thread woke up.
 * @param expirations  what the timerfd read returned (>= 1; 0 is taken as 1)
 * @param now_ns       the time the callback starts
 */
void tickstat_wake(tickstat_t *t, uint64_t expirations, uint64_t now_ns);

/** The callback returned at @p start_ns + run; @p end_ns is the time now. */
void tickstat_done(tickstat_t *t, uint64_t start_ns, uint64_t end_ns);

/** Late, overrun and missed ticks together: hal_tick_overruns(). */
uint32_t tickstat_faults(const tickstat_t *t);

#endif /* LHAL_TICKSTAT_H */
