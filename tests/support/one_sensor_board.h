/* SPDX-License-Identifier: MIT */
/* What every backend of a board with one servo, one sonar and no bump switch answers for
 * the instances it lacks: a refusal that touches nothing (include after <cmocka.h>). */
#ifndef SLAM_TEST_ONE_SENSOR_BOARD_H
#define SLAM_TEST_ONE_SENSOR_BOARD_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal.h"

static inline void assert_one_sensor_board(void)
{
    uint32_t echo = 7u;
    bool pressed = true;
    assert_int_equal(hal_servo_count(), 1u);
    assert_int_equal(hal_sonar_count(), 1u);
    assert_int_equal(hal_bump_count(), 0u);
    assert_int_equal(hal_servo_set_pulse(1u, 1500u), HAL_EINVAL);
    assert_int_equal(hal_sonar_trigger(1u), HAL_EINVAL);
    assert_int_equal(hal_sonar_poll(1u, &echo), HAL_EINVAL);
    assert_int_equal(hal_sonar_poll(255u, &echo), HAL_EINVAL);
    assert_int_equal(echo, 7u);
    assert_int_equal(hal_bump_read(0u, &pressed), HAL_ENOSYS);
    assert_true(pressed);
}

#endif
