/* SPDX-License-Identifier: MIT */
/* Tests of HAL traces: a written trace reads back the same; bad traces are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "hal_common/trace.h"

static char path[64];

static int setup(void **state)
{
    (void)state;
    snprintf(path, sizeof path, "/tmp/slam-trace-%ld.txt", (long)getpid());
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    unlink(path);
    return 0;
}

static void test_round_trip(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    c.cell_um = 25000u;
    c.cal_left = FIX_Q30_ONE - 5;
    static const trace_tick_t ticks[] = {
        {{0, 65535}, '-', 0, '-', {0, 0}, 1500},
        {{12, 65530}, 'b', 0, 'o', {-1000, 1000}, 1222},
        {{13, 2}, 'e', 5831, '-', {250, -250}, 1222},
        {{14, 3}, 't', 0, 'b', {0, 0}, 2222},
        {{15, 4}, 'i', 0, '-', {0, 0}, 2222},
    };
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    trace_write_header(f, &c);
    for (size_t i = 0; i < 5; i++) {
        trace_write_tick(f, &ticks[i]);
    }
    trace_write_end(f, 5);
    fclose(f);

    slam_config_t d;
    trace_tick_t *got = NULL;
    size_t n = 0;
    char err[200] = "";
    assert_int_equal(trace_read(path, &d, &got, &n, err, sizeof err), 0);
    assert_int_equal(n, 5);
    assert_memory_equal(&c, &d, sizeof c);
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(got[i].enc[0], ticks[i].enc[0]);
        assert_int_equal(got[i].enc[1], ticks[i].enc[1]);
        assert_int_equal(got[i].poll, ticks[i].poll);
        assert_int_equal(got[i].echo_us, ticks[i].echo_us);
        assert_int_equal(got[i].trig, ticks[i].trig);
        assert_int_equal(got[i].duty[0], ticks[i].duty[0]);
        assert_int_equal(got[i].duty[1], ticks[i].duty[1]);
        assert_int_equal(got[i].servo_us, ticks[i].servo_us);
    }
    free(got);
}

static void test_bad_traces_are_refused(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *want;
    } cases[] = {
        {"sonarslam-trace 2\nend 0\n", ":1: not a version 1"},
        {"sonarslam-trace 1\ntick 1 2 x 0 - 0 0 1500\nend 1\n", ":2: malformed tick"},
        {"sonarslam-trace 1\ntick 70000 2 - 0 - 0 0 1500\nend 1\n", ":2: malformed tick"},
        {"sonarslam-trace 1\ntick 1 2 - 0 - 0 0 1500 junk\nend 1\n", ":2: malformed tick"},
        {"sonarslam-trace 1\nconfig om_max 300\nend 0\n", ":2: om_max"},
        {"sonarslam-trace 1\ntick 1 2 - 0 - 0 0 1500\nend 2\n", ":3: end says 2 ticks"},
        {"sonarslam-trace 1\ntick 1 2 - 0 - 0 0 1500\n", "no end line"},
        {"sonarslam-trace 1\nend 0\ntick 1 2 - 0 - 0 0 1500\n", ":3: text after the end"},
        {"sonarslam-trace 1\nhello\nend 0\n", ":2: unexpected line"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        FILE *f = fopen(path, "w");
        assert_non_null(f);
        fputs(cases[i].text, f);
        fclose(f);
        slam_config_t d;
        trace_tick_t *got = (trace_tick_t *)&d; /* must stay untouched */
        size_t n = 77;
        char err[200] = "";
        assert_int_equal(trace_read(path, &d, &got, &n, err, sizeof err), -1);
        if (strstr(err, cases[i].want) == NULL) {
            fail_msg("case %zu: '%s' lacks '%s'", i, err, cases[i].want);
        }
        assert_ptr_equal(got, (trace_tick_t *)&d);
        assert_int_equal(n, 77);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_round_trip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_traces_are_refused, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
