/* SPDX-License-Identifier: MIT */
/* Tests of the sonarslam-linux program on a fake GPIO chip: options, errors, --check, runs. */
#define _GNU_SOURCE
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "fake_gpio.h"
#include "hal_common/mapexport.h"
#include "lhal/app.h"
#include "lhal/lhal.h"
#include "slam/grid.h"
#include "tmptree.h"
#include "wiring.h"

enum { TRIG = 5, L_IN1 = 7 };

static char root[TMPTREE_PATH_MAX];
static char conf[TMPTREE_PATH_MAX + 16];
static char out_buf[16384];
static char err_buf[4096];

/* A frozen clock: no echo deadline or watchdog limit passes on a slow machine. */
static uint64_t frozen_clock(void)
{
    return 42000000000ull;
}

static int setup(void **state)
{
    (void)state;
    fake_gpio_reset();
    lhal_set_clock(frozen_clock);
    tmptree_make(root, "app");
    snprintf(conf, sizeof conf, "%s/robot.conf", root);
    wiring_conf_file(root, "", "");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tmptree_remove(root); /* first, so a failed check leaves nothing behind */
    assert_int_equal(fake_gpio_requested_count(), 0);
    return 0;
}

/* Runs the program with a NULL-terminated argument list; its output lands in the buffers. */
static int run(const char *first, ...)
{
    char *argv[16] = {"sonarslam-linux"};
    int argc = 1;
    va_list ap;
    va_start(ap, first);
    for (const char *a = first; a != NULL && argc < 15; a = va_arg(ap, const char *)) {
        argv[argc++] = (char *)(uintptr_t)a;
    }
    va_end(ap);
    argv[argc] = NULL;
    memset(out_buf, 0, sizeof out_buf);
    memset(err_buf, 0, sizeof err_buf);
    FILE *out = fmemopen(out_buf, sizeof out_buf - 1u, "w");
    FILE *err = fmemopen(err_buf, sizeof err_buf - 1u, "w");
    assert_non_null(out);
    assert_non_null(err);
    int rc = app_main(argc, argv, out, err);
    fclose(out);
    fclose(err);
    return rc;
}

static void test_help(void **state)
{
    (void)state;
    assert_int_equal(run("--help", NULL), APP_EXIT_OK);
    assert_non_null(strstr(out_buf, "usage: sonarslam-linux --config FILE"));
    assert_non_null(strstr(out_buf, "--check"));
    assert_int_equal(run("-h", NULL), APP_EXIT_OK);
}

static void test_bad_command_lines(void **state)
{
    (void)state;
    static const struct {
        const char *a;
        const char *b;
        const char *says;
    } cases[] = {
        {NULL, NULL, "missing --config FILE"},
        {"--bogus", NULL, "unknown option '--bogus'"},
        {"--config", NULL, "--config needs a value"},
        {"--ticks", "0", "--ticks '0': expected a whole number of ticks >= 1"},
        {"--ticks", "-5", "--ticks '-5'"},
        {"--ticks", "12x", "--ticks '12x'"},
        {"stray", NULL, "unexpected argument 'stray'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(run(cases[i].a, cases[i].b, NULL), APP_EXIT_USAGE);
        if (strstr(err_buf, cases[i].says) == NULL) {
            fail_msg("case %zu: '%s' does not say '%s'", i, err_buf, cases[i].says);
        }
    }
}

static void test_bad_config_exits_2_naming_file_and_line(void **state)
{
    (void)state;
    assert_int_equal(run("--config", "/nonexistent/robot.conf", NULL), APP_EXIT_USAGE);
    assert_non_null(strstr(err_buf, "/nonexistent/robot.conf: cannot open"));

    char text[4096];
    snprintf(text, sizeof text, "%s", tmptree_read(root, "robot.conf"));
    strcat(text, "sonar_echo = 12\n");
    tmptree_file(root, "robot.conf", text);
    assert_int_equal(run("-c", conf, NULL), APP_EXIT_USAGE);
    assert_non_null(strstr(err_buf, "robot.conf:23: sonar_echo is given twice"));
    assert_int_equal(fake_gpio_requested_count(), 0); /* nothing was opened */
}

static void test_check(void **state)
{
    (void)state;
    assert_int_equal(run("--config", conf, "--check", NULL), APP_EXIT_OK);
    assert_non_null(strstr(out_buf, "(nothing moves)"));
    assert_non_null(strstr(out_buf, "check: all 16 items ok")); /* no standby line here */
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "");

    fake_gpio_busy(9, "someone");
    assert_int_equal(run("--config", conf, "--check", NULL), APP_EXIT_HARDWARE);
    assert_non_null(
        strstr(out_buf, "motor_right_in1          FAIL: line 9 is in use by 'someone'"));
}

static void test_hardware_failure_exits_1(void **state)
{
    (void)state;
    fake_gpio_busy(TRIG, "someone");
    assert_int_equal(run("--config", conf, "--ticks", "5", NULL), APP_EXIT_HARDWARE);
    assert_non_null(strstr(err_buf, "sonar_trigger: line 5 is in use by 'someone'"));
}

/* The Linux program's capacity holds at least a 12 m home at 50 mm. */
_Static_assert(SLAM_GRID_A >= 240u && SLAM_GRID_B >= 240u, "the Linux grid capacity is below 12 m");

/* The grey level of a map cell in a written PGM (north up, as mapfile writes it). */
static int pgm_cell(const char *rel, unsigned a, unsigned b)
{
    const char *pgm = tmptree_read(root, rel);
    char header[32];
    snprintf(header, sizeof header, "P5\n%u %u\n255\n", SLAM_GRID_A, SLAM_GRID_B);
    if (strncmp(pgm, header, strlen(header)) != 0) {
        return -1;
    }
    const uint8_t *px = (const uint8_t *)pgm + strlen(header);
    return px[(size_t)(SLAM_GRID_B - 1u - b) * SLAM_GRID_A + a];
}

static void test_run_drives_the_firmware_and_stops_the_motors(void **state)
{
    (void)state;
    assert_int_equal(run("--config", conf, "--ticks", "40", NULL), APP_EXIT_OK);
    unsigned ticks = 0;
    const char *at = strstr(out_buf, "motors stopped after ");
    assert_non_null(at);
    assert_int_equal(sscanf(at, "motors stopped after %u ticks", &ticks), 1);
    assert_true(ticks >= 40u);
    /* The firmware's sweep commanded the servo and sent a ping through the backend. */
    assert_string_equal(tmptree_read(root, "pwmchip1/pwm0/period"), "20000000\n");
    assert_true(fake_gpio_rises(TRIG) >= 1u);
    /* Motors off at the end. */
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm1/enable"), "0\n");
    /* The maps: the robot stood at the start cell for every tick, so TM there is full. They
     * are the whole capacity (grid_a = grid_b = 0), pgm_cell() reads them at its size. */
    assert_non_null(strstr(out_buf, "maps written to"));
    unsigned a0 = SLAM_GRID_A / 2u;
    unsigned b0 = SLAM_GRID_B / 2u;
    assert_int_equal(pgm_cell("maps/tm.pgm", a0, b0), 0);
    assert_int_equal(pgm_cell("maps/tm.pgm", a0 + 5u, b0), 255);
    /* The robot's own cell is known free; far from it nothing was seen. */
    assert_int_equal(pgm_cell("maps/om.pgm", a0, b0), MAPX_FREE);
    assert_int_equal(pgm_cell("maps/om.pgm", a0 + 40u, b0 + 40u), MAPX_UNKNOWN);
    assert_true(tmptree_exists(root, "maps/om_post.pgm"));
    assert_true(tmptree_exists(root, "maps/om.yaml"));
    assert_false(tmptree_exists(root, "maps/tm.yaml"));
    /* Its origin is a whole number of 50 mm cells from the world's origin (the default start
     * pose, SLAM_START_UM), so that every map reader places it exactly. */
    char want[96];
    unsigned ox_um = a0 * 50000u;
    unsigned oy_um = b0 * 50000u;
    snprintf(want, sizeof want, "origin: [-%u.%06u, -%u.%06u, 0.0]", ox_um / 1000000u,
             ox_um % 1000000u, oy_um / 1000000u, oy_um % 1000000u);
    const char *yaml = tmptree_read(root, "maps/om.yaml");
    if (strstr(yaml, want) == NULL) {
        fail_msg("om.yaml: no '%s' in:\n%s", want, yaml);
    }
    assert_non_null(strstr(out_buf, "sonar: 1 pings"));
}

/* The background loop reads what the tick writes: the tick count, the hold and held flags,
 * the sweep's counters for STATUS frames, and the grid, which telemetry streams and the
 * map store saves. On Linux they are two threads, and every such read happens inside the
 * background loop's turn: in the ThreadSanitizer build (host-tsan) this run is clean. */
static void test_run_saves_and_streams_while_the_tick_runs(void **state)
{
    (void)state;
    char text[4096];
    /* A 160 x 160 grid: its save (some 200 calls of robot_idle()) fits the run's ticks. */
    snprintf(text, sizeof text,
             "save_period_s = 1\ngrid_a = 160\ngrid_b = 160\nstart_cell_a = 80\n"
             "start_cell_b = 80\n%s",
             tmptree_read(root, "robot.conf"));
    strcat(text, "telemetry = pty\n");
    tmptree_file(root, "robot.conf", text);
    assert_int_equal(run("--config", conf, "--ticks", "1000", NULL), APP_EXIT_OK);
    assert_non_null(strstr(out_buf, "telemetry on /dev/pts/"));
    /* Saved after 100 ticks (a save takes some 200 calls of robot_idle()), the robot
     * standing as it looks round. Ten seconds of ticks leave the background loop time
     * for it on a loaded machine, under ThreadSanitizer too. */
    assert_true(tmptree_exists(root, "maps/slot0.bin") || tmptree_exists(root, "maps/slot1.bin"));
    unsigned long long sent = 0;
    const char *at = strstr(out_buf, "telemetry: ");
    assert_non_null(at);
    assert_int_equal(sscanf(at, "telemetry: %llu bytes sent", &sent), 1);
    assert_true(sent > 1000u);
}

static void test_io_fault_stops_for_safety(void **state)
{
    (void)state;
    /* The servo's duty file vanishes: the firmware's first servo command fails. */
    tmptree_unlink(root, "pwmchip1/pwm0/duty_cycle");
    assert_int_equal(run("--config", conf, "--ticks", "400", NULL), APP_EXIT_SAFETY);
    assert_non_null(strstr(err_buf, "servo_pwm: writing"));
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
    assert_int_equal(fake_gpio_value(L_IN1), 0);
}

static pthread_t main_thread;

static void *send_sigterm(void *arg)
{
    (void)arg;
    /* Once the program runs (the firmware has pinged), ask it to stop. */
    for (int i = 0; i < 20000 && fake_gpio_rises(TRIG) == 0u; i++) {
        const struct timespec ms = {0, 1000000L};
        nanosleep(&ms, NULL);
    }
    pthread_kill(main_thread, SIGTERM);
    return NULL;
}

static void test_sigterm_stops_cleanly(void **state)
{
    (void)state;
    main_thread = pthread_self();
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, send_sigterm, NULL), 0);
    int rc = run("--config", conf, NULL);
    pthread_join(t, NULL);
    assert_int_equal(rc, APP_EXIT_OK);
    assert_non_null(strstr(out_buf, "stopped by signal 15"));
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
    assert_true(tmptree_exists(root, "maps/om.pgm"));
    /* The program put SIGTERM's old action back. */
    struct sigaction sa;
    sigaction(SIGTERM, NULL, &sa);
    assert_ptr_equal(sa.sa_handler, SIG_DFL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_bad_command_lines),
        cmocka_unit_test_setup_teardown(test_bad_config_exits_2_naming_file_and_line, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_check, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hardware_failure_exits_1, setup, teardown),
        cmocka_unit_test_setup_teardown(test_run_drives_the_firmware_and_stops_the_motors, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_run_saves_and_streams_while_the_tick_runs, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_io_fault_stops_for_safety, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sigterm_stops_cleanly, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
