/* SPDX-License-Identifier: MIT */
/* Tests of the simulated robot's instance tables: a second sonar, a second servo, bump switches,
 * through the world and the host HAL. */
#include <math.h>

#include "hal/hal.h"
#include "hal_common/trace.h"
#include "host_test.h"
#include "one_sensor_board.h"

#define SOUND 343.0

/* A 6 m x 3 m room around the origin: walls at x = -3 and 3, y = -2 and 1. */
#define BOX "wall -3 -2 3 -2\nwall 3 -2 3 1\nwall 3 1 -3 1\nwall -3 1 -3 -2\nstart 0 0 0\n"

/* The robot with a fixed sonar on its left side looking left (the default row), ideal. */
static sim_t *side_world(const room_t *r, const sim_errors_t *e, uint64_t seed)
{
    sim_params_t p;
    sim_params_default(&p);
    p.extra_sonars = 1u;
    sim_t *s = sim_create(r, &p, e, seed);
    assert_non_null(s);
    return s;
}

static sim_t *ideal_side_world(const room_t *r)
{
    sim_errors_t e;
    sim_errors_ideal(&e);
    return side_world(r, &e, 1u);
}

/* Ping one sonar and wait for its answer: the status, and the width with an echo. */
static int ping_on(sim_t *s, uint8_t sonar, uint32_t *echo_us)
{
    assert_int_equal(sim_sonar_trigger_on(s, sonar), HAL_OK);
    for (int n = 0; n < 10; n++) {
        int st = sim_sonar_poll_on(s, sonar, echo_us);
        if (st != HAL_SONAR_BUSY) {
            return st;
        }
        sim_step(s);
    }
    fail_msg("sonar %u never answered", (unsigned)sonar);
    return -1;
}

/* A width as the range it stands for, m. */
static double range_of(uint32_t echo_us)
{
    return (double)echo_us * 1e-6 * SOUND / 2.0;
}

static void test_the_mount_table(void **state)
{
    (void)state;
    sim_params_t p;
    sim_params_default(&p);
    assert_int_equal(p.servos, 1u);
    assert_int_equal(p.extra_sonars, 0u); /* instance 1 is off unless asked for */
    assert_int_equal(p.bumps, 0u);
    assert_true(p.extra_sonar[0].servo == -1 && p.extra_sonar[0].yaw_deg == 90.0);

    sim_errors_t e;
    sim_errors_ideal(&e);
    const char *field = NULL;
    sim_params_t bad = p;
    bad.extra_sonars = SIM_SONARS_MAX;
    assert_int_equal(sim_params_check(&bad, &e, &field), -1);
    assert_string_equal(field, "p.extra_sonar");
    bad = p;
    bad.extra_sonars = 1u;
    bad.extra_sonar[0].servo = 1; /* the robot has one servo */
    assert_int_equal(sim_params_check(&bad, &e, &field), -1);
    assert_string_equal(field, "p.extra_sonar");
    bad.servos = 2u;
    assert_int_equal(sim_params_check(&bad, &e, NULL), 0);
    bad.servos = 0u;
    assert_int_equal(sim_params_check(&bad, &e, &field), -1);
    assert_string_equal(field, "p.servos");
    bad = p;
    bad.bumps = SIM_BUMPS_MAX + 1u;
    assert_int_equal(sim_params_check(&bad, &e, &field), -1);
    assert_string_equal(field, "p.bump");
    bad.bumps = 1u;
    bad.bump[0] = (sim_bump_t){30.0, 30.0};
    assert_int_equal(sim_params_check(&bad, &e, &field), -1);
    assert_string_equal(field, "p.bump");
}

static void test_second_sonar_answers_from_its_mount(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_t *s = ideal_side_world(&r);
    assert_int_equal(sim_sonar_count(s), 2u);
    assert_int_equal(sim_last_ping_on(s, 1u).kind, SIM_PING_NONE);
    uint32_t w0 = 0u;
    uint32_t w1 = 0u;
    /* Facing +x: the swept sonar (servo at 90°, 50 mm ahead) sees the east wall, the side
     * one (60 mm to the left, looking left) the north wall. */
    assert_int_equal(ping_on(s, 1u, &w1), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w1) - 0.94) < 0.002);
    sim_ping_t p1 = sim_last_ping_on(s, 1u);
    assert_true(fabs(p1.true_range_m - 0.94) < 1e-9);
    assert_true(fabs(p1.bearing - TEST_PI / 2.0) < 1e-12);
    assert_true(fabs(p1.servo_deg - 0.0) < 1e-12);          /* where a servo would point it so */
    assert_int_equal(sim_last_ping(s).kind, SIM_PING_NONE); /* sonar 0 did not ping */
    assert_int_equal(ping_on(s, 0u, &w0), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w0) - 2.95) < 0.002);
    assert_true(fabs(sim_last_ping_on(s, 1u).true_range_m - 0.94) < 1e-9); /* its own */

    /* Turned to face +y, the side sonar (now at x = -0.06) looks along -x: 2.94 m. */
    assert_int_equal(sim_place(s, 0.0, 0.0, TEST_PI / 2.0), 0);
    for (int k = 0; k < 6; k++) {
        sim_step(s); /* the last ping's sound dies away */
    }
    assert_int_equal(ping_on(s, 1u, &w1), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w1) - 2.94) < 0.002);
    assert_true(fabs(test_angle_diff(sim_last_ping_on(s, 1u).bearing, TEST_PI)) < 1e-12);
    sim_destroy(s);
    room_free(&r);
}

static void test_fixed_sonar_ignores_the_servo(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_t *s = ideal_side_world(&r);
    uint32_t w = 0u;
    sim_servo_set_pulse(s, 500u); /* the sweep servo to 0°: sonar 0 now looks left */
    for (int k = 0; k < 40; k++) {
        sim_step(s);
    }
    assert_int_equal(ping_on(s, 0u, &w), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w) - 1.0) < 0.002); /* the servo axis is on the centre line */
    for (int k = 0; k < 6; k++) {
        sim_step(s);
    }
    assert_int_equal(ping_on(s, 1u, &w), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w) - 0.94) < 0.002);
    assert_true(fabs(sim_last_ping_on(s, 1u).bearing - TEST_PI / 2.0) < 1e-12);
    sim_destroy(s);
    room_free(&r);
}

static void test_sonar_on_a_second_servo(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_params_t p;
    sim_params_default(&p);
    p.servos = 2u;
    p.extra_sonars = 1u;
    p.extra_sonar[0] = (sim_sonar_mount_t){.x_m = -0.05, .y_m = 0.0, .yaw_deg = 180.0, .servo = 1};
    sim_errors_t e;
    sim_errors_ideal(&e);
    sim_t *s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    assert_int_equal(sim_servo_count(s), 2u);
    assert_int_equal(sim_servo_set_pulse_on(s, 2u, 1500u), HAL_EINVAL);
    assert_int_equal(sim_servo_pulse_on(s, 2u), 0u);
    uint32_t w = 0u;
    /* Servo 1 at 90° turns the sonar mounted backwards straight back: the west wall. */
    assert_int_equal(ping_on(s, 1u, &w), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w) - 2.95) < 0.002);
    /* Servo 1 to 180° turns it 90° clockwise from there: to +y, the north wall. */
    assert_int_equal(sim_servo_set_pulse_on(s, 1u, 2500u), HAL_OK);
    assert_int_equal(sim_servo_pulse_on(s, 1u), 2500u);
    assert_int_equal(sim_servo_pulse(s), 1500u); /* servo 0 is not moved */
    for (int k = 0; k < 40; k++) {
        sim_step(s);
    }
    assert_true(fabs(sim_truth(s).servo_deg - 90.0) < 1e-9);
    assert_int_equal(ping_on(s, 1u, &w), HAL_SONAR_ECHO);
    assert_true(fabs(range_of(w) - 1.0) < 0.002);
    assert_true(fabs(sim_last_ping_on(s, 1u).servo_deg - 180.0) < 1e-9);
    assert_true(fabs(sim_last_ping_on(s, 1u).bearing - TEST_PI / 2.0) < 1e-9);
    sim_destroy(s);
    room_free(&r);
}

/* What sonar 0 reads in a run of pings, with sonar 1 fitted and pinging or not: sonar 1
 * draws from a stream of its own and hears only its own sound. */
static void sweep_readings(const room_t *r, bool with_side, uint32_t out[40])
{
    sim_errors_t e;
    sim_errors_default(&e);
    sim_t *s = with_side ? side_world(r, &e, 5u) : test_world(r, &e, 5u);
    for (int i = 0; i < 40; i++) {
        sim_servo_set_pulse(s, (uint16_t)(1000u + 25u * (unsigned)i));
        for (int k = 0; k < 6; k++) {
            sim_step(s);
        }
        uint32_t w = 0u;
        if (with_side) {
            (void)ping_on(s, 1u, &w);
        }
        out[i] = ping_on(s, 0u, &w) == HAL_SONAR_ECHO ? w : 0u;
    }
    sim_destroy(s);
}

static void test_sonar_1_leaves_sonar_0_as_it_was(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    uint32_t alone[40];
    uint32_t beside[40];
    sweep_readings(&r, false, alone);
    sweep_readings(&r, true, beside);
    assert_memory_equal(alone, beside, sizeof alone);
    room_free(&r);
}

static void test_indices_beyond_the_robot(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_t *s = test_ideal_world(&r);
    uint32_t w = 7u;
    bool pressed = true;
    assert_int_equal(sim_sonar_count(s), 1u);
    assert_int_equal(sim_sonar_trigger_on(s, 1u), HAL_EINVAL);
    assert_int_equal(sim_sonar_poll_on(s, 1u, &w), HAL_EINVAL);
    assert_int_equal(w, 7u);
    assert_int_equal(sim_last_ping_on(s, 1u).kind, SIM_PING_NONE);
    assert_int_equal(sim_servo_set_pulse_on(s, 1u, 1000u), HAL_EINVAL);
    assert_int_equal(sim_bump_count(s), 0u);
    assert_int_equal(sim_bump_read(s, 0u, &pressed), HAL_ENOSYS);
    assert_true(pressed);
    sim_destroy(s);
    room_free(&r);
}

/* Drive straight on at a quarter of full duty until the body touches something. */
static void drive_into(sim_t *s)
{
    sim_motor_set(s, HAL_WHEEL_LEFT, 250);
    sim_motor_set(s, HAL_WHEEL_RIGHT, 250);
    for (int k = 0; k < 2000 && !sim_truth(s).contact; k++) {
        sim_step(s);
    }
    assert_true(sim_truth(s).contact);
    sim_motor_set(s, HAL_WHEEL_LEFT, 0);
    sim_motor_set(s, HAL_WHEEL_RIGHT, 0);
    for (int k = 0; k < 50; k++) {
        sim_step(s);
    }
}

static void bumps_now(const sim_t *s, bool out[2])
{
    for (uint8_t i = 0; i < 2u; i++) {
        assert_int_equal(sim_bump_read(s, i, &out[i]), HAL_OK);
    }
}

static void test_bump_switches_close_within_their_arc(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_params_t p;
    sim_params_default(&p);
    p.bumps = 2u; /* front left, front right */
    sim_errors_t e;
    sim_errors_ideal(&e);
    sim_t *s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    assert_int_equal(sim_bump_count(s), 2u);
    bool b[2] = {true, true};
    bool pressed = false;
    assert_int_equal(sim_bump_read(s, 2u, &pressed), HAL_EINVAL);
    assert_int_equal(sim_bump_read(s, 0u, NULL), HAL_EINVAL);
    bumps_now(s, b);
    assert_false(b[0] || b[1]);

    /* Head-on into the east wall: both front switches. */
    assert_int_equal(sim_place(s, 2.0, -0.5, 0.0), 0);
    drive_into(s);
    bumps_now(s, b);
    assert_true(b[0] && b[1]);
    /* Backing away releases them. */
    sim_motor_set(s, HAL_WHEEL_LEFT, -250);
    sim_motor_set(s, HAL_WHEEL_RIGHT, -250);
    for (int k = 0; k < 30; k++) {
        sim_step(s);
    }
    assert_false(sim_truth(s).contact);
    bumps_now(s, b);
    assert_false(b[0] || b[1]);

    /* At 45° to the east wall, heading up and right: it is on the right. */
    assert_int_equal(sim_place(s, 2.0, -1.0, TEST_PI / 4.0), 0);
    drive_into(s);
    bumps_now(s, b);
    assert_false(b[0]);
    assert_true(b[1]);
    /* Heading down and right: on the left. */
    assert_int_equal(sim_place(s, 2.0, 0.0, -TEST_PI / 4.0), 0);
    drive_into(s);
    bumps_now(s, b);
    assert_true(b[0]);
    assert_false(b[1]);
    /* 5 mm from the wall, not touching it: nothing. */
    assert_int_equal(sim_place(s, 2.905, -0.5, 0.0), 0);
    sim_step(s);
    bumps_now(s, b);
    assert_false(b[0] || b[1]);
    sim_destroy(s);
    room_free(&r);
}

/* ---- through the host HAL ------------------------------------------------------------------ */

static unsigned side_pings;

/* A tick that pings sonar 1 (the firmware does not yet): a trace records sonar 0 alone. */
static void ping_side(void *ctx)
{
    (void)ctx;
    uint32_t w;
    if (hal_sonar_poll(1u, &w) != HAL_SONAR_BUSY && hal_sonar_trigger(1u) == HAL_OK) {
        side_pings++;
    }
}

static void test_hal_instances(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, BOX);
    sim_errors_t e;
    sim_errors_ideal(&e);

    /* The default robot: one of each, no switches. */
    sim_t *s = test_world(&r, &e, 1u);
    hal_host_attach(s);
    assert_int_equal(hal_init(), HAL_OK);
    assert_one_sensor_board();
    hal_host_attach(NULL);
    sim_destroy(s);

    /* A second sonar and two switches fitted. */
    uint32_t w = 7u;
    bool pressed = true;
    sim_params_t p;
    sim_params_default(&p);
    p.extra_sonars = 1u;
    p.bumps = 2u;
    s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    hal_host_attach(s);
    assert_int_equal(hal_init(), HAL_OK);
    assert_int_equal(hal_sonar_count(), 2u);
    assert_int_equal(hal_bump_count(), 2u);
    assert_int_equal(hal_sonar_trigger(2u), HAL_EINVAL);
    assert_int_equal(hal_bump_read(2u, &pressed), HAL_EINVAL);
    assert_int_equal(hal_bump_read(1u, &pressed), HAL_OK);
    assert_false(pressed);
    assert_int_equal(hal_sonar_trigger(1u), HAL_OK);
    assert_int_equal(hal_sonar_trigger(1u), HAL_EBUSY);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK); /* a ping of its own */
    int st = HAL_SONAR_BUSY;
    for (int k = 0; k < 10 && st == HAL_SONAR_BUSY; k++) {
        hal_host_step();
        st = hal_sonar_poll(1u, &w);
    }
    assert_int_equal(st, HAL_SONAR_ECHO);
    assert_int_equal(w, sim_last_ping_on(s, 1u).echo_us);
    assert_true(fabs(range_of(w) - 0.94) < 0.002);

    /* A trace records sonar 0 only: a tick that uses sonar 1 leaves its lines as they were. */
    const char *path = test_path("instances.trace");
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    slam_config_t cfg;
    slam_config_default(&cfg);
    trace_write_header(f, &cfg);
    hal_host_trace(f);
    side_pings = 0u;
    assert_int_equal(hal_tick_start(ping_side, NULL), HAL_OK);
    for (int k = 0; k < 30; k++) {
        hal_host_step();
    }
    hal_host_trace(NULL);
    fclose(f);
    assert_true(side_pings >= 3u);
    trace_tick_t *ticks = NULL;
    size_t n = 0u;
    char err[200];
    assert_int_equal(trace_read(path, &cfg, &ticks, &n, err, sizeof err), 0);
    assert_int_equal(n, 30u);
    for (size_t k = 0; k < n; k++) {
        assert_int_equal(ticks[k].poll, '-');
        assert_int_equal(ticks[k].trig, '-');
    }
    free(ticks);
    unlink(path);
    hal_host_attach(NULL);
    sim_destroy(s);
    room_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_mount_table),
        cmocka_unit_test(test_second_sonar_answers_from_its_mount),
        cmocka_unit_test(test_fixed_sonar_ignores_the_servo),
        cmocka_unit_test(test_sonar_on_a_second_servo),
        cmocka_unit_test(test_sonar_1_leaves_sonar_0_as_it_was),
        cmocka_unit_test(test_indices_beyond_the_robot),
        cmocka_unit_test(test_bump_switches_close_within_their_arc),
        cmocka_unit_test(test_hal_instances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
