/* SPDX-License-Identifier: MIT */
/* Tests of the fake HAL's instances, and that the robot uses the paper's servo and sonar alone. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fake_hal.h"
#include "one_sensor_board.h"
#include "slam/error.h"
#include "slam/robot.h"

static robot_t robot;

static int reset(void **state)
{
    (void)state;
    fake_hal_reset();
    return 0;
}

static void test_one_of_each_and_no_switches_by_default(void **state)
{
    (void)state;
    assert_one_sensor_board();
    assert_int_equal(fake_hal.calls_bad_instance, 4u);
    /* Nothing of instance 0 was touched. */
    assert_int_equal(fake_hal.calls_servo + fake_hal.calls_trigger + fake_hal.calls_poll, 0u);
}

static void test_more_instances_when_scripted(void **state)
{
    (void)state;
    fake_hal.servos = 2u;
    fake_hal.sonars = 2u;
    fake_hal.bumps = 2u;
    fake_hal.bump_pressed[1] = true;
    uint32_t echo = 7u;
    bool pressed = true;
    assert_int_equal(hal_servo_set_pulse(1u, 1234u), HAL_OK);
    assert_int_equal(fake_hal.servo_pulse_other_us[0], 1234u);
    assert_int_equal(fake_hal.servo_pulse_us, 0u);
    assert_int_equal(hal_sonar_trigger(1u), HAL_OK);
    assert_int_equal(hal_sonar_poll(1u, &echo), HAL_SONAR_IDLE);
    assert_int_equal(fake_hal.calls_other_instance, 3u);
    assert_int_equal(hal_sonar_trigger(2u), HAL_EINVAL);
    assert_int_equal(hal_bump_read(0u, &pressed), HAL_OK);
    assert_false(pressed);
    assert_int_equal(hal_bump_read(1u, &pressed), HAL_OK);
    assert_true(pressed);
    assert_int_equal(hal_bump_read(2u, &pressed), HAL_EINVAL);
    assert_int_equal(hal_bump_read(0u, NULL), HAL_EINVAL);
}

static void test_robot_uses_instance_0_alone(void **state)
{
    (void)state;
    fake_hal.servos = 2u;
    fake_hal.sonars = 2u;
    fake_hal.bumps = 2u;
    slam_config_t cfg;
    slam_config_default(&cfg);
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    for (uint32_t t = 0; t < 600u; t++) {
        if (fake_hal.calls_trigger > 0u && t % 7u == 0u) {
            fake_hal.sonar_next = HAL_SONAR_ECHO; /* about a metre */
            fake_hal.sonar_echo_us = 5831u;
        }
        robot_tick(&robot);
        robot_idle(&robot);
    }
    assert_true(fake_hal.calls_trigger > 5u);
    assert_true(fake_hal.calls_poll > 5u);
    assert_true(fake_hal.calls_servo > 5u);
    assert_int_equal(fake_hal.calls_other_instance, 0u);
    assert_int_equal(fake_hal.calls_bad_instance, 0u);
    assert_true(fake_hal.calls_bump > 0u); /* the robot reads its switches as it explores */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_one_of_each_and_no_switches_by_default, reset),
        cmocka_unit_test_setup(test_more_instances_when_scripted, reset),
        cmocka_unit_test_setup(test_robot_uses_instance_0_alone, reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
