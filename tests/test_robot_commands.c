/* SPDX-License-Identifier: MIT */
/* Tests of the commands robot_idle() takes from the UART: each is answered, does what it
 * says once the robot stands, and a malformed or refused one changes nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "fake_hal.h"
#include "slam/error.h"
#include "slam/robot.h"
#include "slam/telemetry.h"
#include "test_frames.h"

static robot_t robot;
static slam_config_t cfg;
static size_t seen; /* UART bytes already looked at by replies() */

static int setup(void **state)
{
    (void)state;
    fake_hal_reset();
    test_config_default(&cfg);
    cfg.save_period_s = 0u;
    memset(&robot, 0, sizeof robot);
    seen = 0u;
    return 0;
}

/* Ticks of a robot on a floor without walls: the wheels turn as the motors drive them
 * (about 1 count a tick per 50 ‰ of duty), the sonar never hears an echo. */
static void run(unsigned ticks)
{
    for (unsigned i = 0; i < ticks; i++) {
        fake_hal.encoder[0] = (uint16_t)(fake_hal.encoder[0] + fake_hal.motor[0] / 50);
        fake_hal.encoder[1] = (uint16_t)(fake_hal.encoder[1] + fake_hal.motor[1] / 50);
        if (robot.sweep.phase == SWEEP_WAIT) {
            fake_hal.sonar_next = HAL_SONAR_TIMEOUT;
        }
        robot_tick(&robot);
        robot_idle(&robot);
    }
}

static void send(uint8_t type, const uint8_t *payload, uint8_t len)
{
    uint8_t buf[TELEM_FRAME_MAX];
    fake_hal_receive(buf, telem_frame(buf, type, payload, len));
}

static void send_set(uint8_t key, uint32_t value)
{
    const uint8_t p[5] = {key, (uint8_t)value, (uint8_t)(value >> 8), (uint8_t)(value >> 16),
                          (uint8_t)(value >> 24)};
    send(TELEM_CMD_SET, p, 5u);
}

typedef struct {
    unsigned acks, errors, configs;
    uint8_t cmd, code, key; /* of the last ACK or ERROR */
    uint32_t value;         /* of the last CONFIG */
} replies_t;

/* The replies written since the last call. */
static replies_t replies(void)
{
    replies_t r = {0};
    size_t pos = seen;
    frame_t f;
    unsigned bad = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        if (f.type == TELEM_ACK) {
            r.acks++;
            r.cmd = f.payload[0];
        } else if (f.type == TELEM_ERROR) {
            r.errors++;
            r.cmd = f.payload[0];
            r.code = f.payload[1];
            r.key = f.payload[2];
        } else if (f.type == TELEM_CONFIG) {
            r.configs++;
            r.key = f.payload[0];
            r.value = get32(f.payload + 1);
        }
    }
    seen = fake_hal.uart_len;
    return r;
}

static bool standing(void)
{
    return fake_hal.motor[0] == 0 && fake_hal.motor[1] == 0;
}

static void test_stop_and_start(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_SQUARE;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    run(100);
    assert_false(standing());
    send(TELEM_CMD_STOP, NULL, 0u);
    run(100);
    replies_t r = replies();
    assert_int_equal(r.acks, 1u);
    assert_int_equal(r.cmd, TELEM_CMD_STOP);
    assert_true(standing());
    assert_true(robot.hold & ROBOT_HOLD_STOP);
    odom_pose_t at = robot.pose;
    uint32_t pings = robot.sweep.pings;
    run(300);
    assert_true(standing());
    assert_int_equal(robot.pose.x_um, at.x_um);   /* it stays where it stopped */
    assert_true(robot.sweep.pings > pings + 10u); /* while the sweep goes on */
    send(TELEM_CMD_START, NULL, 0u);
    run(100);
    assert_int_equal(replies().acks, 1u);
    assert_false(standing());
    assert_true(robot.pose.x_um > at.x_um);
}

static void test_set_applies_once_the_robot_stands(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_SQUARE;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    run(200);
    odom_pose_t before = robot.pose;
    assert_true(before.x_um > 50000);
    send_set(40u, 120u); /* cruise_mm_s */
    run(1);
    replies_t r = replies();
    assert_int_equal(r.configs, 1u);
    assert_int_equal(r.key, 40u);
    assert_int_equal(r.value, 120u);
    assert_int_equal(robot.cfg.cruise_mm_s, 120u);
    assert_int_equal(robot.explore.cfg.cruise_mm_s, 200); /* not yet: the robot is moving */
    assert_true(robot.hold & ROBOT_HOLD_COMMAND);
    run(200);
    assert_int_equal(robot.hold, 0u);
    assert_int_equal(robot.explore.cfg.cruise_mm_s, 120);
    /* The pose was kept; the square begins again where the robot stood. */
    assert_true(robot.pose.x_um >= before.x_um);
    run(300);
    assert_true(robot.pose.x_um > before.x_um + 50000);
    /* The odometry takes new gains without losing the pose. */
    odom_pose_t p = robot.pose;
    send(TELEM_CMD_STOP, NULL, 0u);
    run(200);
    p = robot.pose;
    send_set(3u, 140000u); /* wheel_base_um */
    run(50);
    assert_int_equal(replies().configs, 1u);
    assert_int_equal(robot.pose.x_um, p.x_um);
    assert_int_equal(robot.pose.y_um, p.y_um);
    assert_int_equal(robot.pose.heading, p.heading);
    assert_int_equal(robot.cfg.wheel_base_um, 140000u);
    /* GET reads it back. */
    const uint8_t key = 3u;
    send(TELEM_CMD_GET, &key, 1u);
    run(1);
    r = replies();
    assert_int_equal(r.configs, 1u);
    assert_int_equal(r.value, 140000u);
}

static void test_mode_and_calibration_run(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_OFF;
    cfg.umbmark_pause_s = 1u;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    run(50);
    assert_true(standing());
    const uint8_t random = EXPLORE_RANDOM;
    send(TELEM_CMD_MODE, &random, 1u);
    run(400);
    assert_int_equal(replies().acks, 1u);
    assert_int_equal(robot.explore.cfg.mode, EXPLORE_RANDOM);
    assert_int_equal(robot.cfg.explore_mode, EXPLORE_RANDOM);
    assert_true(robot.pose.x_um > 10000 || robot.pose.heading != 0u);

    /* The calibration run: UMBmark, the pose correction off, odometry put back at the
     * start pose as the first run begins, after the pause (1 s here). */
    assert_true(robot.loc.on);
    send(TELEM_CMD_STOP, NULL, 0u);
    send(TELEM_CMD_CALIBRATE, NULL, 0u); /* also drives again */
    run(60);
    replies_t r = replies();
    assert_int_equal(r.acks, 2u);
    assert_int_equal(r.cmd, TELEM_CMD_CALIBRATE);
    assert_int_equal(robot.cfg.explore_mode, ROBOT_CALIBRATION_MODE);
    assert_int_equal(ROBOT_CALIBRATION_MODE, EXPLORE_UMBMARK);
    assert_true(robot.umbmark.on);
    assert_false(robot.loc.on);
    assert_int_equal(robot.hold & ROBOT_HOLD_STOP, 0u);
    assert_true(standing());
    assert_int_equal(robot.umbmark.run, 0u);
    run(100);
    assert_int_equal(robot.umbmark.run, 1u);
    assert_int_equal(robot.umbmark.state, UMB_LEG);
    assert_false(standing());
    assert_true(robot.pose.x_um > 0 && robot.pose.x_um < 100000);
    assert_true(robot.pose.y_um > -2000 && robot.pose.y_um < 2000);

    /* Back to exploring: the correction is on again, from scratch. */
    const uint8_t tm = EXPLORE_TM;
    send(TELEM_CMD_MODE, &tm, 1u);
    run(200);
    assert_false(robot.umbmark.on);
    assert_true(robot.loc.on);
    assert_int_equal(robot.explore.cfg.mode, EXPLORE_TM);
}

static void test_send_map_restarts_the_rows(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_OFF;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    run(400); /* the rows are somewhere in the middle of OM */
    assert_true(robot.telem.row > 10u);
    (void)replies();
    send(TELEM_CMD_SEND_MAP, NULL, 0u);
    run(2u * TELEM_ROW_TICKS);
    size_t pos = seen;
    frame_t f;
    unsigned bad = 0;
    bool hello = false;
    bool row0 = false;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        hello |= f.type == TELEM_HELLO;
        if (f.type == TELEM_MAP_ROW && !row0) {
            assert_true(hello); /* the geometry first */
            assert_int_equal(f.payload[0], 0u);
            assert_int_equal(get16(f.payload + 1), 0u);
            assert_int_equal(get16(f.payload + 3), 0u);
            row0 = true;
        }
    }
    assert_true(row0);
    assert_int_equal(replies().acks, 1u);
}

static void test_save_on_command(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_OFF;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    /* Five hits the pose correction holds back: the save asked for puts them in OM first. */
    for (int i = 0; i < 5; i++) {
        readq_reading_t rd = {
            .ping = {i * 100000, 0, 0u}, .range_um = 700000u, .servo = 0u, .echo = true};
        assert_true(readq_post(&robot.readq, &rd) != READQ_DROPPED);
    }
    robot_idle(&robot); /* which drains the queue */
    assert_int_equal(robot.loc.hold.count, 5u);
    assert_int_equal(robot.mapper.hits, 0u);
    send(TELEM_CMD_SAVE, NULL, 0u);
    run(400);
    assert_int_equal(replies().acks, 1u);
    assert_int_equal(robot.store.saves, 1u);
    assert_true(robot.mapper.hits >= 5u);

    /* A robot without storage says so. */
    fake_hal_reset();
    fake_hal.storage_size = 0u;
    seen = 0u;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    send(TELEM_CMD_SAVE, NULL, 0u);
    run(10);
    replies_t r = replies();
    assert_int_equal(r.errors, 1u);
    assert_int_equal(r.code, TELEM_ERR_UNSUPPORTED);
    assert_int_equal(robot.store.saves, 0u);
}

/* Every malformed or refused command gets one ERROR and leaves the robot as it was. */
static void test_refused_commands_change_nothing(void **state)
{
    (void)state;
    cfg.explore_mode = EXPLORE_RANDOM;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    run(100);
    uint8_t buf[TELEM_FRAME_MAX];
    const uint8_t set_cruise[5] = {40u, 150u, 0u, 0u, 0u};
    static const struct {
        uint8_t code;
        uint8_t key;
    } want[] = {
        {TELEM_ERR_CRC, 0u},     {TELEM_ERR_LENGTH, 0u}, {TELEM_ERR_LENGTH, 0u},
        {TELEM_ERR_COMMAND, 0u}, {TELEM_ERR_KEY, 99u},   {TELEM_ERR_KEY, 0u},
        {TELEM_ERR_RANGE, 40u},  {TELEM_ERR_RANGE, 45u}, {TELEM_ERR_FIXED, 11u},
        {TELEM_ERR_RANGE, 0u},   {TELEM_ERR_LENGTH, 0u},
    };
    for (unsigned i = 0; i < sizeof want / sizeof want[0]; i++) {
        slam_config_t cfg_before = robot.cfg;
        uint8_t hold = robot.hold;
        uint8_t pending = robot.pending;
        size_t n;
        switch (i) {
        case 0: /* SET with a damaged CRC */
            n = telem_frame(buf, TELEM_CMD_SET, set_cruise, 5u);
            buf[n - 2u] ^= 1u;
            fake_hal_receive(buf, n);
            break;
        case 1: /* SET one byte short, with a good CRC */
            fake_hal_receive(buf, telem_frame(buf, TELEM_CMD_SET, set_cruise, 4u));
            break;
        case 2: /* STOP with a payload */
            fake_hal_receive(buf, telem_frame(buf, TELEM_CMD_STOP, set_cruise, 1u));
            break;
        case 3:
            fake_hal_receive(buf, telem_frame(buf, 0x7Fu, NULL, 0u));
            break;
        case 4: {
            const uint8_t key = 99u;
            send(TELEM_CMD_GET, &key, 1u);
            break;
        }
        case 5:
            send_set(0u, 1u);
            break;
        case 6:
            send_set(40u, 400u); /* cruise above top speed */
            break;
        case 7:
            send_set(45u, 300u); /* square_laps is a byte */
            break;
        case 8:
            send_set(11u, 100000u); /* cell_um: only at start */
            break;
        case 9: {
            const uint8_t mode = EXPLORE_MODES;
            send(TELEM_CMD_MODE, &mode, 1u);
            break;
        }
        default: /* a frame that stops half-way */
            n = telem_frame(buf, TELEM_CMD_SET, set_cruise, 5u);
            fake_hal_receive(buf, n - 3u);
            break;
        }
        run(TELEM_RX_TIMEOUT_TICKS + 5u);
        replies_t r = replies();
        assert_int_equal(r.errors, 1u);
        assert_int_equal(r.acks + r.configs, 0u);
        assert_int_equal(r.code, want[i].code);
        assert_int_equal(r.key, want[i].key);
        assert_memory_equal(&robot.cfg, &cfg_before, sizeof cfg_before);
        assert_int_equal(robot.hold, hold);
        assert_int_equal(robot.pending, pending);
    }
    assert_int_equal(robot.telem.refused, sizeof want / sizeof want[0]);
    assert_int_equal(robot.telem.commands, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_stop_and_start, setup),
        cmocka_unit_test_setup(test_set_applies_once_the_robot_stands, setup),
        cmocka_unit_test_setup(test_mode_and_calibration_run, setup),
        cmocka_unit_test_setup(test_send_map_restarts_the_rows, setup),
        cmocka_unit_test_setup(test_save_on_command, setup),
        cmocka_unit_test_setup(test_refused_commands_change_nothing, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
