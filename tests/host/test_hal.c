/* SPDX-License-Identifier: MIT */
/* Tests of the host HAL: clock and tick, the wires, UART, storage and the HAL trace. */
#include <math.h>

#include "hal/hal.h"
#include "hal_common/trace.h"
#include "host_test.h"
#include "slam/error.h"
#include "slam/robot.h"

static room_t room;
static sim_t *world;

static int setup(void **state)
{
    (void)state;
    char err[300];
    if (room_load(&room, HOST_ROOMS_DIR "/obstacles.room", NULL, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    room_free(&room);
    return 0;
}

/* A fresh default world attached and initialised. */
static void boot_with(uint64_t seed, const sim_errors_t *e)
{
    world = test_world(&room, e, seed);
    hal_host_attach(world);
    assert_int_equal(hal_init(), HAL_OK);
}

static void boot(uint64_t seed)
{
    sim_errors_t e;
    sim_errors_default(&e);
    boot_with(seed, &e);
}

static void shutdown(void)
{
    hal_host_attach(NULL);
    sim_destroy(world);
    world = NULL;
}

static uint32_t seen_time[8];
static unsigned calls;

static void record_time(void *ctx)
{
    (void)ctx;
    if (calls < 8u) {
        seen_time[calls] = hal_time_us();
    }
    calls++;
}

static void test_init_clock_and_tick(void **state)
{
    (void)state;
    hal_host_attach(NULL);
    assert_int_equal(hal_init(), HAL_EIO); /* no world */
    hal_host_step();                       /* nothing to step: harmless */
    boot(1u);
    assert_int_equal(hal_time_us(), 0u);
    assert_int_equal(hal_tick_overruns(), 0u);
    hal_host_step(); /* no callback yet: only the world moves */
    assert_int_equal(hal_time_us(), 10000u);
    assert_int_equal(sim_truth(world).ticks, 1u);
    assert_int_equal(hal_tick_start(NULL, NULL), HAL_EINVAL);
    calls = 0;
    assert_int_equal(hal_tick_start(record_time, NULL), HAL_OK);
    assert_int_equal(hal_tick_start(record_time, NULL), HAL_EBUSY);
    for (int k = 0; k < 5; k++) {
        hal_host_step();
    }
    assert_int_equal(calls, 5u);
    for (unsigned k = 0; k < 5u; k++) { /* the callback runs at the start of its period */
        assert_int_equal(seen_time[k], 10000u * (k + 1u));
    }
    assert_int_equal(hal_time_us(), 60000u);
    /* hal_init() restarts the clock; a new world forgets the callback. */
    assert_int_equal(hal_init(), HAL_OK);
    assert_int_equal(hal_time_us(), 0u);
    shutdown();
    boot(1u);
    assert_int_equal(hal_tick_start(record_time, NULL), HAL_OK);
    shutdown();
}

static void test_wires_reach_the_world(void **state)
{
    (void)state;
    boot(3u);
    hal_motor_set(HAL_WHEEL_LEFT, 700);
    hal_motor_set(HAL_WHEEL_RIGHT, -4000);
    assert_int_equal(sim_motor_duty(world, HAL_WHEEL_LEFT), 700);
    assert_int_equal(sim_motor_duty(world, HAL_WHEEL_RIGHT), -1000);
    (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, 2000);
    assert_int_equal(sim_servo_pulse(world), 2000);
    for (int k = 0; k < 50; k++) {
        hal_host_step();
    }
    assert_int_equal(hal_encoder_count(HAL_WHEEL_LEFT), sim_encoder_count(world, HAL_WHEEL_LEFT));
    assert_int_equal(hal_encoder_count(HAL_WHEEL_RIGHT), sim_encoder_count(world, HAL_WHEEL_RIGHT));
    assert_true(hal_encoder_count(HAL_WHEEL_LEFT) > 100u);
    assert_true(hal_encoder_count(HAL_WHEEL_RIGHT) > 60000u); /* backwards, wrapped */
    assert_true(fabs(sim_truth(world).servo_deg - 135.0) < 1e-9);
    /* hal_init() stops the motors. */
    assert_int_equal(hal_init(), HAL_OK);
    assert_int_equal(sim_motor_duty(world, HAL_WHEEL_LEFT), 0);
    assert_int_equal(sim_motor_duty(world, HAL_WHEEL_RIGHT), 0);
    /* The sonar through the HAL. */
    uint32_t w = 99u;
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_IDLE);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_EBUSY);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_BUSY);
    hal_host_step();
    hal_host_step();
    hal_host_step();
    hal_host_step();
    int st = hal_sonar_poll(HAL_SONAR_SWEPT, &w);
    assert_true(st == HAL_SONAR_ECHO || st == HAL_SONAR_TIMEOUT);
    if (st == HAL_SONAR_ECHO) {
        assert_int_equal(w, sim_last_ping(world).echo_us);
    }
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &w), HAL_SONAR_IDLE);
    hal_irq_state_t irq = hal_critical_enter();
    hal_critical_exit(irq);
    hal_watchdog_kick();
    shutdown();
}

static void test_uart(void **state)
{
    (void)state;
    boot(1u);
    static const uint8_t bytes[] = {0x7E, 0x00, 0x41, 0xFF};
    assert_int_equal(hal_uart_write(bytes, sizeof bytes), sizeof bytes); /* discarded */
    const char *path = test_path("uart.bin");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    hal_host_uart_sink(f);
    assert_int_equal(hal_uart_write(bytes, sizeof bytes), sizeof bytes);
    assert_int_equal(hal_uart_write(bytes, 2u), 2u);
    hal_host_uart_sink(NULL);
    fclose(f);
    f = fopen(path, "rb");
    assert_non_null(f);
    uint8_t got[16];
    assert_int_equal(fread(got, 1u, sizeof got, f), 6u);
    fclose(f);
    assert_memory_equal(got, bytes, 4u);
    assert_memory_equal(got + 4, bytes, 2u);
    uint8_t in[4];
    assert_int_equal(hal_uart_read(in, sizeof in), 0u);
    unlink(path);
    shutdown();
}

static void test_storage(void **state)
{
    (void)state;
    boot(1u);
    size_t size = hal_storage_size();
    assert_int_equal(size, 128u * 1024u);
    uint8_t buf[64];
    assert_int_equal(hal_storage_begin(2u), HAL_EINVAL);
    assert_int_equal(hal_storage_write(0u, 0u, "x", 1u), HAL_EINVAL); /* not begun */
    assert_int_equal(hal_storage_commit(0u), HAL_EINVAL);
    assert_int_equal(hal_storage_begin(0u), HAL_OK);
    assert_int_equal(hal_storage_read(0u, 100u, buf, 8u), HAL_OK);
    for (int i = 0; i < 8; i++) {
        assert_int_equal(buf[i], 0xFF); /* erased */
    }
    assert_int_equal(hal_storage_write(0u, 10u, "hello", 5u), HAL_OK);
    assert_int_equal(hal_storage_write(0u, (uint32_t)size - 2u, "abc", 3u), HAL_EINVAL);
    assert_int_equal(hal_storage_write(0u, UINT32_MAX, "a", 1u), HAL_EINVAL);
    assert_int_equal(hal_storage_write(0u, 0u, NULL, 4u), HAL_EINVAL);
    assert_int_equal(hal_storage_write(0u, (uint32_t)size - 3u, "xyz", 3u), HAL_OK);
    assert_int_equal(hal_storage_commit(0u), HAL_OK);
    assert_int_equal(hal_storage_commit(0u), HAL_EINVAL);
    assert_int_equal(hal_storage_write(0u, 0u, "x", 1u), HAL_EINVAL); /* committed */
    assert_int_equal(hal_storage_read(0u, 10u, buf, 5u), HAL_OK);
    assert_memory_equal(buf, "hello", 5u);
    assert_int_equal(hal_storage_read(0u, (uint32_t)size - 3u, buf, 3u), HAL_OK);
    assert_memory_equal(buf, "xyz", 3u);
    assert_int_equal(hal_storage_read(0u, (uint32_t)size - 3u, buf, 4u), HAL_EINVAL);
    assert_int_equal(hal_storage_read(3u, 0u, buf, 1u), HAL_EINVAL);
    /* The other slot is independent, and storage outlives a reboot and a new world. */
    assert_int_equal(hal_storage_read(1u, 10u, buf, 5u), HAL_OK);
    assert_int_not_equal(memcmp(buf, "hello", 5u), 0);
    shutdown();
    boot(2u);
    assert_int_equal(hal_storage_read(0u, 10u, buf, 5u), HAL_OK);
    assert_memory_equal(buf, "hello", 5u);
    shutdown();
}

/* ---- traces ----------------------------------------------------------------------------- */

static robot_t robot;
static robot_t replayed;

static void robot_cb(void *ctx)
{
    robot_t *r = ctx;
    robot_tick(r);
    /* A drive of the test's own: the firmware does not drive yet. */
    uint32_t t = r->ticks;
    int16_t l = (int16_t)((t / 150u) % 3u == 0u ? -500 : 600);
    int16_t rr = (int16_t)((t / 230u) % 2u == 0u ? 650 : 400);
    hal_motor_set(HAL_WHEEL_LEFT, l);
    hal_motor_set(HAL_WHEEL_RIGHT, rr);
}

/* Run the firmware for @p ticks with a trace to @p path; returns the config used. */
static void traced_run(const char *path, uint64_t seed, unsigned ticks, slam_config_t *cfg)
{
    /* The default robot's noise, slip and sonar errors, on true wheels and with the
     * optimistic sonar: this firmware runs uncalibrated, and with the default robot's
     * wheels (E_d 1.005, E_b 1.03) the walls mode's first minute maps 50 hits or fewer; at
     * the typical level, whose walls answer only within about 25° of square, it maps 6
     * (of 426 echoes): too few to prove the replay, which is what is under test here. */
    sim_errors_t e;
    sim_errors_default(&e);
    sim_errors_sonar(&e, SIM_SONAR_OPTIMISTIC);
    e.wheel_ratio_ed = 1.0;
    e.wheel_base_eb = 1.0;
    boot_with(seed, &e);
    slam_config_default(cfg);
    slam_config_paper(cfg); /* the replay below runs the tick's own Algorithm C.1 */
    cfg->start_x_um = (int32_t)lround(room.start_x * 1e6);
    cfg->start_y_um = (int32_t)lround(room.start_y * 1e6);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    trace_write_header(f, cfg);
    hal_host_trace(f);
    assert_int_equal(robot_init(&robot, cfg), SLAM_OK);
    assert_int_equal(hal_tick_start(robot_cb, &robot), HAL_OK);
    for (unsigned k = 0; k < ticks; k++) {
        hal_host_step();
    }
    hal_host_trace(NULL);
    fclose(f);
    shutdown();
}

/* What a replay HAL does, with the core's modules and the inputs from the trace. */
static void replay(const slam_config_t *cfg, const trace_tick_t *t, size_t n, robot_t *r)
{
    memset(r, 0, sizeof *r);
    r->cfg = *cfg;
    odom_init(&r->odom, cfg, t[0].enc[0], t[0].enc[1]); /* robot_init's reads */
    sweep_init(&r->sweep, cfg);
    mapper_init(&r->mapper, cfg);
    grid_init(&r->grid, cfg);
    for (size_t i = 0; i < n; i++) {
        odom_step(&r->odom, t[i].enc[0], t[i].enc[1]);
        r->pose = odom_pose(&r->odom);
        sweep_echo_t echo = SWEEP_ECHO_PENDING;
        if (sweep_waiting(&r->sweep)) {
            assert_true(t[i].poll != '-');
            echo = t[i].poll == 'e' ? SWEEP_ECHO_DONE
                                    : (t[i].poll == 't' ? SWEEP_ECHO_TIMEOUT : SWEEP_ECHO_PENDING);
        } else {
            assert_true(t[i].poll == '-');
        }
        sweep_step(&r->sweep, echo, t[i].echo_us, &r->last);
        if (r->last.servo_cmd) {
            assert_int_equal(r->last.servo_pulse_us, t[i].servo_us);
        }
        assert_true((t[i].trig != '-') == r->last.trigger);
        if (r->last.trigger && t[i].trig != 'o') {
            r->ping_errors++;
        }
        mapper_tick(&r->mapper, &r->grid, &r->pose, &r->last);
        r->ticks++;
    }
}

static void test_trace_replays_the_maps(void **state)
{
    (void)state;
    const char *path = test_path("trace.txt");
    slam_config_t cfg;
    enum { TICKS = 6000 };
    traced_run(path, 5u, TICKS, &cfg);

    slam_config_t got_cfg;
    trace_tick_t *ticks = NULL;
    size_t n = 0;
    char err[300] = "";
    if (trace_read(path, &got_cfg, &ticks, &n, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(n, TICKS);
    assert_memory_equal(&got_cfg, &cfg, sizeof cfg);
    /* Outputs recorded as in force after each tick. */
    assert_int_equal(ticks[0].duty[0], -500);
    assert_int_equal(ticks[0].duty[1], 650);
    unsigned echoes = 0;
    unsigned trig = 0;
    for (size_t i = 0; i < n; i++) {
        echoes += ticks[i].poll == 'e';
        trig += ticks[i].trig == 'o';
        assert_true(ticks[i].poll == 'e' || ticks[i].echo_us == 0u);
    }
    assert_true(echoes > 500u);
    assert_true(trig >= (unsigned)robot.sweep.pings - 1u && trig <= robot.sweep.pings);

    replay(&cfg, ticks, n, &replayed);
    assert_int_equal(replayed.ticks, robot.ticks);
    assert_true(replayed.pose.x_um == robot.pose.x_um && replayed.pose.y_um == robot.pose.y_um &&
                replayed.pose.heading == robot.pose.heading);
    assert_int_equal(replayed.mapper.hits, robot.mapper.hits);
    assert_true(robot.mapper.hits > 50u);
    assert_memory_equal(replayed.grid.om, robot.grid.om, sizeof robot.grid.om);
    assert_memory_equal(replayed.grid.tm, robot.grid.tm, sizeof robot.grid.tm);
    free(ticks);
    unlink(path);
}

static int files_equal(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb");
    FILE *fb = fopen(b, "rb");
    assert_non_null(fa);
    assert_non_null(fb);
    int same = 1;
    for (;;) {
        int ca = fgetc(fa);
        int cb = fgetc(fb);
        if (ca != cb) {
            same = 0;
            break;
        }
        if (ca == EOF) {
            break;
        }
    }
    fclose(fa);
    fclose(fb);
    return same;
}

static void test_same_seed_same_traffic(void **state)
{
    (void)state;
    const char *a = test_path("ta.txt");
    const char *b = test_path("tb.txt");
    const char *c = test_path("tc.txt");
    slam_config_t cfg;
    traced_run(a, 11u, 3000u, &cfg);
    robot_t first = robot;
    traced_run(b, 11u, 3000u, &cfg);
    assert_true(files_equal(a, b));
    assert_memory_equal(first.grid.om, robot.grid.om, sizeof robot.grid.om);
    traced_run(c, 12u, 3000u, &cfg);
    assert_false(files_equal(a, c));
    unlink(a);
    unlink(b);
    unlink(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_clock_and_tick),
        cmocka_unit_test(test_wires_reach_the_world),
        cmocka_unit_test(test_uart),
        cmocka_unit_test(test_storage),
        cmocka_unit_test(test_trace_replays_the_maps),
        cmocka_unit_test(test_same_seed_same_traffic),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
