/* SPDX-License-Identifier: MIT */
/* Tests of hal.h on Linux against a fake GPIO chip, a temporary PWM tree and a frozen clock. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

#include <cmocka.h>

#include "fake_gpio.h"
#include "hal/hal.h"
#include "lhal/lhal.h"
#include "one_sensor_board.h"
#include "tmptree.h"
#include "wait_until.h"
#include "wiring.h"

#define MS 1000000ull

/* The fake's line offsets, in wiring.h's order; then, when a test wires them, sonar 1 and
 * two bump switches. */
enum {
    L_A = 1,
    L_B = 2,
    R_A = 3,
    R_B = 4,
    TRIG = 5,
    ECHO = 6,
    L_IN1 = 7,
    L_IN2 = 8,
    R_IN1 = 9,
    R_IN2 = 10,
    STBY = 11,
    TRIG1 = 12,
    ECHO1 = 13,
    BUMP0 = 14,
    BUMP1 = 15
};

static char root[TMPTREE_PATH_MAX];
static lconf_t cfg;

/* The backend's clock: frozen unless a test moves it. */
static _Atomic uint64_t fake_now_ns = 1000000u * MS;

static uint64_t fake_clock(void)
{
    return atomic_load(&fake_now_ns);
}

static void advance_ns(uint64_t ns)
{
    atomic_fetch_add(&fake_now_ns, ns);
}

static int setup(void **state)
{
    (void)state;
    fake_gpio_reset();
    tmptree_make(root, "backend");
    wiring_lconf(&cfg, "fakechip0", L_A, root);
    cfg.enc_invert[1] = true;
    cfg.motor_invert[1] = true;
    cfg.storage_bytes = 8192u;
    lhal_set_clock(fake_clock);
    return 0;
}

static int setup_up(void **state)
{
    setup(state);
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_OK);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    lhal_shutdown();
    tmptree_remove(root); /* first, so a failed check leaves nothing behind */
    assert_int_equal(fake_gpio_requested_count(), 0);
    return 0;
}

static const char *pwm(const char *rel)
{
    return tmptree_read(root, rel);
}

/* The output thread writes what hal.h posted: wait until it has. */
static void written(void)
{
    lhal_stats_t st;
    WAIT_UNTIL((lhal_stats(&st), st.outputs_written == st.outputs_posted));
}

static void test_init_requests_every_line_with_the_motors_stopped(void **state)
{
    (void)state;
    static const unsigned inputs[] = {L_A, L_B, R_A, R_B, ECHO};
    static const unsigned outputs[] = {TRIG, L_IN1, L_IN2, R_IN1, R_IN2, STBY};
    for (size_t i = 0; i < sizeof inputs / sizeof inputs[0]; i++) {
        assert_true(fake_gpio_requested(inputs[i]));
        assert_false(fake_gpio_is_output(inputs[i]));
    }
    for (size_t i = 0; i < sizeof outputs / sizeof outputs[0]; i++) {
        assert_true(fake_gpio_is_output(outputs[i]));
        assert_int_equal(fake_gpio_value(outputs[i]), 0);
    }
    assert_int_equal(fake_gpio_requested_count(), 11);
    assert_string_equal(pwm("pwmchip0/pwm0/period"), "50000\n");
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm0/enable"), "1\n");
    assert_string_equal(pwm("pwmchip0/pwm1/enable"), "1\n");
    /* The servo waits for its first command. */
    assert_string_equal(pwm("pwmchip1/pwm0/enable"), "");
    assert_int_equal(hal_storage_size(), 8192);
    assert_int_equal(hal_encoder_count(HAL_WHEEL_LEFT), 0);
    uint32_t w;
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_IDLE);
    assert_int_equal(hal_init(), HAL_OK); /* a second call changes nothing */
    assert_int_equal(fake_gpio_requested_count(), 11);
}

static void test_encoders_decode_both_lines_in_timestamp_order(void **state)
{
    (void)state;
    /* One forward cycle per wheel. Read line by line (all of A, then all of B) it would
     * count 0; in timestamp order it counts 4. */
    const fake_edge_t left[] = {
        {L_A, 1000, true}, {L_B, 2000, true}, {L_A, 3000, false}, {L_B, 4000, false}};
    fake_gpio_edges(left, 4);
    WAIT_UNTIL(hal_encoder_count(HAL_WHEEL_LEFT) == 4u);
    /* The right wheel is inverted: the same cycle counts down. */
    const fake_edge_t right[] = {
        {R_A, 5000, true}, {R_B, 6000, true}, {R_A, 7000, false}, {R_B, 8000, false}};
    fake_gpio_edges(right, 4);
    WAIT_UNTIL(hal_encoder_count(HAL_WHEEL_RIGHT) == (uint16_t)(0u - 4u));
    assert_int_equal(hal_encoder_count(HAL_WHEEL_LEFT), 4);

    /* A lost edge is counted, and moves nothing. */
    fake_gpio_edge(L_A, 9000, false);
    lhal_stats_t st;
    WAIT_UNTIL((lhal_stats(&st), st.enc_illegal[0] == 1u));
    assert_int_equal(st.enc_edges[0], 5);
    assert_int_equal(hal_encoder_count(HAL_WHEEL_LEFT), 4);
}

static hal_sonar_status_t poll_until_done(uint32_t *w)
{
    hal_sonar_status_t st = HAL_SONAR_BUSY;
    for (int i = 0; i < 10000 && st == HAL_SONAR_BUSY; i++) {
        st =
            (hal_sonar_status_t)hal_sonar_poll(HAL_SONAR_SWEPT, w); /* never an error for sonar 0 */
        if (st == HAL_SONAR_BUSY) {
            wait_ms(1);
        }
    }
    return st;
}

static void test_sonar_pulse_and_echo_width(void **state)
{
    (void)state;
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    written();
    assert_int_equal(fake_gpio_rises(TRIG), 1);
    assert_int_equal(fake_gpio_value(TRIG), 0);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_EBUSY);
    written();
    assert_int_equal(fake_gpio_rises(TRIG), 1); /* no second pulse */

    const fake_edge_t echo[] = {{ECHO, 70000000u, true}, {ECHO, 70000000u + 5831000u, false}};
    fake_gpio_edges(echo, 2);
    uint32_t w = 0;
    assert_int_equal(poll_until_done(&w), HAL_SONAR_ECHO);
    assert_int_equal(w, 5831);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_IDLE);
    lhal_stats_t st;
    lhal_stats(&st);
    assert_int_equal(st.sonar[0].pings, 1);
    assert_int_equal(st.sonar[0].echoes, 1);
}

static void test_sonar_times_out_on_the_backend_clock(void **state)
{
    (void)state;
    uint32_t w;
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    advance_ns(30 * MS); /* within sonar_timeout_us + 5 ms */
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_BUSY);
    advance_ns(5 * MS);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_TIMEOUT);
    lhal_stats_t st;
    lhal_stats(&st);
    assert_int_equal(st.sonar[0].no_response, 1);
}

static void test_sonar_reports_a_stuck_echo_line(void **state)
{
    (void)state;
    fake_gpio_edge(ECHO, 1000, true);
    lhal_stats_t st;
    WAIT_UNTIL((lhal_stats(&st), st.sonar[0].stray == 1u));
    uint32_t w;
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_TIMEOUT);
    lhal_stats(&st);
    assert_int_equal(st.sonar[0].stuck_high, 1);
}

static void test_motor_direction_duty_and_standby(void **state)
{
    (void)state;
    hal_motor_set(HAL_WHEEL_LEFT, 500);
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 1);
    assert_int_equal(fake_gpio_value(L_IN2), 0);
    assert_int_equal(fake_gpio_value(STBY), 1);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "25000\n");

    hal_motor_set(HAL_WHEEL_LEFT, -2000); /* clamped to full reverse */
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(L_IN2), 1);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "50000\n");

    /* The right motor is inverted: forward drives IN2. */
    hal_motor_set(HAL_WHEEL_RIGHT, 300);
    written();
    assert_int_equal(fake_gpio_value(R_IN1), 0);
    assert_int_equal(fake_gpio_value(R_IN2), 1);
    assert_string_equal(pwm("pwmchip0/pwm1/duty_cycle"), "15000\n");

    hal_motor_set(HAL_WHEEL_LEFT, 0);
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(L_IN2), 0);
    assert_int_equal(fake_gpio_value(STBY), 1); /* the right motor still runs */
    hal_motor_set(HAL_WHEEL_RIGHT, 0);
    written();
    assert_int_equal(fake_gpio_value(STBY), 0);
    assert_string_equal(pwm("pwmchip0/pwm1/duty_cycle"), "0\n");
}

static void test_servo_starts_at_its_first_command_and_clamps(void **state)
{
    (void)state;
    (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, 1500);
    written();
    assert_string_equal(pwm("pwmchip1/pwm0/period"), "20000000\n");
    assert_string_equal(pwm("pwmchip1/pwm0/duty_cycle"), "1500000\n");
    assert_string_equal(pwm("pwmchip1/pwm0/enable"), "1\n");
    (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, 3000);
    written();
    assert_string_equal(pwm("pwmchip1/pwm0/duty_cycle"), "2600000\n");
    (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, 100);
    written();
    assert_string_equal(pwm("pwmchip1/pwm0/duty_cycle"), "400000\n");
}

static void test_shutdown_stops_and_releases_everything(void **state)
{
    (void)state;
    hal_motor_set(HAL_WHEEL_LEFT, 800);
    hal_motor_set(HAL_WHEEL_RIGHT, -800);
    (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, 1000);
    written();
    assert_string_equal(pwm("pwmchip1/pwm0/enable"), "1\n");
    assert_true(lhal_shutdown());
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm0/enable"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm1/duty_cycle"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm1/enable"), "0\n");
    assert_string_equal(pwm("pwmchip1/pwm0/enable"), "0\n");
    assert_int_equal(fake_gpio_requested_count(), 0);
    /* Calls after shutdown do nothing. */
    hal_motor_set(HAL_WHEEL_LEFT, 800);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    lhal_shutdown(); /* twice is fine */
}

static void test_emergency_stop_holds(void **state)
{
    (void)state;
    hal_motor_set(HAL_WHEEL_LEFT, 600);
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 1);
    assert_int_equal(fake_gpio_value(STBY), 1);
    lhal_emergency_stop();
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm0/enable"), "0\n");
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(STBY), 0);
    hal_motor_set(HAL_WHEEL_LEFT, 700);
    written();
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(STBY), 0);
}

static void test_time_and_storage(void **state)
{
    (void)state;
    uint32_t t = hal_time_us();
    advance_ns(1234000u);
    assert_int_equal(hal_time_us() - t, 1234);

    const char map[] = "OM";
    assert_int_equal(hal_storage_begin(1), HAL_OK);
    assert_int_equal(hal_storage_write(1, 8, map, sizeof map), HAL_OK);
    assert_int_equal(hal_storage_commit(1), HAL_OK);
    char back[sizeof map];
    assert_int_equal(hal_storage_read(1, 8, back, sizeof back), HAL_OK);
    assert_memory_equal(back, map, sizeof map);
    assert_true(tmptree_exists(root, "store/slot1.bin"));
    assert_int_equal(hal_storage_write(1, 8190, map, sizeof map), HAL_EINVAL);
    /* No telemetry configured: nothing is taken. */
    assert_int_equal(hal_uart_write((const uint8_t *)"x", 1), 0);
}

/* ---- the tick, the critical section and the watchdog --------------------------------- */

static atomic_uint ticks;
static atomic_bool block_tick;
static atomic_bool tick_blocked;
static void *_Atomic tick_ctx;

/* Runs in the tick thread: it records, the test thread asserts. */
static void tick_cb(void *ctx)
{
    atomic_store(&tick_ctx, ctx);
    atomic_fetch_add(&ticks, 1u);
    while (atomic_load(&block_tick)) {
        atomic_store(&tick_blocked, true);
        wait_ms(1);
    }
    atomic_store(&tick_blocked, false);
}

static void test_tick_runs_outside_critical_sections(void **state)
{
    (void)state;
    atomic_store(&ticks, 0u);
    assert_int_equal(hal_tick_start(NULL, NULL), HAL_EINVAL);
    assert_int_equal(hal_tick_start(tick_cb, &ticks), HAL_OK);
    assert_int_equal(hal_tick_start(tick_cb, &ticks), HAL_EBUSY);
    WAIT_UNTIL(atomic_load(&ticks) >= 3u);
    assert_ptr_equal(atomic_load(&tick_ctx), &ticks);

    hal_irq_state_t s = hal_critical_enter();
    hal_irq_state_t s2 = hal_critical_enter(); /* nests */
    unsigned held = atomic_load(&ticks);
    wait_ms(50);
    assert_int_equal(atomic_load(&ticks), held); /* no tick ran inside */
    hal_critical_exit(s2);
    hal_critical_exit(s);
    WAIT_UNTIL(atomic_load(&ticks) > held);
    assert_int_equal(lhal_fault(NULL, 0), LHAL_FAULT_NONE);
}

static void test_watchdog_stops_the_motors_when_the_tick_stalls(void **state)
{
    (void)state;
    atomic_store(&ticks, 0u);
    hal_motor_set(HAL_WHEEL_LEFT, 900);
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 1);
    assert_int_equal(fake_gpio_value(STBY), 1);
    assert_int_equal(hal_tick_start(tick_cb, &ticks), HAL_OK);
    WAIT_UNTIL(atomic_load(&ticks) >= 2u);
    atomic_store(&block_tick, true);
    WAIT_UNTIL(atomic_load(&tick_blocked));
    /* The tick is stuck; its last stamp is now. 100 ms later all is still well... */
    advance_ns(100 * MS);
    wait_ms(30); /* give the watchdog a few looks */
    assert_int_equal(lhal_fault(NULL, 0), LHAL_FAULT_NONE);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "45000\n");
    /* ...one more millisecond is too long. */
    advance_ns(1 * MS);
    WAIT_UNTIL(lhal_fault(NULL, 0) != LHAL_FAULT_NONE);
    char msg[256];
    assert_int_equal(lhal_fault(msg, sizeof msg), LHAL_FAULT_WATCHDOG);
    assert_non_null(strstr(msg, "no control tick for 101 ms"));
    /* Stopped before the fault was reported, without the tick's lock, which the stuck tick
     * still holds: the lines, then the PWM. */
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(L_IN2), 0);
    assert_int_equal(fake_gpio_value(STBY), 0);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(pwm("pwmchip0/pwm0/enable"), "0\n");
    atomic_store(&block_tick, false);
    /* And they stay stopped when the tick comes back. */
    hal_motor_set(HAL_WHEEL_LEFT, 900);
    assert_string_equal(pwm("pwmchip0/pwm0/duty_cycle"), "0\n");
}

/* Starts the backend with the background loop watched, and the tick running. */
static void start_watching_idle(uint32_t idle_ms)
{
    cfg.watchdog_idle_ms = idle_ms;
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_OK);
    atomic_store(&ticks, 0u);
    assert_int_equal(hal_tick_start(tick_cb, &ticks), HAL_OK);
}

/* Waits until each thread went round twice after the clock moved (the second round
 * starts after the first stamped the moved clock), so no beat is two moves old when the
 * clock moves again, however long a loaded machine keeps a thread waiting; or until a
 * fault, after which the threads may stop. */
static void all_threads_saw_the_clock(void)
{
    lhal_stats_t st;
    lhal_stats(&st);
    const uint32_t events = st.events_rounds;
    const uint32_t output = st.output_rounds;
    const unsigned seen = atomic_load(&ticks);
    WAIT_UNTIL((lhal_stats(&st), atomic_load(&ticks) >= seen + 2u &&
                                     st.events_rounds >= events + 2u &&
                                     st.output_rounds >= output + 2u) ||
               lhal_fault(NULL, 0) != LHAL_FAULT_NONE);
}

static void test_watchdog_watches_the_background_loop(void **state)
{
    (void)state;
    start_watching_idle(500u);
    /* The threads go on (each stamps the moved clock, so none is ever 100 ms old), but
     * nobody kicks. */
    for (int step = 1; step <= 6 && lhal_fault(NULL, 0) == LHAL_FAULT_NONE; step++) {
        advance_ns(90 * MS);
        all_threads_saw_the_clock();
        if (step <= 5) {
            assert_int_equal(lhal_fault(NULL, 0), LHAL_FAULT_NONE); /* <= 450 ms */
        }
    }
    WAIT_UNTIL(lhal_fault(NULL, 0) != LHAL_FAULT_NONE);
    char msg[256];
    assert_int_equal(lhal_fault(msg, sizeof msg), LHAL_FAULT_WATCHDOG);
    assert_non_null(strstr(msg, "background loop stalled"));
}

static void test_kicks_keep_the_background_watchdog_quiet(void **state)
{
    (void)state;
    start_watching_idle(500u);
    for (int step = 0; step < 12; step++) {
        advance_ns(90 * MS);
        hal_watchdog_kick();
        all_threads_saw_the_clock();
    }
    assert_int_equal(lhal_fault(NULL, 0), LHAL_FAULT_NONE); /* > 1 s of kicked running */
}

/* ---- failures and --check ------------------------------------------------------------- */

/* poll() of the events thread fails when the process may have fewer descriptors than it
 * polls (EINVAL). That thread ended quietly: the counts froze while the motors ran on, and
 * the speed control wound up to full duty. Now it is a fault: the motors stop, the lines
 * go low at once, and the PWM goes off as soon as the files can be opened again. */
static void test_events_thread_failure_stops_the_motors(void **state)
{
    (void)state;
    hal_motor_set(HAL_WHEEL_LEFT, 800);
    written();
    assert_int_equal(fake_gpio_value(L_IN1), 1);
    assert_int_equal(fake_gpio_value(STBY), 1);
    struct rlimit old;
    assert_int_equal(getrlimit(RLIMIT_NOFILE, &old), 0);
    struct rlimit low = {.rlim_cur = 5u, .rlim_max = old.rlim_max}; /* the events thread polls 6 */
    assert_int_equal(setrlimit(RLIMIT_NOFILE, &low), 0);
    WAIT_UNTIL(lhal_fault(NULL, 0) != LHAL_FAULT_NONE);
    char msg[256];
    lhal_fault_t f = lhal_fault(msg, sizeof msg);
    assert_int_equal(setrlimit(RLIMIT_NOFILE, &old), 0);
    assert_int_equal(f, LHAL_FAULT_IO);
    assert_non_null(strstr(msg, "the events thread stopped: poll: Invalid argument"));
    assert_int_equal(fake_gpio_value(L_IN1), 0);
    assert_int_equal(fake_gpio_value(STBY), 0);
    /* The output thread writes the two files one after the other: wait for both. */
    WAIT_UNTIL(strcmp(pwm("pwmchip0/pwm0/enable"), "0\n") == 0 &&
               strcmp(pwm("pwmchip0/pwm0/duty_cycle"), "0\n") == 0);
}

static void test_busy_line_fails_init_naming_the_key(void **state)
{
    (void)state;
    fake_gpio_busy(ECHO, "other-app");
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_EIO);
    assert_non_null(strstr(lhal_error(), "sonar_echo: line 6 is in use by 'other-app'"));
    assert_int_equal(fake_gpio_requested_count(), 0); /* what was opened is released */
    assert_int_equal(hal_tick_start(tick_cb, &ticks), HAL_EIO);
}

static void test_missing_pwm_chip_fails_init_naming_the_key(void **state)
{
    (void)state;
    cfg.motor_pwm[1] = (lconf_pwm_t){7, 0};
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_EIO);
    assert_non_null(strstr(lhal_error(), "motor_right_pwm: "));
    assert_non_null(strstr(lhal_error(), "pwmchip7 does not exist"));
    assert_int_equal(fake_gpio_requested_count(), 0);
}

static void test_missing_chip_fails_init(void **state)
{
    (void)state;
    fake_gpio_no_chip();
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_EIO);
    assert_non_null(strstr(lhal_error(), "gpio_chip: cannot open GPIO chip 'fakechip0'"));
}

static void test_instances_beyond_the_robot_are_refused(void **state)
{
    (void)state;
    assert_one_sensor_board();
    written();
    assert_int_equal(fake_gpio_rises(TRIG), 0);
}

/* The shared robot with sonar 1 (its own trigger and echo lines), servo 1 on
 * ROOT/pwmchip1/pwm1 and two bump switches, one of them pressed from the start. */
static int setup_instances(void **state)
{
    setup(state);
    cfg.sonar1_trigger = TRIG1;
    cfg.sonar1_echo = ECHO1;
    tmptree_pwm_channel(root, 1u, 1u);
    cfg.servo1_pwm = (lconf_pwm_t){1, 1};
    cfg.bump[0] = BUMP0;
    cfg.bump[1] = BUMP1;
    fake_gpio_level(BUMP0, true);
    fake_gpio_level(BUMP1, false);
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_OK);
    return 0;
}

static void test_sonar_1_servo_1_and_bump_switches(void **state)
{
    (void)state;
    assert_int_equal(hal_servo_count(), 2u);
    assert_int_equal(hal_sonar_count(), 2u);
    assert_int_equal(hal_bump_count(), 2u);
    assert_int_equal(fake_gpio_requested_count(), 15);
    assert_true(fake_gpio_is_output(TRIG1));
    assert_false(fake_gpio_is_output(ECHO1));
    assert_false(fake_gpio_is_output(BUMP0));

    /* Sonar 1 pings on its own line and times its own echo. */
    uint32_t w = 0u;
    assert_int_equal(hal_sonar_trigger(1u), HAL_OK);
    written();
    assert_int_equal(fake_gpio_rises(TRIG1), 1);
    assert_int_equal(fake_gpio_rises(TRIG), 0);
    assert_int_equal(hal_sonar_trigger(1u), HAL_EBUSY);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK); /* sonar 0 is not busy */
    const fake_edge_t echo[] = {{ECHO1, 70000000u, true}, {ECHO1, 70000000u + 2345000u, false}};
    fake_gpio_edges(echo, 2);
    int st = HAL_SONAR_BUSY;
    for (int i = 0; i < 10000 && st == HAL_SONAR_BUSY; i++) {
        st = hal_sonar_poll(1u, &w);
        if (st == HAL_SONAR_BUSY) {
            wait_ms(1); /* the events thread reads the edges */
        }
    }
    assert_int_equal(st, HAL_SONAR_ECHO);
    assert_int_equal(w, 2345);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_BUSY);
    assert_int_equal(hal_sonar_trigger(2u), HAL_EINVAL);
    lhal_stats_t sts;
    lhal_stats(&sts);
    assert_int_equal(sts.sonars, 2u);
    assert_int_equal(sts.sonar[1].echoes, 1);
    assert_int_equal(sts.sonar[0].echoes, 0);

    /* Servo 1 on its own channel; servo 0's waits for its first command. */
    assert_int_equal(hal_servo_set_pulse(1u, 1200u), HAL_OK);
    written();
    assert_string_equal(pwm("pwmchip1/pwm1/duty_cycle"), "1200000\n");
    assert_string_equal(pwm("pwmchip1/pwm0/enable"), "");
    assert_int_equal(hal_servo_set_pulse(2u, 1200u), HAL_EINVAL);

    /* Switches close to ground: a low line is pressed. */
    bool b[2] = {true, false};
    assert_int_equal(hal_bump_read(0u, &b[0]), HAL_OK);
    assert_int_equal(hal_bump_read(1u, &b[1]), HAL_OK);
    assert_false(b[0]);
    assert_true(b[1]);
    fake_gpio_edge(BUMP0, 80000000u, false);
    WAIT_UNTIL((hal_bump_read(0u, &b[0]), b[0]));
    fake_gpio_edge(BUMP1, 80000001u, true);
    WAIT_UNTIL((hal_bump_read(1u, &b[1]), !b[1]));
    assert_int_equal(hal_bump_read(2u, &b[0]), HAL_EINVAL);
    assert_int_equal(hal_bump_read(0u, NULL), HAL_EINVAL);

    assert_true(lhal_shutdown());
    assert_int_equal(hal_bump_read(0u, &b[0]), HAL_EIO); /* the backend is down */
    assert_string_equal(pwm("pwmchip1/pwm1/enable"), "0\n");
}

static void test_check_reports_every_item_and_moves_nothing(void **state)
{
    (void)state;
    char out[4096];
    FILE *f = fmemopen(out, sizeof out, "w");
    assert_non_null(f);
    assert_int_equal(lhal_check(&cfg, f), 0);
    fclose(f);
    assert_non_null(strstr(out, "sonar_echo               ok (line 6, input, now low)"));
    assert_non_null(strstr(out, "motor_standby            ok (line 11, output, held low)"));
    assert_non_null(strstr(out, "servo_pwm                ok"));
    assert_non_null(strstr(out, "storage_dir              ok"));
    assert_non_null(strstr(out, "check: all 17 items ok"));
    assert_int_equal(fake_gpio_requested_count(), 0);
    assert_string_equal(pwm("pwmchip0/pwm0/enable"), ""); /* nothing written */
    assert_false(tmptree_exists(root, "store"));          /* nothing created */

    fake_gpio_busy(L_B, "other-app");
    cfg.servo_pwm = (lconf_pwm_t){4, 2};
    f = fmemopen(out, sizeof out, "w");
    assert_int_equal(lhal_check(&cfg, f), 2);
    fclose(f);
    assert_non_null(strstr(out, "encoder_left_b           FAIL: line 2 is in use by 'other-app'"));
    assert_non_null(strstr(out, "servo_pwm                FAIL: "));
    assert_non_null(strstr(out, "pwmchip4 does not exist"));
    assert_non_null(strstr(out, "check: 2 of 17 items failed"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_init_requests_every_line_with_the_motors_stopped,
                                        setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_encoders_decode_both_lines_in_timestamp_order,
                                        setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_sonar_pulse_and_echo_width, setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_sonar_times_out_on_the_backend_clock, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_sonar_reports_a_stuck_echo_line, setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_motor_direction_duty_and_standby, setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_servo_starts_at_its_first_command_and_clamps, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_shutdown_stops_and_releases_everything, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_emergency_stop_holds, setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_time_and_storage, setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_tick_runs_outside_critical_sections, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_watchdog_stops_the_motors_when_the_tick_stalls,
                                        setup_up, teardown),
        cmocka_unit_test_setup_teardown(test_watchdog_watches_the_background_loop, setup, teardown),
        cmocka_unit_test_setup_teardown(test_kicks_keep_the_background_watchdog_quiet, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_events_thread_failure_stops_the_motors, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_busy_line_fails_init_naming_the_key, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_pwm_chip_fails_init_naming_the_key, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_missing_chip_fails_init, setup, teardown),
        cmocka_unit_test_setup_teardown(test_instances_beyond_the_robot_are_refused, setup_up,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_sonar_1_servo_1_and_bump_switches, setup_instances,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_check_reports_every_item_and_moves_nothing, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
