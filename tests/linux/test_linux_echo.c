/* SPDX-License-Identifier: MIT */
/* Tests of the HC-SR04 echo timing: widths from edge timestamps, timeouts, a stuck line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "lhal/echo.h"
#include "slam/config.h"
#include "slam/sonar.h"

#define MS 1000000u
#define TIMEOUT_US 30000u
#define DEADLINE_NS (((uint64_t)TIMEOUT_US + ECHO_RISE_MAX_US) * 1000u)

/* The trigger happens at T0 on the caller's clock; edges have kernel timestamps that
 * deliberately live on another scale (K0), since the two are never compared. */
#define T0 5000000000ull
#define K0 77000000000ull

static echo_t e;

static int setup(void **state)
{
    (void)state;
    echo_init(&e, TIMEOUT_US, false);
    return 0;
}

/* One ping answered after an echo of width_ns; returns what the poll reports. */
static hal_sonar_status_t ping(uint64_t width_ns, uint32_t *width_us)
{
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    echo_edge(&e, K0 + 450000u, true);
    echo_edge(&e, K0 + 450000u + width_ns, false);
    return echo_poll(&e, T0 + 1u * MS, width_us);
}

static void test_width_from_edge_timestamps(void **state)
{
    (void)state;
    uint32_t w = 0;
    assert_int_equal(echo_poll(&e, T0, &w), HAL_SONAR_IDLE);
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    assert_int_equal(echo_poll(&e, T0, &w), HAL_SONAR_BUSY);
    echo_edge(&e, K0, true);
    assert_int_equal(echo_poll(&e, T0 + 1u, &w), HAL_SONAR_BUSY);
    echo_edge(&e, K0 + 5831000u, false);
    assert_int_equal(echo_poll(&e, T0 + 2u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 5831);
    /* Reported once. */
    w = 0;
    assert_int_equal(echo_poll(&e, T0 + 3u, &w), HAL_SONAR_IDLE);
    assert_int_equal(w, 0);
    assert_int_equal(e.pings, 1);
    assert_int_equal(e.echoes, 1);
}

static void test_width_rounds_to_the_nearest_microsecond(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(ping(5831499u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 5831);
    assert_int_equal(ping(5831500u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 5832);
}

static void test_width_to_distance_through_the_firmware(void **state)
{
    (void)state;
    slam_config_t cfg;
    slam_config_default(&cfg); /* 343 m/s */
    sonar_t s;
    sonar_init(&s, &cfg);
    uint32_t w;
    /* 1 m and back at 343 m/s takes 5830.9 µs. */
    assert_int_equal(ping(5830904u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 5831);
    assert_int_equal(sonar_range_um(&s, w), 1000017);             /* 5831 · 171.5 µm, rounded */
    assert_false(sonar_in_confidence(&s, sonar_range_um(&s, w))); /* d >= rc = 1 m */
    assert_int_equal(ping(2915452u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 2915);
    assert_int_equal(sonar_range_um(&s, w), 499923); /* 2915 · 171.5 = 499922.5, rounded up */
    assert_true(sonar_in_confidence(&s, sonar_range_um(&s, w)));
}

static void test_echo_at_the_timeout_is_out_of_range(void **state)
{
    (void)state;
    uint32_t w = 12345;
    assert_int_equal(ping((uint64_t)(TIMEOUT_US - 1u) * 1000u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, TIMEOUT_US - 1u);
    w = 12345;
    assert_int_equal(ping((uint64_t)TIMEOUT_US * 1000u, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(w, 12345); /* untouched with a timeout */
    assert_int_equal(e.out_of_range, 1);
    assert_int_equal(e.echoes, 1);
}

static void test_no_rise_times_out_at_the_deadline(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS - 1u, &w), HAL_SONAR_BUSY);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS + 1u, &w), HAL_SONAR_IDLE);
    assert_int_equal(e.no_response, 1);
}

static void test_stuck_high_echo_is_reported_not_waited_on(void **state)
{
    (void)state;
    uint32_t w;
    /* The echo rises and never falls. */
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    echo_edge(&e, K0, true);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS - 1u, &w), HAL_SONAR_BUSY);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(e.long_echo, 1);
    /* The next ping finds the line still high: a timeout at once, counted as stuck. */
    uint64_t t1 = T0 + 100u * MS;
    assert_int_equal(echo_trigger(&e, t1), HAL_OK);
    assert_int_equal(echo_poll(&e, t1, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(e.stuck_high, 1);
    assert_int_equal(echo_poll(&e, t1, &w), HAL_SONAR_IDLE);
    /* When the line comes down, pings work again. */
    echo_edge(&e, K0 + 200u * MS, false);
    assert_int_equal(e.stray, 1);
    uint64_t t2 = t1 + 100u * MS;
    assert_int_equal(echo_trigger(&e, t2), HAL_OK);
    assert_int_equal(echo_poll(&e, t2, &w), HAL_SONAR_BUSY);
}

static void test_line_high_at_start_is_stuck(void **state)
{
    (void)state;
    echo_init(&e, TIMEOUT_US, true);
    uint32_t w;
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    assert_int_equal(echo_poll(&e, T0, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(e.stuck_high, 1);
}

static void test_second_trigger_is_busy_until_the_deadline(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    assert_int_equal(echo_trigger(&e, T0 + DEADLINE_NS - 1u), HAL_EBUSY);
    assert_int_equal(e.pings, 1);
    /* Past the deadline the old ping is over even though nobody polled it. */
    assert_int_equal(echo_trigger(&e, T0 + DEADLINE_NS), HAL_OK);
    assert_int_equal(e.pings, 2);
    assert_int_equal(e.no_response, 1);
    assert_int_equal(echo_poll(&e, T0 + DEADLINE_NS, &w), HAL_SONAR_BUSY);
}

static void test_unpolled_result_is_dropped_by_the_next_trigger(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    echo_edge(&e, K0, true);
    echo_edge(&e, K0 + 1u * MS, false);
    assert_int_equal(echo_trigger(&e, T0 + 50u * MS), HAL_OK);
    assert_int_equal(echo_poll(&e, T0 + 50u * MS, &w), HAL_SONAR_BUSY);
}

static void test_lost_falling_edge_times_from_the_latest_rise(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    echo_edge(&e, K0, true);
    echo_edge(&e, K0 + 3u * MS, true); /* the falling edge between was lost */
    echo_edge(&e, K0 + 5u * MS, false);
    assert_int_equal(echo_poll(&e, T0 + 1u, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 2000);
    assert_int_equal(e.lost, 1);
}

static void test_edges_outside_a_ping_are_stray(void **state)
{
    (void)state;
    uint32_t w;
    echo_edge(&e, K0, true);
    echo_edge(&e, K0 + 1u, false);
    assert_int_equal(e.stray, 2);
    assert_int_equal(echo_poll(&e, T0, &w), HAL_SONAR_IDLE);
    /* A falling edge while waiting for the rise is stray too, and the wait goes on. */
    assert_int_equal(echo_trigger(&e, T0), HAL_OK);
    echo_edge(&e, K0 + 2u, false);
    assert_int_equal(e.stray, 3);
    assert_int_equal(echo_poll(&e, T0 + 1u, &w), HAL_SONAR_BUSY);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_width_from_edge_timestamps, setup),
        cmocka_unit_test_setup(test_width_rounds_to_the_nearest_microsecond, setup),
        cmocka_unit_test_setup(test_width_to_distance_through_the_firmware, setup),
        cmocka_unit_test_setup(test_echo_at_the_timeout_is_out_of_range, setup),
        cmocka_unit_test_setup(test_no_rise_times_out_at_the_deadline, setup),
        cmocka_unit_test_setup(test_stuck_high_echo_is_reported_not_waited_on, setup),
        cmocka_unit_test_setup(test_line_high_at_start_is_stuck, setup),
        cmocka_unit_test_setup(test_second_trigger_is_busy_until_the_deadline, setup),
        cmocka_unit_test_setup(test_unpolled_result_is_dropped_by_the_next_trigger, setup),
        cmocka_unit_test_setup(test_lost_falling_edge_times_from_the_latest_rise, setup),
        cmocka_unit_test_setup(test_edges_outside_a_ping_are_stray, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
