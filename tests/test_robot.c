/* SPDX-License-Identifier: MIT */
/* Tests of the robot wiring through a fake HAL: init, one tick's HAL traffic, mapping. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "fake_hal.h"
#include "slam/error.h"
#include "slam/robot.h"

static robot_t robot;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    fake_hal_reset();
    test_config_default(&cfg);
    slam_config_paper(&cfg); /* these tests hold the paper's Eq. 6 */
    memset(&robot, 0, sizeof robot);
    return 0;
}

static void test_bad_config_changes_nothing(void **state)
{
    (void)state;
    memset(&robot, 0x5A, sizeof robot);
    robot_t before = robot;
    cfg.wheel_base_um = 0u;
    fake_hal.motor[0] = 123;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_EINVAL);
    assert_memory_equal(&robot, &before, sizeof robot);
    assert_int_equal(fake_hal.calls_motor, 0u); /* hardware untouched too */
    assert_int_equal(fake_hal.calls_encoder, 0u);
    assert_int_equal(fake_hal.motor[0], 123);
}

static void test_init_stops_motors_and_takes_encoder_reference(void **state)
{
    (void)state;
    fake_hal.motor[0] = 500;
    fake_hal.motor[1] = -500;
    fake_hal.encoder[0] = 65000u;
    fake_hal.encoder[1] = 7u;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    assert_int_equal(fake_hal.motor[0], 0);
    assert_int_equal(fake_hal.motor[1], 0);
    /* No motion since init: the first tick leaves the pose at the start. */
    robot_tick(&robot);
    assert_int_equal(robot.pose.x_um, 0);
    assert_int_equal(robot.pose.y_um, 0);
    assert_int_equal(robot.pose.heading, 0u);
}

/* A straight drive past a wall: the robot's HAL traffic follows the sweep, and with the
 * echo of a wall 0.5 m ahead of the sonar axis, OM fills exactly where the wall is. */
static void test_ticks_drive_sweep_and_map(void **state)
{
    (void)state;
    cfg.sweep_stops = 1u; /* one stop straight ahead keeps the geometry easy */
    cfg.sweep_first_mdeg = cfg.sweep_last_mdeg = 90000;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);

    static uint32_t ticks_in[SLAM_GRID_CELLS];
    memset(ticks_in, 0, sizeof ticks_in);
    unsigned pings = 0;
    for (uint32_t t = 0; t < 1000; t++) {
        /* Forward at 4 counts a tick on both wheels: 1.17 mm a tick, 1.17 m in 10 s. */
        fake_hal.encoder[0] = (uint16_t)(fake_hal.encoder[0] + 4u);
        fake_hal.encoder[1] = (uint16_t)(fake_hal.encoder[1] + 4u);
        unsigned triggers = fake_hal.calls_trigger;
        unsigned polls = fake_hal.calls_poll;
        robot_tick(&robot);
        grid_cell_t here;
        assert_int_equal(grid_cell_of(&robot.grid, robot.pose.x_um, robot.pose.y_um, &here),
                         SLAM_OK);
        ticks_in[grid_index(&robot.grid, here)]++;
        if (fake_hal.calls_trigger != triggers) {
            pings++;
            /* The sensor answers on the next poll: a wall 0.5 m ahead of the sonar, which
             * is 2 m ahead of the start. */
            uint32_t ahead_um = 2000000u - (uint32_t)robot.pose.x_um - 50000u;
            fake_hal.sonar_next = HAL_SONAR_ECHO;
            fake_hal.sonar_echo_us = (uint32_t)((ahead_um * 2ull * 1000u) / 343000u);
        }
        /* Polls happen only while a ping is out. */
        if (fake_hal.calls_poll != polls) {
            assert_true(robot.sweep.phase == SWEEP_WAIT || robot.last.reading_ready);
        }
    }
    assert_int_equal(robot.ticks, 1000u);
    assert_int_equal(pings, robot.sweep.pings);
    assert_true(pings >= 1000u / 6u); /* one every 60 ms */
    assert_int_equal(fake_hal.calls_servo, robot.sweep.echoes + 1u);
    assert_int_equal(fake_hal.servo_pulse_us, 1500u); /* 90° */
    assert_int_equal(robot.ping_errors, 0u);

    /* TM: one count a tick at the robot's cell, up to TMmax (43 ticks a cell at this
     * speed); OM: only readings within rc, all in the wall's cell. */
    uint32_t om_sum = 0;
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(robot.grid.tm[i], ticks_in[i] > 30u ? 30u : ticks_in[i]);
        om_sum += robot.grid.om[i];
        if (robot.grid.om[i] != 0u) {
            /* x = 2 m is the lower edge of cell 80 + 40.5 -> a = 120 (or just before it,
             * rounding the echo width down). */
            uint32_t a = i % SLAM_GRID_A;
            assert_true(a == 120u || a == 119u);
            assert_int_equal(i / SLAM_GRID_A, SLAM_GRID_B / 2u);
        }
    }
    assert_true(robot.mapper.hits > 0u);
    assert_int_equal(robot.mapper.hits + robot.mapper.far, robot.sweep.echoes);
    assert_true(om_sum <= 9u * 2u);
}

static void test_refused_ping_is_counted_and_sweep_goes_on(void **state)
{
    (void)state;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    fake_hal.trigger_result = HAL_EBUSY;
    for (int t = 0; t < 100; t++) {
        robot_tick(&robot);
    }
    assert_true(robot.ping_errors > 5u);
    assert_int_equal(robot.ping_errors, robot.sweep.pings);
    assert_true(robot.sweep.timeouts >= robot.ping_errors - 1u);
    assert_true(fake_hal.calls_servo > 5u);
}

static void test_idle_feeds_watchdog_only_while_ticking(void **state)
{
    (void)state;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    robot_idle(&robot);
    robot_idle(&robot);
    assert_int_equal(fake_hal.calls_watchdog, 0u); /* no tick yet */
    robot_tick(&robot);
    robot_idle(&robot);
    robot_idle(&robot);
    assert_int_equal(fake_hal.calls_watchdog, 1u);
    robot_tick(&robot);
    robot_idle(&robot);
    assert_int_equal(fake_hal.calls_watchdog, 2u);
}

/* `held` promises that the robot stands and stays standing while the hold lasts: a save
 * erases flash next, which stalls an MCU, ticks and all, for up to two seconds. Wheels with
 * inertia keep turning after the duty drops, so on the way down the PI part can cancel the
 * feed-forward exactly for a tick while the ramp still asks for speed: that zero duty is
 * not a stand. 3 200 holds at random moments of a drive, each followed for 50 held ticks. */
static void test_held_means_the_ramp_is_at_rest(void **state)
{
    (void)state;
    uint32_t rng = 12345u;
    cfg.explore_mode = EXPLORE_SQUARE; /* drives from the first tick */
    cfg.save_period_s = 0u;
    for (int hold = 0; hold < 3200; hold++) {
        fake_hal_reset();
        assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
        int32_t speed[2] = {0, 0}; /* wheel speeds, counts per 16 ticks */
        rng = rng * 1103515245u + 12345u;
        uint32_t hold_at = 20u + (rng >> 16) % 300u;
        int held_ticks = 0;
        for (uint32_t t = 0; t < hold_at + 400u && held_ticks < 50; t++) {
            for (unsigned w = 0; w < 2u; w++) {
                /* First-order lag toward duty/100 counts a tick, with noise. */
                rng = rng * 1103515245u + 12345u;
                speed[w] +=
                    (fake_hal.motor[w] * 16 / 100 - speed[w]) / 8 + (int32_t)((rng >> 16) % 5u) - 2;
                fake_hal.encoder[w] = (uint16_t)(fake_hal.encoder[w] + (uint16_t)(speed[w] / 16));
            }
            robot.hold = t >= hold_at;
            bool was_held = robot.held;
            robot_tick(&robot);
            if (was_held) {
                held_ticks++;
                if (fake_hal.motor[0] != 0 || fake_hal.motor[1] != 0 || !robot.held) {
                    fail_msg("hold %d: held at tick %u, then duty %d/%d and held %d", hold,
                             (unsigned)t - 1u, fake_hal.motor[0], fake_hal.motor[1], robot.held);
                }
            }
        }
        assert_int_equal(held_ticks, 50);
    }
}

/* Wheels that follow their duty (a first-order lag toward duty/100 counts a tick), and a
 * sonar that hears a wall 3 m off at every stop (beyond the confidence radius). */
static void world_tick(int32_t speed[2])
{
    for (unsigned w = 0; w < 2u; w++) {
        speed[w] += (fake_hal.motor[w] * 16 / 100 - speed[w]) / 8;
        fake_hal.encoder[w] = (uint16_t)(fake_hal.encoder[w] + (uint16_t)(speed[w] / 16));
    }
    fake_hal.sonar_next = HAL_SONAR_ECHO;
    fake_hal.sonar_echo_us = 17500u;
    robot_tick(&robot);
}

/* A bump switch closing stops the drive as stalled wheels do, a few ticks sooner; a
 * contact counts once however long the switch stays closed; a board without switches is
 * never asked. */
static void test_a_bump_switch_stops_the_drive(void **state)
{
    (void)state;
    test_config_default(&cfg);
    cfg.explore_mode = EXPLORE_RANDOM;
    for (uint8_t bumps = 0; bumps <= 2u; bumps += 2u) {
        fake_hal_reset();
        fake_hal.bumps = bumps;
        assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
        int32_t speed[2] = {0, 0};
        for (int t = 0; t < 3000 && robot.explore.machine.state != EXPLORE_FORWARD; t++) {
            world_tick(speed);
        }
        for (int t = 0; t < 50; t++) {
            world_tick(speed);
        }
        assert_int_equal(robot.explore.machine.state, EXPLORE_FORWARD);
        assert_true(fake_hal.motor[0] > 0 && fake_hal.motor[1] > 0);
        fake_hal.bump_pressed[1] = true;
        for (int t = 0; t < 2; t++) { /* the next tick, or the one after a reading's */
            world_tick(speed);
        }
        if (bumps == 0u) {
            assert_int_equal(fake_hal.calls_bump, 0u);
            assert_int_equal(robot.explore.machine.state, EXPLORE_FORWARD);
            continue;
        }
        assert_int_equal(robot.explore.machine.state, EXPLORE_HOLD);
        for (int t = 0; t < 100; t++) { /* standing, the switch still closed */
            world_tick(speed);
        }
        assert_int_equal(robot.bumped, 1u);
        assert_int_equal(robot.explore.count.stalls, 1u);
        assert_int_equal(fake_hal.motor[0], 0);
        assert_int_equal(fake_hal.motor[1], 0);
    }
}

/* The second sonar, asked for (sonar1_map) with the board fitted: robot_idle() pings it,
 * never the tick, only while the sweep's sonar waits for no echo and 60 ms after its own
 * last ping; each echo is mapped where a wall 0.6 m to the left of the servo's axis
 * stands (its beam at servo angle 0, the robot standing at the origin facing +x), and a
 * ping that gets no answer is given up after the sweep's echo timeout. */
static void test_second_sonar_is_pinged_from_idle_and_mapped(void **state)
{
    (void)state;
    test_config_default(&cfg);
    cfg.explore_mode = EXPLORE_OFF;
    cfg.localize = 0u; /* the evidence map alone: the reading mapped where odometry says */
    cfg.om_mode = OM_MODE_EVIDENCE;
    cfg.sonar1_map = 1u;
    cfg.sonar1_mdeg = 0;
    fake_hal.sonars = 2u;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    assert_true(robot.sonar1.on);
    /* A wall 0.6 m left of the sonar: the echo of 1.2 m of sound at 343 m/s. */
    const uint32_t echo_us = (uint32_t)(1.2 / 343.0 * 1e6 + 0.5);
    uint32_t last_ping_us = 0u;
    unsigned pings = 0u;
    for (uint32_t t = 0; t < 600u; t++) {
        fake_hal.time_us += SLAM_TICK_US;
        unsigned calls = fake_hal.calls_trigger1 + fake_hal.calls_poll1;
        robot_tick(&robot);
        assert_int_equal(fake_hal.calls_trigger1 + fake_hal.calls_poll1, calls); /* never */
        bool sweep_listens = sweep_waiting(&robot.sweep);
        unsigned triggers = fake_hal.calls_trigger1;
        robot_idle(&robot);
        if (fake_hal.calls_trigger1 != triggers) {
            assert_false(sweep_listens);
            assert_true(pings == 0u || fake_hal.time_us - last_ping_us >= 60000u);
            last_ping_us = fake_hal.time_us;
            pings++;
            /* The first 300 ticks' pings are answered at the next call, the rest never. */
            fake_hal.sonar1_next = t < 300u ? HAL_SONAR_ECHO : HAL_SONAR_BUSY;
            fake_hal.sonar1_echo_us = echo_us;
        }
    }
    assert_true(pings > 50u);
    assert_int_equal(fake_hal.calls_bad_instance, 0u);
    /* Every ping but perhaps the last is a reading: the answered ones echoes, the others
     * given up. */
    assert_true(robot.sonar1.readings + 1u >= pings && robot.sonar1.readings <= pings);
    assert_true(robot.sonar1.echoes > 20u && robot.sonar1.echoes < robot.sonar1.readings);
    /* Mapped at (0.05, 0.6) m: the servo's axis 50 mm ahead of the axle, the wall beyond. */
    grid_cell_t wall;
    grid_cell_t near;
    assert_int_equal(grid_cell_of(&robot.grid, 50000, 600000, &wall), SLAM_OK);
    assert_int_equal(grid_cell_of(&robot.grid, 50000, 300000, &near), SLAM_OK);
    assert_int_equal(grid_state(&robot.grid, grid_index(&robot.grid, wall)), GRID_OCCUPIED);
    assert_int_equal(grid_state(&robot.grid, grid_index(&robot.grid, near)), GRID_FREE);
    assert_true(robot.mapper.hits >= robot.sonar1.echoes);
}

/* It stays off where it cannot be: a board without it, and the tick mapping OM itself
 * (the paper's map without the pose correction), which the background loop must not
 * write at the same time. */
static void test_second_sonar_off_where_it_cannot_be(void **state)
{
    (void)state;
    for (int k = 0; k < 2; k++) {
        fake_hal_reset();
        test_config_default(&cfg);
        cfg.sonar1_map = 1u;
        fake_hal.sonars = k == 0 ? 1u : 2u;
        if (k == 1) {
            slam_config_paper(&cfg);
            cfg.sonar1_map = 1u;
        }
        assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
        assert_false(robot.sonar1.on);
        for (uint32_t t = 0; t < 100u; t++) {
            fake_hal.time_us += SLAM_TICK_US;
            robot_tick(&robot);
            robot_idle(&robot);
        }
        assert_int_equal(fake_hal.calls_trigger1 + fake_hal.calls_bad_instance, 0u);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_bad_config_changes_nothing, setup),
        cmocka_unit_test_setup(test_init_stops_motors_and_takes_encoder_reference, setup),
        cmocka_unit_test_setup(test_ticks_drive_sweep_and_map, setup),
        cmocka_unit_test_setup(test_refused_ping_is_counted_and_sweep_goes_on, setup),
        cmocka_unit_test_setup(test_idle_feeds_watchdog_only_while_ticking, setup),
        cmocka_unit_test_setup(test_held_means_the_ramp_is_at_rest, setup),
        cmocka_unit_test_setup(test_a_bump_switch_stops_the_drive, setup),
        cmocka_unit_test_setup(test_second_sonar_is_pinged_from_idle_and_mapped, setup),
        cmocka_unit_test_setup(test_second_sonar_off_where_it_cannot_be, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
