/* SPDX-License-Identifier: MIT */
/* Tests of the configuration as text: round trip, every kind of bad input, file errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "hal_common/config_text.h"

static char path[64];

static int setup(void **state)
{
    (void)state;
    snprintf(path, sizeof path, "/tmp/slam-cfgtext-%ld.conf", (long)getpid());
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    unlink(path);
    return 0;
}

static void write_file(const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_round_trip_is_exact(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    c.cal_left = FIX_Q30_ONE - 12345;
    c.cal_right = FIX_Q30_ONE + 98765;
    c.start_x_um = -1234567;
    c.mount_yaw_mdeg = -15000;
    c.sweep_stops = 7u;
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    cfgtext_write(f, &c);
    fclose(f);
    slam_config_t d;
    slam_config_default(&d);
    char err[256] = "";
    assert_int_equal(cfgtext_load(path, &d, NULL, NULL, err, sizeof err), 0);
    assert_memory_equal(&c, &d, sizeof c);
}

static void test_raw_round_trip(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    c.cal_base = FIX_Q30_ONE + 77;
    c.mount_y_um = -31;
    FILE *f = fopen(path, "w+");
    assert_non_null(f);
    cfgtext_write_raw(f, &c, "config ");
    rewind(f);
    slam_config_t d;
    memset(&d, 0, sizeof d);
    char key[64];
    long long raw;
    char err[128];
    int n = 0;
    while (fscanf(f, "config %63s %lld\n", key, &raw) == 2) {
        assert_int_equal(cfgtext_set_raw(&d, key, raw, err, sizeof err), 0);
        n++;
    }
    fclose(f);
    assert_true(n >= 30);
    assert_memory_equal(&c, &d, sizeof c);
    assert_int_equal(cfgtext_set_raw(&d, "om_max", 256, err, sizeof err), -2);
    assert_int_equal(cfgtext_set_raw(&d, "nope", 1, err, sizeof err), -1);
}

static void test_set_values_and_errors(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    slam_config_t keep = c;
    char err[256];
    assert_int_equal(cfgtext_set(&c, "wheel_base_um", "140000", err, sizeof err), 0);
    assert_int_equal(c.wheel_base_um, 140000u);
    assert_int_equal(cfgtext_set(&c, "cal_base", "1.5", err, sizeof err), 0);
    assert_int_equal(c.cal_base, FIX_Q30_ONE + FIX_Q30_ONE / 2);
    assert_int_equal(cfgtext_set(&c, "start_x_um", "-42", err, sizeof err), 0);
    assert_int_equal(c.start_x_um, -42);
    c = keep;
    static const char *const bad[][2] = {
        {"om_max", "256"},           {"om_max", "-1"},        {"om_max", "9x"},
        {"om_max", ""},              {"wheel_base_um", "4294967296"},
        {"start_x_um", "2147483648"}, {"cal_left", "abc"},     {"cal_left", "2.5"},
        {"cal_left", "nan"},         {"cal_left", "1.0 2"},   {"settle_ticks", "3.5"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err[0] = '\0';
        assert_int_equal(cfgtext_set(&c, bad[i][0], bad[i][1], err, sizeof err), -2);
        assert_non_null(strstr(err, bad[i][0])); /* the message names the key */
        assert_memory_equal(&c, &keep, sizeof c);
    }
    assert_int_equal(cfgtext_set(&c, "no_such_key", "1", err, sizeof err), -1);
    assert_non_null(strstr(err, "no_such_key"));
    assert_memory_equal(&c, &keep, sizeof c);
}

static int take_pins(void *ctx, const char *key, const char *value, char *err, size_t n)
{
    int *count = ctx;
    if (strcmp(key, "gpio_chip") == 0) {
        (*count)++;
        return strcmp(value, "gpiochip0") == 0 ? 0 : (snprintf(err, n, "bad chip"), -2);
    }
    snprintf(err, n, "unknown key '%s'", key);
    return -1;
}

static void test_file_errors_name_file_and_line(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    slam_config_t keep = c;
    char err[256];
    static const struct {
        const char *text;
        const char *want;
    } cases[] = {
        {"# ok\nwheel_base_um = 140000\nbogus\n", ":3: expected 'key = value'"},
        {"\n\nom_max = lots\n", ":3: om_max = 'lots'"},
        {"nope = 1\n", ":1: unknown key 'nope'"},
        {"gpio_chip = gpiochip9\n", ":1: bad chip"},
        {"wheel_base_um = 0\n", "wheel_base_um is out of its valid range"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_file(cases[i].text);
        int count = 0;
        err[0] = '\0';
        assert_int_equal(cfgtext_load(path, &c, take_pins, &count, err, sizeof err), -1);
        if (strstr(err, cases[i].want) == NULL || strstr(err, path) == NULL) {
            fail_msg("case %zu: message '%s' lacks '%s'", i, err, cases[i].want);
        }
        assert_memory_equal(&c, &keep, sizeof c); /* nothing changed */
    }
    assert_int_equal(cfgtext_load("/nonexistent/robot.conf", &c, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/robot.conf: cannot open"));
    /* Comments, blanks, spaces, and a backend's own key. */
    write_file("  # robot\n\n wheel_base_um=135000   # measured\ngpio_chip = gpiochip0\n");
    int count = 0;
    assert_int_equal(cfgtext_load(path, &c, take_pins, &count, err, sizeof err), 0);
    assert_int_equal(c.wheel_base_um, 135000u);
    assert_int_equal(count, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_round_trip_is_exact, setup, teardown),
        cmocka_unit_test_setup_teardown(test_raw_round_trip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_set_values_and_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_file_errors_name_file_and_line, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
