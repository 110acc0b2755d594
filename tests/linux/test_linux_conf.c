/* SPDX-License-Identifier: MIT */
/* Tests of robot.conf: the backend keys, every kind of bad input, and the shipped example. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "hal_common/config_text.h"
#include "lhal/lconf.h"
#include "tmptree.h"

#ifndef LHAL_EXAMPLE_CONF
#error "LHAL_EXAMPLE_CONF names hal/linux/robot-rpi.conf"
#endif

static char root[TMPTREE_PATH_MAX];
static char path[TMPTREE_PATH_MAX + 16];

/* Every required key, wired like the README's table: the [linux] section (its line is line
 * 1 of a file without core keys, so encoder_left_a is on line 2). */
static const char *const minimal = "[linux]\n"
                                   "encoder_left_a = 17\n"
                                   "encoder_left_b = 27\n"
                                   "encoder_right_a = 22\n"
                                   "encoder_right_b = 23\n"
                                   "sonar_trigger = 5\n"
                                   "sonar_echo = 6\n"
                                   "servo_pwm_chip = 2\n"
                                   "servo_pwm_channel = 0\n"
                                   "motor_left_pwm_chip = 0\n"
                                   "motor_left_pwm_channel = 0\n"
                                   "motor_right_pwm_chip = 0\n"
                                   "motor_right_pwm_channel = 1\n"
                                   "motor_left_in1 = 24\n"
                                   "motor_left_in2 = 25\n"
                                   "motor_right_in1 = 16\n"
                                   "motor_right_in2 = 26\n";

static int setup(void **state)
{
    (void)state;
    tmptree_make(root, "conf");
    snprintf(path, sizeof path, "%s/robot.conf", root);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tmptree_remove(root);
    return 0;
}

/* Writes robot.conf and loads it over the defaults; returns lconf_load's result. */
static int load_text(const char *text, slam_config_t *core, lconf_t *lc, char *err, size_t n)
{
    tmptree_file(root, "robot.conf", text);
    slam_config_default(core);
    lconf_default(lc);
    return lconf_load(path, core, lc, err, n);
}

/* Loads minimal + extra, the lines of extra that set the core's keys moved to the top of
 * the file, where they belong (a file with none puts the section on line 1). */
static int load(const char *extra, slam_config_t *core, lconf_t *lc, char *err, size_t n)
{
    char top[2048] = "";
    char section[2048] = "";
    for (const char *line = extra; *line != '\0';) {
        const char *end = strchr(line, '\n');
        size_t len = end != NULL ? (size_t)(end - line) + 1u : strlen(line);
        char key[64];
        bool core_key = sscanf(line, " %63[a-z0-9_]", key) == 1 && cfgtext_rule(key) != NULL;
        char *into = core_key ? top : section;
        strncat(into, line, len);
        line += len;
    }
    /* Room for both halves whole and the minimal file besides, which the optimiser of a
     * Debug build cannot see the length of (-Wformat-truncation). */
    char text[sizeof top + sizeof section + 4096];
    snprintf(text, sizeof text, "%s%s%s", top, minimal, section);
    return load_text(text, core, lc, err, n);
}

static void test_minimal_config_loads_with_defaults(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    assert_int_equal(load("", &core, &lc, err, sizeof err), 0);
    assert_int_equal(lc.enc_a[0], 17);
    assert_int_equal(lc.enc_b[1], 23);
    assert_int_equal(lc.motor_pwm[1].channel, 1);
    assert_int_equal(lc.motor_in2[1], 26);
    assert_string_equal(lc.gpio_chip, "gpiochip0");
    assert_string_equal(lc.pwm_root, "/sys/class/pwm");
    assert_string_equal(lc.telemetry, "none");
    assert_string_equal(lc.storage_dir, ".");
    assert_int_equal(lc.sonar_timeout_us, 30000);
    assert_int_equal(lc.motor_period_ns, 50000);
    assert_int_equal(lc.motor_standby, LCONF_NO_LINE);
    assert_int_equal(lc.enc_bias, LCONF_BIAS_AS_IS);
    assert_int_equal(lc.tick_priority, 50);
    assert_int_equal(lc.watchdog_idle_ms, 2000);
    assert_false(lc.enc_invert[0]);
}

static void test_optional_keys_and_core_keys(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    assert_int_equal(load("gpio_chip = pinctrl-rp1\n"
                          "encoder_right_invert = yes\n"
                          "motor_left_invert = true\n"
                          "encoder_bias = pull-up\n"
                          "motor_standby = 20\n"
                          "motor_right_in2 = -1\n" /* a second value for a key: see below */
                          ,
                          &core, &lc, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "motor_right_in2 is given twice"));
    assert_non_null(strstr(err, "robot.conf:23:"));

    assert_int_equal(load("gpio_chip = pinctrl-rp1\n"
                          "encoder_right_invert = yes\n"
                          "motor_left_invert = true\n"
                          "encoder_bias = pull-up\n"
                          "motor_standby = 20\n"
                          "telemetry = pty\n"
                          "telemetry_baud = 921600\n"
                          "storage_dir = /var/lib/sonarslam\n"
                          "tick_priority = 0\n"
                          "watchdog_idle_ms = 0\n"
                          "pwm_root = /tmp/pwm\n"
                          "wheel_base_um = 150000\n"
                          "encoder_counts_per_rev = 1320\n",
                          &core, &lc, err, sizeof err),
                     0);
    assert_string_equal(lc.gpio_chip, "pinctrl-rp1");
    assert_true(lc.enc_invert[1]);
    assert_true(lc.motor_invert[0]);
    assert_int_equal(lc.enc_bias, LCONF_BIAS_PULL_UP);
    assert_int_equal(lc.motor_standby, 20);
    assert_string_equal(lc.telemetry, "pty");
    assert_int_equal(lc.telemetry_baud, 921600);
    assert_string_equal(lc.storage_dir, "/var/lib/sonarslam");
    assert_int_equal(lc.tick_priority, 0);
    assert_int_equal(lc.watchdog_idle_ms, 0);
    assert_string_equal(lc.pwm_root, "/tmp/pwm");
    assert_int_equal(core.wheel_base_um, 150000);
    assert_int_equal(core.encoder_counts_per_rev, 1320);
}

static void test_dir_driver_without_in2(void **state)
{
    (void)state;
    lconf_t lc;
    lconf_default(&lc);
    char err[256] = "";
    assert_int_equal(lconf_set(&lc, "motor_left_in2", "-1", 0u, err, sizeof err), 0);
    assert_int_equal(lc.motor_in2[0], LCONF_NO_LINE);
}

/* Each bad line, appended to a good file, must fail naming the key (or the line), with
 * neither configuration changed. */
static void test_every_bad_input_is_named_and_changes_nothing(void **state)
{
    (void)state;
    static const struct {
        const char *line;
        const char *says;
    } cases[] = {
        {"no_such_key = 1\n", "unknown key 'no_such_key'"},
        {"this line has no equals sign\n", "expected 'key = value'"},
        {"sonar_echo_x = 3\n", "unknown key"},
        {"gpio_chip =\n", "gpio_chip = '': must not be empty"},
        {"gpio_chip = a-label-much-longer-than-sixty-three-characters-is-refused-here-ok\n",
         "gpio_chip = 'a-label"},
        {"pwm_root = \n", "pwm_root = '': must not be empty"},
        {"telemetry_baud = 12345\n", "telemetry_baud = '12345': expected 9600"},
        {"telemetry_baud = fast\n", "telemetry_baud = 'fast'"},
        {"encoder_left_invert = 2\n", "encoder_left_invert = '2': expected 0 or 1"},
        {"motor_right_invert = maybe\n", "motor_right_invert = 'maybe'"},
        {"encoder_bias = pullup\n", "encoder_bias = 'pullup': expected as-is, disable, pull-up"},
        {"sonar_timeout_us = 999\n",
         "sonar_timeout_us = '999': expected a whole number 1000..100000"},
        {"sonar_timeout_us = 100001\n", "sonar_timeout_us = '100001'"},
        {"sonar_timeout_us = 3e4\n", "sonar_timeout_us = '3e4'"},
        {"motor_pwm_period_ns = 9999\n", "motor_pwm_period_ns = '9999'"},
        {"motor_pwm_period_ns = 50000001\n", "motor_pwm_period_ns = '50000001'"},
        {"storage_bytes = 4095\n", "storage_bytes = '4095'"},
        {"tick_priority = 99\n", "tick_priority = '99'"},
        {"tick_priority = -1\n", "tick_priority = '-1'"},
        {"watchdog_idle_ms = 50\n",
         "watchdog_idle_ms = '50': expected a whole number 0 (off) or 100..60000"},
        {"watchdog_idle_ms = 60001\n", "watchdog_idle_ms = '60001'"},
        {"motor_standby = -2\n", "motor_standby = '-2': expected a line offset 0..4095, or -1"},
        {"motor_standby = 4096\n", "motor_standby = '4096'"},
        {"wheel_base_um = 1\n", ":1: wheel_base_um = 1 is out of its valid range: 50000..1000000"},
        {"sweep_stops = 1\n", "sweep_stops = 1 is out of its valid range: 1..16, and 1 only when"},
        {"wheel_base_um = many\n", "wheel_base_um = 'many': expected a whole number"},
        {"sweep_stops = 300\n", "sweep_stops = '300': out of its valid range: 1..16"},
        {"wheel_base_um = -130000\n",
         "wheel_base_um = '-130000': out of its valid range: 50000..1000000"},
        /* Numbers are decimal (hal_common/number.h); control bytes are shown escaped. */
        {"sonar_timeout_us = 0x7530\n", "sonar_timeout_us = '0x7530': expected a whole number"},
        {"gpio_chip = \033]0;PWNED\007x\n", "gpio_chip = '\\x1b]0;PWNED\\x07x': holds a control"},
        {"encoder_bias = \033[31m\n", "encoder_bias = '\\x1b[31m': expected as-is"},
        /* Duplicates of required keys are caught where they repeat. */
        {"sonar_echo = 7\n", ":18: sonar_echo is given twice (first on line 7)"},
        {"encoder_left_a = 18\n", ":18: encoder_left_a is given twice (first on line 2)"},
        /* A core key given twice is as wrong as a backend key given twice. */
        {"wheel_base_um = 140000\nwheel_base_um = 150000\n",
         ":2: wheel_base_um is given twice (first on line 1)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        slam_config_t core;
        lconf_t lc;
        char err[512] = "";
        assert_int_equal(load(cases[i].line, &core, &lc, err, sizeof err), -1);
        if (strstr(err, cases[i].says) == NULL) {
            fail_msg("case %zu (%s): message '%s' does not say '%s'", i, cases[i].line, err,
                     cases[i].says);
        }
        assert_non_null(strstr(err, "robot.conf"));
        slam_config_t core0;
        lconf_t lc0;
        slam_config_default(&core0);
        lconf_default(&lc0);
        assert_memory_equal(&core, &core0, sizeof core);
        assert_memory_equal(&lc, &lc0, sizeof lc);
    }
}

static void test_bad_line_values_say_which_line(void **state)
{
    (void)state;
    static const struct {
        const char *key;
        const char *value;
        const char *says;
    } cases[] = {
        {"sonar_echo", "-1", "expected a line offset 0..4095"}, /* required: no "not wired" */
        {"sonar_echo", "4096", "expected a line offset 0..4095"},
        {"sonar_echo", "6x", "expected a line offset"},
        {"sonar_echo", "", "expected a line offset"},
        {"encoder_left_a", "GPIO17", "expected a line offset"},
        {"servo_pwm_chip", "-1", "expected a number 0..1023"},
        {"servo_pwm_channel", "1024", "expected a number 0..1023"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        lconf_t lc;
        lconf_default(&lc);
        lconf_t lc0 = lc;
        char err[256] = "";
        assert_int_equal(lconf_set(&lc, cases[i].key, cases[i].value, 0u, err, sizeof err), -2);
        assert_non_null(strstr(err, cases[i].key));
        assert_non_null(strstr(err, cases[i].says));
        assert_memory_equal(&lc, &lc0, sizeof lc);
    }
    lconf_t lc;
    lconf_default(&lc);
    char err[256] = "";
    assert_int_equal(lconf_set(&lc, "wheel_base_um", "1", 0u, err, sizeof err), -1); /* not ours */
}

/* Loads a copy of the minimal file with one line replaced. */
static int load_replacing(const char *line, const char *with, slam_config_t *core, lconf_t *lc,
                          char *err, size_t n)
{
    char text[4096];
    const char *at = strstr(minimal, line);
    assert_non_null(at);
    snprintf(text, sizeof text, "%.*s%s%s", (int)(at - minimal), minimal, with, at + strlen(line));
    return load_text(text, core, lc, err, n);
}

static void test_whole_file_checks(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";

    assert_int_equal(load_replacing("sonar_echo = 6\n", "", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "robot.conf: missing key 'sonar_echo'"));

    /* A clash names both keys with their lines, and blames the later one. */
    assert_int_equal(load("motor_standby = 17\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err,
                           "robot.conf:18: encoder_left_a (line 2) and motor_standby (line 18) "
                           "both use line 17"));

    assert_int_equal(load_replacing("motor_right_pwm_channel = 1\n",
                                    "motor_right_pwm_channel = 0\n", &core, &lc, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "robot.conf:13: motor_left and motor_right both use PWM channel "
                                "pwmchip0/pwm0 (lines 11 and 13)"));

    /* Optional lines that are not wired may all be -1. */
    assert_int_equal(load_replacing("motor_left_in2 = 25\n", "motor_left_in2 = -1\n", &core, &lc,
                                    err, sizeof err),
                     0);
    lc.motor_in2[1] = LCONF_NO_LINE;
    assert_int_equal(lconf_check(&lc, err, sizeof err), 0);
}

static void test_instances_and_bump_switches_are_off_by_default(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    assert_int_equal(load("", &core, &lc, err, sizeof err), 0);
    assert_int_equal(lconf_sonars(&lc), 1u);
    assert_int_equal(lconf_servos(&lc), 1u);
    assert_int_equal(lconf_bumps(&lc), 0u);
    assert_int_equal(lc.sonar1_trigger, LCONF_NO_LINE);
    assert_int_equal(lc.servo1_pwm.chip, -1);
    assert_int_equal(lc.bump_bias, LCONF_BIAS_PULL_UP);
    assert_true(lc.bump_active_low);
}

static void test_instance_1_and_bump_switches(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    assert_int_equal(load("sonar1_trigger = 19\n"
                          "sonar1_echo = 21\n"
                          "servo1_pwm_chip = 2\n"
                          "servo1_pwm_channel = 1\n"
                          "bump0 = 4\n"
                          "bump1 = 14\n"
                          "bump_bias = disable\n"
                          "bump_active_low = no\n",
                          &core, &lc, err, sizeof err),
                     0);
    assert_int_equal(lconf_sonars(&lc), 2u);
    assert_int_equal(lconf_servos(&lc), 2u);
    assert_int_equal(lconf_bumps(&lc), 2u);
    assert_false(lc.bump_active_low);
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(&lc, lines);
    assert_string_equal(lines[LCONF_SONAR1_TRIGGER].name, "sonar1_trigger");
    assert_int_equal(lines[LCONF_SONAR1_TRIGGER].offset, 19);
    assert_int_equal(lines[LCONF_SONAR1_TRIGGER].bias, LCONF_OUTPUT);
    assert_int_equal(lines[LCONF_SONAR1_ECHO].offset, 21);
    assert_int_equal(lines[LCONF_SONAR1_ECHO].bias, LCONF_BIAS_AS_IS);
    assert_string_equal(lines[LCONF_BUMP0 + 1].name, "bump1");
    assert_int_equal(lines[LCONF_BUMP0 + 1].offset, 14);
    assert_int_equal(lines[LCONF_BUMP0 + 1].bias, LCONF_BIAS_DISABLE);
    assert_int_equal(lines[LCONF_BUMP0 + 2].offset, LCONF_NO_LINE);

    /* An instance needs both of its keys; switches are numbered without a gap. */
    assert_int_equal(load("sonar1_trigger = 19\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "robot.conf:18: sonar1_trigger is given without sonar1_echo"));
    assert_int_equal(load("servo1_pwm_channel = 1\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(
        strstr(err, "robot.conf:18: servo1_pwm_channel is given without servo1_pwm_chip"));
    assert_int_equal(load("bump1 = 14\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "robot.conf:18: bump1 is given without bump0"));
    /* Their lines and channels are checked against every other's. */
    assert_int_equal(load("sonar1_trigger = 19\nsonar1_echo = 6\n", &core, &lc, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "sonar_echo (line 7) and sonar1_echo (line 19) both use line 6"));
    assert_int_equal(load("bump0 = 23\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "encoder_right_b (line 5) and bump0 (line 18) both use line 23"));
    assert_int_equal(
        load("servo1_pwm_chip = 2\nservo1_pwm_channel = 0\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "servo and servo1 both use PWM channel pwmchip2/pwm0"));
    assert_int_equal(load("servo1_pwm_chip = -2\n", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "servo1_pwm_chip = '-2': expected a number 0..1023, or -1"));
}

/* One file describes the robot for both programs: the core's keys before the first
 * section, the Linux program's in [linux]; a key in the other part says where it belongs. */
static void test_keys_belong_to_their_part_of_the_file(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *says;
    } cases[] = {
        {"gpio_chip = gpiochip4\n[linux]\n", "robot.conf:1: unknown key 'gpio_chip'"},
        {"gpio_chip = gpiochip4\n[linux]\n", "this program's own keys belong under [linux]"},
        {"[linux]\nwheel_base_um = 140000\n",
         "robot.conf:2: wheel_base_um is a key of the robot's core (slam_config_t): it belongs "
         "before the first [section]"},
        {"[linx]\n", "robot.conf:1: unknown section [linx] (the sections: [linux])"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        slam_config_t core;
        lconf_t lc;
        char err[512] = "";
        assert_int_equal(load_text(cases[i].text, &core, &lc, err, sizeof err), -1);
        if (strstr(err, cases[i].says) == NULL) {
            fail_msg("case %zu: message '%s' does not say '%s'", i, err, cases[i].says);
        }
    }
    /* A section header may be written with spaces and a comment; the section may come
     * twice (what a program skips or reads is decided line by line). */
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    char text[4096];
    snprintf(text, sizeof text, "wheel_base_um = 140000\n%s[ linux ]  # again\ntelemetry = pty\n",
             minimal);
    assert_int_equal(load_text(text, &core, &lc, err, sizeof err), 0);
    assert_int_equal(core.wheel_base_um, 140000);
    assert_string_equal(lc.telemetry, "pty");
}

static void test_missing_file_is_named(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    slam_config_default(&core);
    lconf_default(&lc);
    char err[512] = "";
    assert_int_equal(lconf_load("/nonexistent/robot.conf", &core, &lc, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/robot.conf: cannot open"));
}

static void test_lines_are_listed_with_their_roles(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    char err[512] = "";
    assert_int_equal(load("encoder_bias = pull-down\n", &core, &lc, err, sizeof err), 0);
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(&lc, lines);
    assert_string_equal(lines[LCONF_ENC_RIGHT_B].name, "encoder_right_b");
    assert_int_equal(lines[LCONF_ENC_RIGHT_B].offset, 23);
    assert_int_equal(lines[LCONF_ENC_LEFT_A].bias, LCONF_BIAS_PULL_DOWN);
    assert_int_equal(lines[LCONF_SONAR_ECHO].bias, LCONF_BIAS_AS_IS);
    assert_int_equal(lines[LCONF_SONAR_TRIGGER].bias, LCONF_OUTPUT);
    assert_int_equal(lines[LCONF_MOTOR_LEFT_IN2].offset, 25);
    assert_int_equal(lines[LCONF_MOTOR_STANDBY].offset, LCONF_NO_LINE);
}

static void test_shipped_example_loads(void **state)
{
    (void)state;
    slam_config_t core;
    lconf_t lc;
    slam_config_default(&core);
    lconf_default(&lc);
    char err[512] = "";
    assert_int_equal(lconf_load(LHAL_EXAMPLE_CONF, &core, &lc, err, sizeof err), 0);
    assert_string_equal(lc.gpio_chip, "pinctrl-bcm2711");
    assert_int_equal(lc.sonar_echo, 6);
    assert_int_equal(lc.motor_standby, 20);
    assert_true(lc.enc_invert[1]);
    assert_int_equal(core.encoder_counts_per_rev, 700);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_minimal_config_loads_with_defaults, setup, teardown),
        cmocka_unit_test_setup_teardown(test_optional_keys_and_core_keys, setup, teardown),
        cmocka_unit_test(test_dir_driver_without_in2),
        cmocka_unit_test_setup_teardown(test_every_bad_input_is_named_and_changes_nothing, setup,
                                        teardown),
        cmocka_unit_test(test_bad_line_values_say_which_line),
        cmocka_unit_test_setup_teardown(test_whole_file_checks, setup, teardown),
        cmocka_unit_test_setup_teardown(test_instances_and_bump_switches_are_off_by_default, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_instance_1_and_bump_switches, setup, teardown),
        cmocka_unit_test_setup_teardown(test_keys_belong_to_their_part_of_the_file, setup,
                                        teardown),
        cmocka_unit_test(test_missing_file_is_named),
        cmocka_unit_test_setup_teardown(test_lines_are_listed_with_their_roles, setup, teardown),
        cmocka_unit_test(test_shipped_example_loads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
