/* SPDX-License-Identifier: MIT */
/* Tests of the sweep state machine: order of stops, timing, one reading per stop, timeouts. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "slam/config.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/sweep.h"

/* How the simulated sonar answers a ping. */
typedef enum { ANSWER_ECHO, ANSWER_HAL_TIMEOUT, ANSWER_NEVER } answer_t;

/* A log of everything the sweep did, tick by tick. */
#define MAX_EVENTS 4096
typedef struct {
    unsigned servo_cmds;
    unsigned triggers;
    unsigned readings;
    uint32_t cmd_tick[MAX_EVENTS];
    uint32_t trigger_tick[MAX_EVENTS];
    uint32_t reading_tick[MAX_EVENTS];
    uint16_t pulse[MAX_EVENTS];
    sweep_reading_t reading[MAX_EVENTS];
} sweep_log_t;

static sweep_log_t lg;
static sweep_t sw;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    memset(&lg, 0, sizeof lg);
    slam_config_default(&cfg);
    slam_config_paper(&cfg); /* these tests hold the paper's Eq. 6 */
    return 0;
}

/* Runs the sweep for @p ticks; an echo of 1000 + 10·stop µs comes back echo_delay ticks
 * after each ping, or the sensor times out, or never answers. */
static void run(uint32_t ticks, answer_t (*answer)(unsigned ping), uint32_t echo_delay)
{
    sweep_init(&sw, &cfg);
    uint32_t ping_tick = 0;
    for (uint32_t t = 0; t < ticks; t++) {
        sweep_echo_t echo = SWEEP_ECHO_PENDING;
        uint32_t echo_us = 0;
        if (sweep_waiting(&sw) && t - ping_tick >= echo_delay) {
            switch (answer(lg.triggers - 1u)) {
            case ANSWER_ECHO:
                echo = SWEEP_ECHO_DONE;
                echo_us = 1000u + 10u * sweep_stop_at(&sw, sw.seq);
                break;
            case ANSWER_HAL_TIMEOUT:
                echo = SWEEP_ECHO_TIMEOUT;
                break;
            default:
                break;
            }
        }
        sweep_out_t out;
        sweep_step(&sw, echo, echo_us, &out);
        if (out.reading_ready) {
            lg.reading_tick[lg.readings] = t;
            lg.reading[lg.readings++] = out.reading;
        }
        if (out.servo_cmd) {
            lg.cmd_tick[lg.servo_cmds] = t;
            lg.pulse[lg.servo_cmds++] = out.servo_pulse_us;
        }
        if (out.trigger) {
            ping_tick = t;
            lg.trigger_tick[lg.triggers++] = t;
        }
        assert_true(lg.readings < MAX_EVENTS && lg.servo_cmds < MAX_EVENTS);
    }
}

static answer_t always_echo(unsigned ping)
{
    (void)ping;
    return ANSWER_ECHO;
}

static answer_t every_third_times_out(unsigned ping)
{
    return ping % 3u == 1u ? ANSWER_HAL_TIMEOUT : ANSWER_ECHO;
}

static answer_t never(unsigned ping)
{
    (void)ping;
    return ANSWER_NEVER;
}

static void test_order_of_stops(void **state)
{
    (void)state;
    run(1000, always_echo, 1);
    static const int32_t cycle[12] = {65, 83, 101, 119, 137, 155, 155, 137, 119, 101, 83, 65};
    assert_true(lg.readings > 36u);
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_int_equal(lg.reading[i].servo_mdeg, cycle[i % 12u] * 1000);
        assert_int_equal(lg.reading[i].servo, fix_bam_from_mdeg(cycle[i % 12u] * 1000));
        assert_true(lg.reading[i].echo);
        assert_int_equal(lg.reading[i].echo_us, 1000u + 10u * lg.reading[i].stop);
    }
    /* Servo pulses: linear from 500 µs at 0° to 2500 µs at 180°. */
    assert_int_equal(lg.pulse[0], 1222); /* 65° */
    assert_int_equal(lg.pulse[1], 1422); /* 83° */
    assert_int_equal(lg.pulse[5], 2222); /* 155° */
    assert_int_equal(lg.pulse[6], 2222); /* and back */
    assert_int_equal(lg.pulse[11], 1222);
}

static void test_one_reading_per_stop_and_settled_pings(void **state)
{
    (void)state;
    cfg.ping_interval_ticks = 1u; /* only the servo sets the pace here */
    run(2000, always_echo, 2);
    /* Every stop: command, then exactly settle_ticks later one ping, then one reading,
     * in whose tick the next stop is commanded. */
    assert_true(lg.readings > 50u);
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_int_equal(lg.trigger_tick[i] - lg.cmd_tick[i], cfg.settle_ticks);
        assert_int_equal(lg.reading_tick[i] - lg.trigger_tick[i], 2u);
        assert_int_equal(lg.cmd_tick[i + 1u], lg.reading_tick[i]);
    }
    assert_true(lg.servo_cmds == lg.readings + 1u);
    assert_true(lg.triggers == lg.readings || lg.triggers == lg.readings + 1u);
    /* A stop with a near obstacle takes 30 ms of settling plus 20 ms of echo: 50 ms. */
    assert_int_equal(lg.cmd_tick[1] - lg.cmd_tick[0], 5u);
    assert_int_equal(sw.pings, lg.triggers);
    assert_int_equal(sw.echoes, lg.readings);
    assert_int_equal(sw.timeouts, 0u);
}

/* Successive pings are at least ping_interval_ticks apart (60 ms by default, the
 * HC-SR04's measurement cycle), and no more than the servo and the echo need. */
static void test_pings_keep_their_interval(void **state)
{
    (void)state;
    assert_int_equal(cfg.ping_interval_ticks * SLAM_TICK_US, 60000u);
    static const struct {
        uint8_t interval;
        uint32_t echo_delay;
        uint32_t spacing; /* ticks from one trigger to the next */
    } cases[] = {
        {6u, 1u, 6u},               /* a near echo: the interval sets the pace */
        {6u, 3u, 6u},               /* the servo settles while the sound dies away */
        {6u, 4u, 7u},               /* a late answer, then 3 ticks of settling: 70 ms */
        {9u, 1u, 9u}, {1u, 1u, 4u}, /* no interval: 30 ms of settling and 10 ms of echo */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        memset(&lg, 0, sizeof lg);
        cfg.ping_interval_ticks = cases[c].interval;
        run(1000, always_echo, cases[c].echo_delay);
        assert_true(lg.triggers > 100u);
        for (unsigned i = 1; i < lg.triggers; i++) {
            assert_int_equal(lg.trigger_tick[i] - lg.trigger_tick[i - 1u], cases[c].spacing);
            assert_true(lg.trigger_tick[i] - lg.cmd_tick[i] >= cfg.settle_ticks);
        }
        assert_int_equal(lg.trigger_tick[0], cfg.settle_ticks); /* the first goes at once */
    }
}

static void test_configured_timing(void **state)
{
    (void)state;
    cfg.settle_ticks = 7u;
    cfg.echo_timeout_ticks = 2u;
    run(1000, never, 0);
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_int_equal(lg.trigger_tick[i] - lg.cmd_tick[i], 7u);
        assert_int_equal(lg.reading_tick[i] - lg.trigger_tick[i], 2u);
        assert_false(lg.reading[i].echo);
    }
    assert_int_equal(lg.readings, 1000u / 9u);
}

static grid_t grid;

/* A timeout gives a reading without an echo; mapped, it changes no OM cell, and the sweep
 * goes on to the next stop. Both the HAL's timeout and the sweep's own count. */
static void test_timeouts_map_nothing_and_sweep_goes_on(void **state)
{
    (void)state;
    run(3000, every_third_times_out, 1);
    unsigned timeouts = 0;
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_int_equal(lg.reading[i].echo, i % 3u != 1u);
        timeouts += !lg.reading[i].echo;
        if (!lg.reading[i].echo) {
            assert_int_equal(lg.reading[i].echo_us, 0u);
            /* the next stop was commanded in the same tick */
            assert_int_equal(lg.cmd_tick[i + 1u], lg.reading_tick[i]);
        }
    }
    assert_int_equal(sw.timeouts, timeouts);

    mapper_t m;
    mapper_init(&m, &cfg);
    grid_init(&grid, &cfg);
    odom_pose_t pose = {0, 0, 0u};
    sweep_out_t out = {.reading_ready = true};
    out.reading = lg.reading[1];
    mapper_tick(&m, &grid, &pose, &out);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(grid.om[i], 0);
    }
    assert_int_equal(m.timeouts, 1u);
    assert_int_equal(m.last, MAPPER_TIMEOUT);

    /* The sweep's own timeout when the sensor never answers: after echo_timeout_ticks. */
    memset(&lg, 0, sizeof lg);
    run(500, never, 0);
    assert_true(lg.readings > 20u);
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_false(lg.reading[i].echo);
        assert_int_equal(lg.reading_tick[i] - lg.trigger_tick[i], cfg.echo_timeout_ticks);
    }
}

static void test_single_stop(void **state)
{
    (void)state;
    cfg.sweep_stops = 1u;
    cfg.sweep_first_mdeg = cfg.sweep_last_mdeg = 90000;
    run(200, always_echo, 1);
    assert_true(lg.readings > 10u);
    for (unsigned i = 0; i < lg.readings; i++) {
        assert_int_equal(lg.reading[i].servo_mdeg, 90000);
        assert_int_equal(lg.reading[i].stop, 0u);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_order_of_stops, setup),
        cmocka_unit_test_setup(test_one_reading_per_stop_and_settled_pings, setup),
        cmocka_unit_test_setup(test_pings_keep_their_interval, setup),
        cmocka_unit_test_setup(test_configured_timing, setup),
        cmocka_unit_test_setup(test_timeouts_map_nothing_and_sweep_goes_on, setup),
        cmocka_unit_test_setup(test_single_stop, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
