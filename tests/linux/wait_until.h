/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Waiting in tests for what another thread does (the backend's tick, events and watchdog
 * threads). The bound of 60 s of real time only keeps a broken build from hanging; no
 * assertion depends on how long anything took.
 */
#ifndef TEST_WAIT_UNTIL_H
#define TEST_WAIT_UNTIL_H

#include <stdint.h>
#include <time.h>

static inline uint64_t wait_real_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static inline void wait_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/** Wait until @p cond holds (or the bound passes), then assert it. */
#define WAIT_UNTIL(cond)                                                                           \
    do {                                                                                           \
        uint64_t wait_end_ = wait_real_ns() + 60000000000ull;                                      \
        while (!(cond) && wait_real_ns() < wait_end_) {                                            \
            wait_ms(1);                                                                            \
        }                                                                                          \
        assert_true(cond);                                                                         \
    } while (0)

#endif /* TEST_WAIT_UNTIL_H */
