/* SPDX-License-Identifier: MIT */
/* Tests of the configuration as text: round trip, every kind of bad input, file errors. */
#define _POSIX_C_SOURCE 200809L /* mkfifo, ftruncate, fileno */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "hal_common/config_text.h"
#include "slam/config_fields.h"

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
    assert_int_equal(cfgtext_load(path, &d, NULL, NULL, NULL, err, sizeof err), 0);
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
    assert_int_equal(n, SLAM_CONFIG_ROWS); /* every field, once */
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
        {"om_max", "256"},
        {"om_max", "-1"},
        {"om_max", "9x"},
        {"om_max", ""},
        {"wheel_base_um", "4294967296"},
        {"start_x_um", "2147483648"},
        {"cal_left", "abc"},
        {"cal_left", "2.5"},
        {"cal_left", "nan"},
        {"cal_left", "1.0 2"},
        {"settle_ticks", "3.5"},
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

static int take_pins(void *ctx, const char *key, const char *value, unsigned line, char *err,
                     size_t n)
{
    (void)line;
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
        {"wheel_base_um = 0\n", ":1: wheel_base_um = 0 is out of its valid range: 50000..1000000"},
        /* The check names the key, its value, its rule and the line that set it. */
        {"sweep_first_mdeg = 65000\n\nsweep_stops = 1\n",
         ":3: sweep_stops = 1 is out of its valid range: 1..16, and 1 only when "
         "sweep_first_mdeg equals sweep_last_mdeg"},
        /* A bad value the file did not set is blamed on the line of the field its rule
         * compares it with, and both values are given. */
        {"om_mode = 0\nom_max = 2\npost_threshold = 3\n",
         ":3: post_threshold = 3 is out of its valid range: 0..254, below om_max when om_mode is "
         "0, "
         "below 127 when it is 1 (om_max = 2, om_mode = 0)"},
        {"top_speed_mm_s = 150\n", ":1: cruise_mm_s = 200 is out of its valid range: 1..5000, at "
                                   "most top_speed_mm_s (top_speed_mm_s = 150)"},
        /* A core key twice. */
        {"wheel_base_um = 140000\n# again:\nwheel_base_um = 150000\n",
         ":3: wheel_base_um is given twice (first on line 1)"},
        /* Numbers beyond the type say so, not "not a number". */
        {"wheel_base_um = 99999999999999999999999\n",
         ":1: wheel_base_um = '99999999999999999999999': "
         "out of its valid range: 50000..1000000"},
        {"cal_left = 1e999\n", ":1: cal_left = '1e999': must lie between -2 and 2"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_file(cases[i].text);
        int count = 0;
        err[0] = '\0';
        assert_int_equal(cfgtext_load(path, &c, take_pins, &count, NULL, err, sizeof err), -1);
        if (strstr(err, cases[i].want) == NULL || strstr(err, path) == NULL) {
            fail_msg("case %zu: message '%s' lacks '%s'", i, err, cases[i].want);
        }
        assert_memory_equal(&c, &keep, sizeof c); /* nothing changed */
    }
    assert_int_equal(cfgtext_load("/nonexistent/robot.conf", &c, NULL, NULL, NULL, err, sizeof err),
                     -1);
    assert_non_null(strstr(err, "/nonexistent/robot.conf: cannot open"));
    /* Comments, blanks, spaces, and a backend's own key. */
    write_file("  # robot\n\n wheel_base_um=135000   # measured\ngpio_chip = gpiochip0\n");
    int count = 0;
    cfgtext_where_t where;
    assert_int_equal(cfgtext_load(path, &c, take_pins, &count, &where, err, sizeof err), 0);
    assert_int_equal(c.wheel_base_um, 135000u);
    assert_int_equal(count, 1);
    assert_int_equal(cfgtext_where_line(&where, "wheel_base_um"), 3u);
    assert_int_equal(cfgtext_where_line(&where, "om_max"), 0u);
    assert_int_equal(cfgtext_where_line(&where, "gpio_chip"), 0u); /* not a core key */
}

/* Text that is not a configuration: NUL bytes, endless lines, huge files, a directory. */
static void test_not_text(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    slam_config_t keep = c;
    char err[256] = "";
    static const char nul[] = "om_max = 9\nwheel_base_um = 14\0000000\n";
    assert_int_equal(
        cfgtext_parse("mem.conf", nul, sizeof nul - 1u, &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "mem.conf:2: a NUL byte"));
    static char longline[2000];
    memset(longline, ' ', sizeof longline);
    memcpy(longline, "om_max = 9", 10);
    assert_int_equal(
        cfgtext_parse("mem.conf", longline, sizeof longline, &c, NULL, NULL, NULL, err, sizeof err),
        -1);
    assert_non_null(strstr(err, "mem.conf:1: line longer than 511 characters"));
    /* No newline at the end is fine. */
    assert_int_equal(
        cfgtext_parse("mem.conf", "om_max = 8", 10u, &c, NULL, NULL, NULL, err, sizeof err), 0);
    assert_int_equal(c.om_max, 8u);
    c = keep;
    /* An input is a regular file: /dev/zero (it never ends) and a FIFO (no writer: opening
     * it would wait for ever) are refused at once; a large file at its stated limit. */
    assert_int_equal(cfgtext_load("/dev/zero", &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/dev/zero: is not a regular file"));
    char fifo[64];
    snprintf(fifo, sizeof fifo, "/tmp/slam-cfgtext-%ld.fifo", (long)getpid());
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    assert_int_equal(cfgtext_load(fifo, &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, ".fifo: is not a regular file (a FIFO"));
    unlink(fifo);
    FILE *big = fopen(path, "w");
    assert_non_null(big);
    assert_int_equal(ftruncate(fileno(big), (off_t)CFGTEXT_FILE_MAX + 1), 0);
    fclose(big);
    assert_int_equal(cfgtext_load(path, &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, ": larger than 1048576 bytes"));
    assert_int_equal(cfgtext_load("/tmp", &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/tmp: is a directory"));
    assert_memory_equal(&c, &keep, sizeof c);
}

/* Every rule that states a range "lo..hi" agrees with slam_config_check() at both ends:
 * the messages cannot drift from the firmware unnoticed. */
static void test_rules_match_the_check(void **state)
{
    (void)state;
    static const char *const keys[] = {
#define KEY_NAME(name, type, dflt, lo, hi, rule, id, live, words) #name,
        SLAM_CONFIG_FIELDS(KEY_NAME)
#undef KEY_NAME
    };
    FILE *f = fopen(path, "w+");
    assert_non_null(f);
    slam_config_t d;
    slam_config_default(&d);
    cfgtext_write(f, &d);
    rewind(f);
    char key[64];
    char value[64];
    size_t n = 0;
    while (fscanf(f, "%63s = %63s\n", key, value) == 2) { /* every field has a rule */
        if (cfgtext_rule(key) == NULL) {
            fail_msg("%s has no rule", key);
        }
        if (n >= sizeof keys / sizeof keys[0] || strcmp(key, keys[n]) != 0) {
            fail_msg("line %zu of the text is %s, not the table's row", n + 1u, key);
        }
        n++;
    }
    fclose(f);
    assert_int_equal(n, sizeof keys / sizeof keys[0]);
    char err[256];
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        const char *rule = cfgtext_rule(keys[i]);
        assert_non_null(rule);
        const char *dots = strstr(rule, "..");
        char *end_lo = NULL;
        char *end_hi = NULL;
        double lo = dots != NULL ? strtod(rule, &end_lo) : 0.0;
        double hi = dots != NULL ? strtod(dots + 2, &end_hi) : 0.0;
        if (dots == NULL || end_lo == rule || (end_lo != dots && end_lo != dots + 1) ||
            end_hi == dots + 2) {
            fail_msg("%s: rule '%s' does not begin with lo..hi", keys[i], rule);
        }
        bool plain = *end_hi == '\0' || *end_hi == ' '; /* no ", and ..." condition */
        bool fraction = strncmp(keys[i], "cal_", 4) == 0;
        double step = fraction ? 0.001 : 1.0;
        const double probe[4] = {lo, hi, lo - step, hi + step};
        for (int k = 0; k < 4; k++) {
            if (k < 2 && !plain) {
                continue; /* the bound depends on another field */
            }
            slam_config_t c;
            slam_config_default(&c);
            char text[40];
            snprintf(text, sizeof text, fraction ? "%.3f" : "%.0f", probe[k]);
            bool ok = cfgtext_set(&c, keys[i], text, err, sizeof err) == 0 &&
                      slam_config_check(&c, NULL) == 0;
            if (ok != (k < 2)) {
                fail_msg("%s = %s: the rule '%s' says %s, the check says %s", keys[i], text, rule,
                         k < 2 ? "valid" : "invalid", ok ? "valid" : "invalid");
            }
        }
    }
}

/* explore_mode's words list the modes of explore_modes.h, by number, and the text takes
 * each number. */
static void test_mode_words_are_the_modes(void **state)
{
    (void)state;
    char want[160] = "";
#define MODE_NAME(id, value, name, ...) #name ", "
    static const char names[] = SLAM_EXPLORE_MODES(MODE_NAME);
#undef MODE_NAME
    snprintf(want, sizeof want, "0..%d (%.*s)", EXPLORE_MODES - 1, (int)sizeof names - 3, names);
    assert_string_equal(cfgtext_rule("explore_mode"), want);
    assert_null(cfgtext_rule("no_such_key"));
    char err[256];
    for (int m = 0; m < EXPLORE_MODES; m++) {
        slam_config_t c;
        slam_config_default(&c);
        char text[16];
        snprintf(text, sizeof text, "%d", m);
        assert_int_equal(cfgtext_set(&c, "explore_mode", text, err, sizeof err), 0);
        assert_int_equal(cfgtext_check(&c, NULL, err, sizeof err), 0);
    }
}

/* A rule that compares two fields names both, with their values, and in a file blames
 * the line that set either when the other was not set there. */
static void test_rule_messages_name_both_fields(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    char err[300] = "";
    static const char text[] = "# sonar\nrange_min_um = 1000000\n";
    assert_int_equal(
        cfgtext_parse("s.conf", text, sizeof text - 1u, &c, NULL, NULL, NULL, err, sizeof err), -1);
    assert_string_equal(err, "s.conf:2: confidence_radius_um = 1000000 is out of its valid range: "
                             "1..10000000, above range_min_um (range_min_um = 1000000)");
    assert_string_equal(cfgtext_partners("sweep_stops"), "sweep_first_mdeg sweep_last_mdeg");
    assert_null(cfgtext_partners("wheel_base_um"));
    assert_null(cfgtext_partners("no_such_key"));
}

/* A message quotes the file: control bytes in it are shown escaped, never sent to the
 * terminal (an xterm takes ESC ] 0 ; ... BEL as a new title). */
static void test_messages_escape_control_bytes(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *says;
    } cases[] = {
        {"cell_um = \033]0;PWNED\007\n", "x.conf:1: cell_um = '\\x1b]0;PWNED\\x07': expected"},
        {"\033[2J = 5\n", "x.conf:1: unknown key '\\x1b[2J'"},
        {"no equals \r here\n", "x.conf:1: expected 'key = value', got 'no equals \\x0d here'"},
        {"cal_left = \xc2\x9b"
         "1m\n",
         "cal_left = '\\xc2\\x9b1m'"}, /* C1 CSI in UTF-8 */
        {"cal_left = \xff\n", "cal_left = '\\xff'"},
        {"cal_left = caf\xc3\xa9\n", "cal_left = 'caf\xc3\xa9'"}, /* printable UTF-8 stays */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        slam_config_t c;
        slam_config_default(&c);
        char err[256] = "";
        assert_int_equal(cfgtext_parse("x.conf", cases[i].text, strlen(cases[i].text), &c, NULL,
                                       NULL, NULL, err, sizeof err),
                         -1);
        if (strstr(err, cases[i].says) == NULL) {
            fail_msg("case %zu: '%s' does not say '%s'", i, err, cases[i].says);
        }
        for (const char *p = err; *p != '\0'; p++) {
            assert_true((unsigned char)*p >= 0x20u && (unsigned char)*p != 0x7Fu);
        }
    }
    /* Escaping is idempotent, and what is cut is cut at a whole escape. */
    char s[32] = "a\033b";
    cfgtext_escape(s, sizeof s);
    assert_string_equal(s, "a\\x1bb");
    cfgtext_escape(s, sizeof s);
    assert_string_equal(s, "a\\x1bb");
    char small[5] = "\033\033";
    cfgtext_escape(small, sizeof small);
    assert_string_equal(small, "\\x1b");
    /* --set values go through cfgtext_set(), which escapes too. */
    slam_config_t c;
    slam_config_default(&c);
    char err[128] = "";
    assert_int_equal(cfgtext_set(&c, "cell_um", "\a5", err, sizeof err), -2);
    assert_non_null(strstr(err, "'\\x075'"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_round_trip_is_exact, setup, teardown),
        cmocka_unit_test_setup_teardown(test_raw_round_trip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_set_values_and_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_file_errors_name_file_and_line, setup, teardown),
        cmocka_unit_test_setup_teardown(test_not_text, setup, teardown),
        cmocka_unit_test_setup_teardown(test_rules_match_the_check, setup, teardown),
        cmocka_unit_test(test_mode_words_are_the_modes),
        cmocka_unit_test(test_messages_escape_control_bytes),
        cmocka_unit_test(test_rule_messages_name_both_fields),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
