/* SPDX-License-Identifier: MIT */
/* The template port as a port starts from it: it links the core, with hal/defaults for the
 * optional calls it leaves out, and the core runs on a HAL that has nothing yet. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "hal/hal.h"
#include "slam/error.h"
#include "slam/robot.h"

static robot_t robot;

static void tick(void *ctx)
{
    robot_tick(ctx);
}

static void test_defaults_answer_as_hal_h_says(void **state)
{
    (void)state;
    uint8_t buf[4] = {1u, 2u, 3u, 4u};
    assert_int_equal(hal_storage_size(), 0u);
    for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
        assert_int_equal(hal_storage_begin(slot), HAL_ENOSYS);
        assert_int_equal(hal_storage_write(slot, 0u, buf, sizeof buf), HAL_ENOSYS);
        assert_int_equal(hal_storage_commit(slot), HAL_ENOSYS);
        assert_int_equal(hal_storage_read(slot, 0u, buf, sizeof buf), HAL_ENOSYS);
    }
    assert_int_equal(hal_uart_read(buf, sizeof buf), 0u);
    assert_int_equal(buf[0], 1u); /* nothing received, nothing written */
}

static void test_instances_beyond_the_board_are_refused(void **state)
{
    (void)state;
    uint32_t echo = 7u;
    bool pressed = true;
    assert_int_equal(hal_servo_count(), 1u);
    assert_int_equal(hal_sonar_count(), 1u);
    assert_int_equal(hal_servo_set_pulse(HAL_SERVO_SWEEP, 1500u), HAL_OK);
    assert_int_equal(hal_servo_set_pulse(1u, 1500u), HAL_EINVAL);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_ENOSYS);
    assert_int_equal(hal_sonar_trigger(1u), HAL_EINVAL);
    assert_int_equal(hal_sonar_poll(HAL_SONAR_SWEPT, &echo), HAL_SONAR_IDLE);
    assert_int_equal(hal_sonar_poll(1u, &echo), HAL_EINVAL);
    assert_int_equal(echo, 7u);
    /* No bump switches: hal/defaults answers for the template. */
    assert_int_equal(hal_bump_count(), 0u);
    assert_int_equal(hal_bump_read(0u, &pressed), HAL_ENOSYS);
    assert_true(pressed);
}

static void test_core_runs_on_the_template(void **state)
{
    (void)state;
    slam_config_t cfg;
    slam_config_default(&cfg);
    assert_int_equal(hal_init(), HAL_OK);
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    /* The template cannot start a tick yet; the program ticks itself, as a port's first
     * bring-up might, and the core must take a HAL that answers HAL_ENOSYS throughout. */
    assert_int_equal(hal_tick_start(tick, &robot), HAL_ENOSYS);
    for (uint32_t t = 0; t < 1000u; t++) {
        robot_tick(&robot);
        robot_idle(&robot);
    }
    assert_int_equal(robot.ticks, 1000u);
    assert_true(robot.ping_errors > 0u); /* every refused trigger is counted */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_answer_as_hal_h_says),
        cmocka_unit_test(test_instances_beyond_the_board_are_refused),
        cmocka_unit_test(test_core_runs_on_the_template),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
