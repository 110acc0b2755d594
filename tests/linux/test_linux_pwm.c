/* SPDX-License-Identifier: MIT */
/* Tests of the sysfs PWM writes (into a temporary tree) and of the motor direction plan. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "hal/hal.h"
#include "lhal/motor.h"
#include "lhal/pwm.h"
#include "tmptree.h"

static char root[TMPTREE_PATH_MAX];

static int setup(void **state)
{
    (void)state;
    tmptree_make(root, "pwm");
    tmptree_pwm_channel(root, 0u, 0u);
    tmptree_file(root, "pwmchip0/export", "");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tmptree_remove(root);
    return 0;
}

static void test_open_existing_channel_writes_nothing(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256] = "";
    assert_int_equal(pwm_open(&p, root, 0u, 0u, 0u, err, sizeof err), 0);
    char want[TMPTREE_PATH_MAX + 32];
    snprintf(want, sizeof want, "%s/pwmchip0/pwm0", root);
    assert_string_equal(p.dir, want);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/period"), "");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "");
    assert_string_equal(tmptree_read(root, "pwmchip0/export"), "");
    assert_int_equal(pwm_writable(&p, err, sizeof err), 0);
}

static void test_missing_chip_names_the_path(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256] = "";
    assert_int_equal(pwm_open(&p, root, 3u, 0u, 0u, err, sizeof err), -1);
    assert_non_null(strstr(err, "pwmchip3 does not exist"));
}

static void test_missing_channel_is_exported(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256] = "";
    /* The temporary tree does not grow pwm1 the way sysfs does, so this fails after the
     * export, and says which channel never appeared. */
    assert_int_equal(pwm_open(&p, root, 0u, 1u, 0u, err, sizeof err), -1);
    assert_string_equal(tmptree_read(root, "pwmchip0/export"), "1\n");
    assert_non_null(strstr(err, "pwm1 did not appear"));
}

static void test_export_failure_names_the_file(void **state)
{
    (void)state;
    tmptree_unlink(root, "pwmchip0/export");
    pwm_chan_t p;
    char err[256] = "";
    assert_int_equal(pwm_open(&p, root, 0u, 1u, 0u, err, sizeof err), -1);
    assert_non_null(strstr(err, "cannot export channel 1"));
    assert_non_null(strstr(err, "pwmchip0/export"));
}

static void test_start_writes_period_duty_enable(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256];
    assert_int_equal(pwm_open(&p, root, 0u, 0u, 0u, err, sizeof err), 0);
    assert_int_equal(pwm_start(&p, 20000000u, 1500000u), 0);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/period"), "20000000\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/duty_cycle"), "1500000\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "1\n");
    assert_true(p.enabled);
    assert_int_equal(p.period_ns, 20000000u);
}

static void test_duty_is_clamped_and_repeats_are_skipped(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256];
    assert_int_equal(pwm_open(&p, root, 0u, 0u, 0u, err, sizeof err), 0);
    assert_int_equal(pwm_start(&p, 50000u, 0u), 0);
    assert_int_equal(pwm_set_duty(&p, 90000u), 0);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/duty_cycle"), "50000\n");
    /* Without the file, a write fails: so an unchanged duty writes nothing... */
    tmptree_unlink(root, "pwmchip0/pwm0/duty_cycle");
    assert_int_equal(pwm_set_duty(&p, 50000u), 0);
    /* ...and a new one tries, and says why it failed. */
    assert_int_equal(pwm_set_duty(&p, 25000u), -ENOENT);
    assert_int_equal(p.duty_ns, UINT32_MAX); /* unknown now: the next write is not skipped */
}

static void test_stop_and_kill_write_zero(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256];
    assert_int_equal(pwm_open(&p, root, 0u, 0u, 0u, err, sizeof err), 0);
    assert_int_equal(pwm_start(&p, 50000u, 40000u), 0);
    assert_int_equal(pwm_stop(&p), 0);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
    assert_false(p.enabled);

    assert_int_equal(pwm_start(&p, 50000u, 40000u), 0);
    pwm_kill(&p);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
    assert_int_equal(p.duty_ns, 40000u); /* the kill switch leaves the owner's state alone */
}

static void test_not_writable_attribute_is_named(void **state)
{
    (void)state;
    pwm_chan_t p;
    char err[256] = "";
    assert_int_equal(pwm_open(&p, root, 0u, 0u, 0u, err, sizeof err), 0);
    tmptree_unlink(root, "pwmchip0/pwm0/enable");
    assert_int_equal(pwm_writable(&p, err, sizeof err), -1);
    assert_non_null(strstr(err, "pwm0/enable is not writable"));
}

static void test_write_u32_formats_like_echo(void **state)
{
    (void)state;
    char path[TMPTREE_PATH_MAX + 16];
    snprintf(path, sizeof path, "%s/x", root);
    assert_int_equal(pwm_write_u32(path, 0u), -ENOENT); /* it never creates files */
    tmptree_file(root, "x", "123456789\n");
    assert_int_equal(pwm_write_u32(path, 4294967295u), 0);
    assert_string_equal(tmptree_read(root, "x"), "4294967295\n");
    assert_int_equal(pwm_write_u32(path, 7u), 0);
    assert_string_equal(tmptree_read(root, "x"), "7\n"); /* truncated, not overwritten */
}

/* ---- motor plan ---------------------------------------------------------------------- */

static void test_motor_plan(void **state)
{
    (void)state;
    const struct {
        int16_t duty;
        bool invert;
        bool in1, in2;
        uint32_t duty_ns;
    } cases[] = {
        {500, false, true, false, 25000u},
        {-1000, false, false, true, 50000u},
        {0, false, false, false, 0u},
        {2000, false, true, false, 50000u},
        {INT16_MIN, false, false, true, 50000u},
        {1, false, true, false, 50u},
        {300, true, false, true, 15000u},
        {-300, true, true, false, 15000u},
        {0, true, false, false, 0u},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        motor_out_t m = motor_plan(cases[i].duty, cases[i].invert, 50000u);
        assert_int_equal(m.in1, cases[i].in1);
        assert_int_equal(m.in2, cases[i].in2);
        assert_int_equal(m.duty_ns, cases[i].duty_ns);
    }
    assert_true(
        motor_same_direction(motor_plan(100, false, 50000u), motor_plan(900, false, 50000u)));
    assert_false(
        motor_same_direction(motor_plan(100, false, 50000u), motor_plan(-100, false, 50000u)));
    assert_false(
        motor_same_direction(motor_plan(100, false, 50000u), motor_plan(0, false, 50000u)));
    /* Full scale of a 20 ms period does not overflow. */
    assert_int_equal(motor_plan(HAL_DUTY_MAX, false, 50000000u).duty_ns, 50000000u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_open_existing_channel_writes_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_chip_names_the_path, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_channel_is_exported, setup, teardown),
        cmocka_unit_test_setup_teardown(test_export_failure_names_the_file, setup, teardown),
        cmocka_unit_test_setup_teardown(test_start_writes_period_duty_enable, setup, teardown),
        cmocka_unit_test_setup_teardown(test_duty_is_clamped_and_repeats_are_skipped, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_stop_and_kill_write_zero, setup, teardown),
        cmocka_unit_test_setup_teardown(test_not_writable_attribute_is_named, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_u32_formats_like_echo, setup, teardown),
        cmocka_unit_test(test_motor_plan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
