/* SPDX-License-Identifier: MIT */
/* Tests of the world's wiring and timing faults: a stuck echo line, a lagging or stalled
 * servo, lost ticks, an encoder that stops counting; each off by default. */
#include <math.h>

#include "hal/hal.h"
#include "host_test.h"

#define HALL "wall -3 -3 9 -3\nwall 9 -3 9 3\nwall 9 3 -3 3\nwall -3 3 -3 -3\n"

static room_t room;

static int setup(void **state)
{
    (void)state;
    test_room(&room, HALL "start 0 0 0\n");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    room_free(&room);
    return 0;
}

static sim_t *faulty(void (*set)(sim_errors_t *e), uint64_t seed)
{
    sim_errors_t e;
    sim_errors_ideal(&e);
    if (set != NULL) {
        set(&e);
    }
    return test_world(&room, &e, seed);
}

static void stuck_often(sim_errors_t *e)
{
    e->echo_stuck_per_s = 0.5;
}

/* Pings during an episode time out as SIM_PING_STUCK, in runs of 0.5..3 s; the others
 * echo from the wall ahead. */
static void test_stuck_echo_line(void **state)
{
    (void)state;
    sim_t *s = faulty(stuck_often, 3u);
    assert_int_equal(sim_place(s, 7.0, 0.0, 0.0), 0); /* the east wall 2 m ahead */
    unsigned stuck = 0;
    unsigned echoes = 0;
    unsigned longest = 0;
    unsigned run = 0;
    for (int t = 0; t < 60000; t++) {
        if (t % 6 == 0) { /* the sonar's 60 ms cycle: no late echo of the ping before */
            assert_int_equal(sim_sonar_trigger(s), HAL_OK);
        }
        sim_step(s);
        uint32_t w = 0;
        hal_sonar_status_t st = sim_sonar_poll(s, &w);
        if (st == HAL_SONAR_ECHO || st == HAL_SONAR_TIMEOUT) {
            sim_ping_t p = sim_last_ping(s);
            if (p.kind == SIM_PING_STUCK) {
                assert_int_equal(st, HAL_SONAR_TIMEOUT);
                stuck++;
                run++;
                longest = run > longest ? run : longest;
            } else {
                assert_int_equal(p.kind, SIM_PING_ECHO);
                assert_int_equal(st, HAL_SONAR_ECHO);
                echoes++;
                run = 0;
            }
        }
    }
    /* 0.5 episodes a second of 1.75 s on average: about half the time stuck. */
    double share = (double)stuck / (stuck + echoes);
    print_message("stuck %u of %u pings, longest run %u pings\n", stuck, stuck + echoes, longest);
    assert_true(share > 0.25 && share < 0.6);
    assert_true(longest >= 25u && longest <= 51u); /* at most 3 s of pings 60 ms apart */
    sim_destroy(s);
}

static void lag(sim_errors_t *e)
{
    e->servo_lag = 0.75;
}

/* A lagging servo slews at a quarter of its speed: 1.5° a tick instead of 6°. */
static void test_servo_lag(void **state)
{
    (void)state;
    sim_t *s = faulty(lag, 1u);
    sim_servo_set_pulse(s, 500); /* 0° */
    sim_step(s);
    assert_true(fabs(sim_truth(s).servo_deg - 88.5) < 1e-9);
    for (int t = 0; t < 59; t++) {
        sim_step(s);
    }
    assert_true(fabs(sim_truth(s).servo_deg - 0.0) < 1e-9);
    sim_destroy(s);
}

static void stall(sim_errors_t *e)
{
    e->servo_stall_per_s = 1.0;
}

/* A stalled horn holds its angle whatever the pulse says, then moves on. */
static void test_servo_stall(void **state)
{
    (void)state;
    sim_t *s = faulty(stall, 7u);
    unsigned held = 0;
    unsigned moved = 0;
    for (int t = 0; t < 20000; t++) {
        sim_servo_set_pulse(s, (t / 20) % 2 ? 500 : 2500); /* 0° and 180° in turn */
        double before = sim_truth(s).servo_deg;
        sim_step(s);
        double after = sim_truth(s).servo_deg;
        bool asked = (t / 20) % 2 ? before > 0.0 : before < 180.0;
        if (asked) {
            held += after == before;
            moved += after != before;
        }
    }
    print_message("held %u, moved %u of the ticks the servo was asked to move\n", held, moved);
    assert_true(held > moved / 2u && moved > held / 2u); /* about 1.75 s stalled a second */
    sim_destroy(s);
    /* Without the fault it never holds when asked. */
    s = faulty(NULL, 7u);
    sim_servo_set_pulse(s, 500);
    double before = sim_truth(s).servo_deg;
    sim_step(s);
    assert_true(sim_truth(s).servo_deg < before);
    sim_destroy(s);
}

static unsigned ticks_run;

static void count_tick(void *ctx)
{
    (void)ctx;
    ticks_run++;
}

static void miss(sim_errors_t *e)
{
    e->tick_miss = 0.2;
}

/* A lost tick: the world moves on, the callback does not run, and the HAL counts an
 * overrun. */
static void test_missed_ticks(void **state)
{
    (void)state;
    sim_t *s = faulty(miss, 9u);
    hal_host_attach(s);
    assert_int_equal(hal_init(), HAL_OK);
    ticks_run = 0;
    assert_int_equal(hal_tick_start(count_tick, NULL), HAL_OK);
    for (int t = 0; t < 10000; t++) {
        hal_host_step();
    }
    sim_truth_t tr = sim_truth(s);
    assert_int_equal(tr.ticks, 10000u);
    assert_int_equal(ticks_run + tr.ticks_missed, 10000u);
    assert_int_equal(hal_tick_overruns(), (uint32_t)tr.ticks_missed);
    assert_true(tr.ticks_missed > 1800u && tr.ticks_missed < 2200u);
    hal_host_attach(NULL);
    sim_destroy(s);
}

static void enc_stop(sim_errors_t *e)
{
    e->encoder_stop_per_s = 0.5;
}

/* A stopped encoder holds its count while its wheel turns, then counts on from there:
 * the counts of the episode are lost, the other wheel's are not. */
static void test_encoder_stops(void **state)
{
    (void)state;
    sim_t *s = faulty(enc_stop, 11u);
    sim_t *ok = faulty(NULL, 11u);
    unsigned frozen = 0;
    for (int t = 0; t < 3000; t++) {
        int16_t duty = (int16_t)((t / 300) % 2 ? 400 : -400); /* turn in place, both ways */
        sim_motor_set(s, HAL_WHEEL_LEFT, duty);
        sim_motor_set(s, HAL_WHEEL_RIGHT, (int16_t)-duty);
        sim_motor_set(ok, HAL_WHEEL_LEFT, duty);
        sim_motor_set(ok, HAL_WHEEL_RIGHT, (int16_t)-duty);
        uint16_t l0 = sim_encoder_count(s, HAL_WHEEL_LEFT);
        uint16_t r0 = sim_encoder_count(s, HAL_WHEEL_RIGHT);
        uint16_t okl = sim_encoder_count(ok, HAL_WHEEL_LEFT);
        sim_step(s);
        sim_step(ok);
        bool moving = sim_encoder_count(ok, HAL_WHEEL_LEFT) != okl;
        frozen += moving && (sim_encoder_count(s, HAL_WHEEL_LEFT) == l0 ||
                             sim_encoder_count(s, HAL_WHEEL_RIGHT) == r0);
    }
    /* The world itself moved exactly as without the fault: only the counters lie. */
    sim_truth_t a = sim_truth(s);
    sim_truth_t b = sim_truth(ok);
    assert_true(a.x == b.x && a.y == b.y && a.th == b.th);
    print_message("a counter held in %u of 3000 ticks\n", frozen);
    assert_true(frozen > 500u && frozen < 2500u);
    sim_destroy(s);
    sim_destroy(ok);
}

/* Every fault is off by default and in the ideal world, and each level is checked. */
static void test_levels_checked(void **state)
{
    (void)state;
    sim_errors_t e;
    sim_errors_default(&e);
    assert_true(e.echo_stuck_per_s == 0.0 && e.servo_lag == 0.0 && e.servo_stall_per_s == 0.0 &&
                e.tick_miss == 0.0 && e.encoder_stop_per_s == 0.0);
    sim_params_t p;
    sim_params_default(&p);
    const char *bad = NULL;
    e.servo_lag = 0.96;
    assert_int_equal(sim_params_check(&p, &e, &bad), -1);
    assert_string_equal(bad, "e.servo_lag");
    e.servo_lag = 0.0;
    e.tick_miss = 0.91;
    assert_int_equal(sim_params_check(&p, &e, &bad), -1);
    assert_string_equal(bad, "e.tick_miss");
    e.tick_miss = 0.0;
    e.encoder_stop_per_s = (double)NAN;
    assert_int_equal(sim_params_check(&p, &e, &bad), -1);
    assert_string_equal(bad, "e.encoder_stop_per_s");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stuck_echo_line), cmocka_unit_test(test_servo_lag),
        cmocka_unit_test(test_servo_stall),     cmocka_unit_test(test_missed_ticks),
        cmocka_unit_test(test_encoder_stops),   cmocka_unit_test(test_levels_checked),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
