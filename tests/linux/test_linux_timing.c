/* SPDX-License-Identifier: MIT */
/* Tests of the tick accounting and the watchdog's stall test, on injected timestamps. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "lhal/tickstat.h"
#include "lhal/wdog.h"

#define MS 1000000ull
#define P (10u * MS)
#define T0 (1000u * MS)

static void test_punctual_ticks_are_clean(void **state)
{
    (void)state;
    tickstat_t t;
    tickstat_init(&t, P, 2u * MS, T0);
    for (uint64_t k = 0; k < 100; k++) {
        uint64_t start = T0 + k * P + 50000u; /* 50 µs late: normal */
        tickstat_wake(&t, 1u, start);
        tickstat_done(&t, start, start + 300000u);
    }
    assert_int_equal(t.ticks, 100);
    assert_int_equal(t.late, 0);
    assert_int_equal(t.overruns, 0);
    assert_int_equal(t.missed, 0);
    assert_int_equal(tickstat_faults(&t), 0);
    assert_int_equal(t.max_latency_ns, 50000u);
    assert_int_equal(t.max_run_ns, 300000u);
}

static void test_late_start_is_counted_beyond_the_threshold(void **state)
{
    (void)state;
    tickstat_t t;
    tickstat_init(&t, P, 2u * MS, T0);
    tickstat_wake(&t, 1u, T0 + 2u * MS); /* exactly at the threshold: not late */
    tickstat_done(&t, T0 + 2u * MS, T0 + 2u * MS + 1000u);
    assert_int_equal(t.late, 0);
    tickstat_wake(&t, 1u, T0 + P + 2u * MS + 1u);
    tickstat_done(&t, T0 + P + 2u * MS + 1u, T0 + P + 3u * MS);
    assert_int_equal(t.late, 1);
    assert_int_equal(t.max_latency_ns, 2u * MS + 1u);
    assert_int_equal(tickstat_faults(&t), 1);
}

static void test_overrun_is_a_tick_ending_after_the_next_was_due(void **state)
{
    (void)state;
    tickstat_t t;
    tickstat_init(&t, P, 2u * MS, T0);
    tickstat_wake(&t, 1u, T0);
    tickstat_done(&t, T0, T0 + P); /* ends just as the next is due: fine */
    assert_int_equal(t.overruns, 0);
    tickstat_wake(&t, 1u, T0 + P + 1u * MS);
    tickstat_done(&t, T0 + P + 1u * MS, T0 + 2u * P + 1u); /* 9 ms run after 1 ms latency */
    assert_int_equal(t.overruns, 1);
    assert_int_equal(t.late, 0);
    assert_int_equal(t.max_run_ns, P); /* the first tick ran a whole period */
}

static void test_missed_expirations_are_counted_and_the_schedule_kept(void **state)
{
    (void)state;
    tickstat_t t;
    tickstat_init(&t, P, 2u * MS, T0);
    tickstat_wake(&t, 1u, T0);
    tickstat_done(&t, T0, T0 + 1000u);
    /* The thread slept through two periods: the read returns 3 expirations. */
    tickstat_wake(&t, 3u, T0 + 3u * P + 100u);
    tickstat_done(&t, T0 + 3u * P + 100u, T0 + 3u * P + 200u);
    assert_int_equal(t.missed, 2);
    assert_int_equal(t.late, 0); /* measured from the latest expiry, not the first missed */
    assert_int_equal(t.ticks, 2);
    /* The next tick is due one period later. */
    tickstat_wake(&t, 1u, T0 + 4u * P);
    assert_int_equal(t.max_latency_ns, 100u);
    assert_int_equal(tickstat_faults(&t), 2);
    /* A zero count (never returned by a timerfd) counts as one expiry. */
    tickstat_wake(&t, 0u, T0 + 5u * P);
    assert_int_equal(t.missed, 2);
    assert_int_equal(t.late, 0);
}

static void test_fault_total_saturates(void **state)
{
    (void)state;
    tickstat_t t;
    tickstat_init(&t, P, 2u * MS, T0);
    tickstat_wake(&t, (uint64_t)UINT32_MAX + 10u, T0 + ((uint64_t)UINT32_MAX + 9u) * P);
    assert_int_equal(t.missed, UINT32_MAX);
    assert_int_equal(tickstat_faults(&t), UINT32_MAX);
}

/* ---- watchdog ------------------------------------------------------------------------ */

/* Every stamp fresh at `now`, then one of them moved back. */
static wdog_stamps_t stamps(uint64_t now)
{
    return (wdog_stamps_t){.tick_ns = now, .events_ns = now, .output_ns = now, .kick_ns = now};
}

static void test_watchdog_trips_only_beyond_100_ms(void **state)
{
    (void)state;
    const wdog_t w = {.tick_limit_ns = WDOG_TICK_LIMIT_NS, .idle_limit_ns = 0u};
    uint64_t age = 0u;
    assert_int_equal(WDOG_TICK_LIMIT_NS, 100u * MS);
    wdog_stamps_t s = stamps(T0);
    s.kick_ns = 0u;
    assert_int_equal(wdog_check(&w, T0 + 100u * MS, &s, &age), WDOG_OK);
    assert_int_equal(age, 100u * MS);
    s.events_ns = s.output_ns = T0 + 100u * MS;
    assert_int_equal(wdog_check(&w, T0 + 100u * MS + 1u, &s, &age), WDOG_TICK_STALL);
    assert_int_equal(age, 100u * MS + 1u);
    /* A stamp newer than "now" (written between the two reads) is fresh. */
    s = stamps(T0 + 5u);
    assert_int_equal(wdog_check(&w, T0, &s, &age), WDOG_OK);
    assert_int_equal(age, 0u);
}

/* The stamp at `field` of wdog_stamps_t is fresh at exactly `limit` old and stale (the
 * verdict, with its age) one nanosecond later, the others fresh. */
static void assert_stale_beyond(const wdog_t *w, size_t field, uint64_t limit, wdog_verdict_t v)
{
    uint64_t age = 0u;
    uint64_t now = T0 + 5000u * MS;
    wdog_stamps_t s = stamps(now);
    uint64_t *stamp = (uint64_t *)(void *)((char *)&s + field);
    *stamp = now - limit;
    assert_int_equal(wdog_check(w, now, &s, &age), WDOG_OK);
    (*stamp)--;
    assert_int_equal(wdog_check(w, now, &s, &age), v);
    assert_int_equal(age, limit + 1u);
}

/* A thread that is stuck (a write that never returns) or dead stamps no more. */
static void test_watchdog_watches_every_thread(void **state)
{
    (void)state;
    const wdog_t w = {.tick_limit_ns = 100u * MS, .idle_limit_ns = 0u};
    assert_stale_beyond(&w, offsetof(wdog_stamps_t, events_ns), 100u * MS, WDOG_EVENTS_STALL);
    assert_stale_beyond(&w, offsetof(wdog_stamps_t, output_ns), 100u * MS, WDOG_OUTPUT_STALL);
    /* The tick is named first, then the events thread, then the output thread. */
    uint64_t age = 0u;
    uint64_t now = T0 + 5000u * MS;
    wdog_stamps_t s = stamps(now);
    s.output_ns = now - 150u * MS;
    assert_int_equal(wdog_check(&w, now, &s, &age), WDOG_OUTPUT_STALL);
    s.events_ns = now - 120u * MS;
    assert_int_equal(wdog_check(&w, now, &s, &age), WDOG_EVENTS_STALL);
    s.tick_ns = now - 101u * MS;
    assert_int_equal(wdog_check(&w, now, &s, &age), WDOG_TICK_STALL);
    assert_int_equal(age, 101u * MS);
}

static void test_watchdog_watches_the_kicks_when_asked(void **state)
{
    (void)state;
    const wdog_t w = {.tick_limit_ns = 100u * MS, .idle_limit_ns = 2000u * MS};
    assert_stale_beyond(&w, offsetof(wdog_stamps_t, kick_ns), 2000u * MS, WDOG_IDLE_STALL);
    /* A stalled tick is the first thing said. */
    uint64_t age = 0u;
    uint64_t now = T0 + 5000u * MS;
    wdog_stamps_t s = stamps(now);
    s.tick_ns = now - 200u * MS;
    s.kick_ns = now - 3000u * MS;
    assert_int_equal(wdog_check(&w, now, &s, &age), WDOG_TICK_STALL);
    assert_int_equal(age, 200u * MS);
    /* With no idle limit the kicks are ignored. */
    const wdog_t off = {.tick_limit_ns = 100u * MS, .idle_limit_ns = 0u};
    s = stamps(now);
    s.kick_ns = 0u;
    assert_int_equal(wdog_check(&off, now, &s, &age), WDOG_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_punctual_ticks_are_clean),
        cmocka_unit_test(test_late_start_is_counted_beyond_the_threshold),
        cmocka_unit_test(test_overrun_is_a_tick_ending_after_the_next_was_due),
        cmocka_unit_test(test_missed_expirations_are_counted_and_the_schedule_kept),
        cmocka_unit_test(test_fault_total_saturates),
        cmocka_unit_test(test_watchdog_trips_only_beyond_100_ms),
        cmocka_unit_test(test_watchdog_watches_every_thread),
        cmocka_unit_test(test_watchdog_watches_the_kicks_when_asked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
