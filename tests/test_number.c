/* SPDX-License-Identifier: MIT */
/* Tests of the one rule for numbers in text (hal_common/number.h) against the table of
 * cases the Python readers are held to as well (tests/data/numbers.txt). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "hal_common/number.h"

#ifndef NUMBERS_TXT
#error "NUMBERS_TXT names tests/data/numbers.txt"
#endif

/* \xNN escapes of a case's text, undone in place. */
static void unescape(char *s)
{
    char *out = s;
    for (const char *p = s; *p != '\0';) {
        if (p[0] == '\\' && p[1] == 'x' && p[2] != '\0' && p[3] != '\0') {
            char hex[3] = {p[2], p[3], '\0'};
            *out++ = (char)strtol(hex, NULL, 16);
            p += 4;
        } else {
            *out++ = *p++;
        }
    }
    *out = '\0';
}

static void test_every_case_of_the_table(void **state)
{
    (void)state;
    FILE *f = fopen(NUMBERS_TXT, "r");
    assert_non_null(f);
    char line[256];
    unsigned cases = 0u;
    while (fgets(line, sizeof line, f) != NULL) {
        line[strcspn(line, "\n")] = '\0';
        if (line[0] == '#' || line[0] == '\0') {
            continue;
        }
        char *kind = line;
        char *text = strchr(kind, '|');
        assert_non_null(text);
        *text++ = '\0';
        char *want = strrchr(text, '|');
        assert_non_null(want);
        *want++ = '\0';
        unescape(text);
        num_status_t expect = strcmp(want, "bad") == 0     ? NUM_BAD
                              : strcmp(want, "range") == 0 ? NUM_RANGE
                                                           : NUM_OK;
        if (strcmp(kind, "int") == 0) {
            long long v = 12345;
            num_status_t r = num_int(text, INT64_MIN, INT64_MAX, &v);
            if (r != expect) {
                fail_msg("int '%s': %d, expected %d", text, (int)r, (int)expect);
            }
            if (r == NUM_OK) {
                assert_true(v == strtoll(want, NULL, 10));
            } else {
                assert_true(v == 12345); /* untouched */
            }
        } else {
            assert_string_equal(kind, "real");
            double v = 12345.0;
            num_status_t r = num_real(text, -HUGE_VAL, HUGE_VAL, &v);
            if (r != expect) {
                fail_msg("real '%s': %d, expected %d", text, (int)r, (int)expect);
            }
            if (r == NUM_OK) {
                assert_true(v == strtod(want, NULL));
            } else {
                assert_true(v == 12345.0);
            }
        }
        cases++;
    }
    fclose(f);
    assert_true(cases >= 50u);
}

static void test_ranges_are_inclusive(void **state)
{
    (void)state;
    long long i = 0;
    assert_int_equal(num_int("5", 5, 5, &i), NUM_OK);
    assert_int_equal(num_int("4", 5, 6, &i), NUM_RANGE);
    assert_int_equal(num_int("7", 5, 6, &i), NUM_RANGE);
    double d = 0.0;
    assert_int_equal(num_real("0.01", 0.01, 1e6, &d), NUM_OK);
    assert_int_equal(num_real("0.009", 0.01, 1e6, &d), NUM_RANGE);
    assert_int_equal(num_real("1e6", 0.01, 1e6, &d), NUM_OK);
    assert_int_equal(num_real("1000000.001", 0.01, 1e6, &d), NUM_RANGE);
}

static void test_unsigned_reaches_2_to_the_64_and_refuses_negatives(void **state)
{
    (void)state;
    unsigned long long u = 0u;
    assert_int_equal(num_uint("18446744073709551615", 0u, UINT64_MAX, &u), NUM_OK);
    assert_true(u == UINT64_MAX);
    assert_int_equal(num_uint("18446744073709551616", 0u, UINT64_MAX, &u), NUM_RANGE);
    assert_int_equal(num_uint("-1", 0u, UINT64_MAX, &u), NUM_RANGE);
    assert_int_equal(num_uint("-0", 0u, UINT64_MAX, &u), NUM_OK);
    assert_true(u == 0u);
    assert_int_equal(num_uint(" 1", 0u, UINT64_MAX, &u), NUM_BAD);
    assert_int_equal(num_uint("0x10", 0u, UINT64_MAX, &u), NUM_BAD);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_case_of_the_table),
        cmocka_unit_test(test_ranges_are_inclusive),
        cmocka_unit_test(test_unsigned_reaches_2_to_the_64_and_refuses_negatives),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
