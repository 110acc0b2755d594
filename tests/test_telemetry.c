/* SPDX-License-Identifier: MIT */
/* Tests of telemetry: frames and CRC, the event ring, a decoder that resynchronises, and
 * the maps rebuilt from MAP_ROW frames. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "fake_hal.h"
#include "slam/error.h"
#include "slam/robot.h"
#include "slam/telemetry.h"

/* ---- a decoder, written from the protocol description in telemetry.h ------------------ */

typedef struct {
    uint8_t type;
    uint8_t len;
    uint8_t payload[255];
} frame_t;

/* Finds the next good frame at or after *pos; false at the end of the bytes. */
static bool next_frame(const uint8_t *buf, size_t n, size_t *pos, frame_t *f, unsigned *bad)
{
    while (*pos + 6u <= n) {
        size_t p = *pos;
        if (buf[p] != 0xA5u || buf[p + 1u] != 0x5Au) {
            (*pos)++;
            continue;
        }
        uint8_t len = buf[p + 3u];
        if (p + 6u + len > n) {
            (*pos)++;
            continue;
        }
        uint16_t crc = (uint16_t)(buf[p + 4u + len] | (buf[p + 5u + len] << 8));
        if (crc != telem_crc16(buf + p + 2u, (size_t)len + 2u)) {
            (*bad)++;
            (*pos)++;
            continue;
        }
        f->type = buf[p + 2u];
        f->len = len;
        memcpy(f->payload, buf + p + 4u, len);
        *pos = p + 6u + len;
        return true;
    }
    return false;
}

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

static robot_t robot;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    fake_hal_reset();
    slam_config_default(&cfg);
    cfg.explore_mode = EXPLORE_OFF;
    cfg.save_period_s = 0u;
    return 0;
}

static void test_crc16_and_frame_layout(void **state)
{
    (void)state;
    assert_int_equal(telem_crc16((const uint8_t *)"123456789", 9u), 0x29B1u);
    uint8_t buf[TELEM_FRAME_MAX];
    const uint8_t pl[3] = {1, 2, 3};
    size_t n = telem_frame(buf, 7u, pl, 3u);
    assert_int_equal(n, 9u);
    static const uint8_t head[7] = {0xA5, 0x5A, 7, 3, 1, 2, 3};
    assert_memory_equal(buf, head, 7u);
    uint16_t crc = telem_crc16(buf + 2, 5u);
    assert_int_equal(buf[7], crc & 0xFFu);
    assert_int_equal(buf[8], crc >> 8);
}

static void test_ring_drops_when_full_and_counts(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    odom_pose_t p = {1, 2, 3u};
    for (uint32_t i = 0; i < TELEM_RING + 4u; i++) {
        telem_post_pose(&t, i, &p);
    }
    assert_int_equal(t.dropped, 5u); /* one slot stays empty to tell full from empty */
    static grid_t g;
    telem_status_t st = {0};
    telem_idle(&t, &g, &st, 0u);
    /* The kept events went out in order: ticks 0..14. */
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    uint32_t want = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        if (f.type == TELEM_POSE) {
            assert_int_equal(get32(f.payload), want++);
        }
    }
    assert_int_equal(want, TELEM_RING - 1u);
    assert_int_equal(bad, 0u);
}

/* A robot run: every reading and pose comes out once, and the maps can be rebuilt. */
static void test_robot_stream_decodes(void **state)
{
    (void)state;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    static uint8_t om[SLAM_GRID_CELLS];
    static uint8_t tm[SLAM_GRID_CELLS];
    unsigned readings = 0;
    for (uint32_t t = 0; t < 4000; t++) {
        fake_hal.encoder[0] = (uint16_t)(fake_hal.encoder[0] + 1u);
        fake_hal.encoder[1] = (uint16_t)(fake_hal.encoder[1] + 1u);
        if (robot.sweep.phase == SWEEP_WAIT) {
            fake_hal.sonar_next = HAL_SONAR_ECHO;
            fake_hal.sonar_echo_us = 3000u + 100u * robot.sweep.seq; /* about 0.5 m */
        }
        robot_tick(&robot);
        readings += robot.last.reading_ready;
        robot_idle(&robot);
    }
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    unsigned counts[6] = {0};
    uint32_t last_pose_tick = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        assert_true(f.type >= TELEM_HELLO && f.type <= TELEM_STATUS);
        counts[f.type]++;
        switch (f.type) {
        case TELEM_HELLO:
            assert_int_equal(f.len, 19u);
            assert_int_equal(get16(f.payload + 1), SLAM_GRID_A);
            assert_int_equal(get32(f.payload + 5), cfg.cell_um);
            break;
        case TELEM_POSE:
            assert_int_equal(f.len, 16u);
            last_pose_tick = get32(f.payload);
            break;
        case TELEM_READING:
            assert_int_equal(f.len, 26u);
            assert_true(f.payload[4] < 6u);                    /* stop */
            assert_int_equal(f.payload[5], MAPPER_HIT);        /* all within rc */
            assert_true(get32(f.payload + 10) > 400000u);      /* range about 0.5 m */
            break;
        case TELEM_MAP_ROW: {
            uint16_t row = get16(f.payload + 1);
            uint16_t first = get16(f.payload + 3);
            uint8_t n = (uint8_t)(f.len - 5u);
            assert_true(row < SLAM_GRID_B && first + n <= SLAM_GRID_A);
            memcpy((f.payload[0] == 0u ? om : tm) + (uint32_t)row * SLAM_GRID_A + first, f.payload + 5, n);
            break;
        }
        default:
            assert_int_equal(f.len, 32u);
            break;
        }
    }
    assert_int_equal(bad, 0u);
    assert_int_equal(counts[TELEM_READING], readings);
    assert_int_equal(counts[TELEM_POSE], 400u);
    assert_int_equal(last_pose_tick, 3990u);
    assert_int_equal(counts[TELEM_STATUS], 40u);
    assert_int_equal(counts[TELEM_HELLO], 8u);
    assert_true(counts[TELEM_MAP_ROW] >= 2u * SLAM_GRID_B); /* every row of both maps */
    /* Rows sent before the last changes are stale, so compare a map at rest: stop
     * mapping and let the rows go round once more. */
    for (uint32_t t = 0; t < TELEM_ROW_TICKS * 2u * SLAM_GRID_B; t++) {
        robot.ticks++;
        robot_idle(&robot);
    }
    pos = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        if (f.type == TELEM_MAP_ROW) {
            uint16_t row = get16(f.payload + 1);
            uint16_t first = get16(f.payload + 3);
            memcpy((f.payload[0] == 0u ? om : tm) + (uint32_t)row * SLAM_GRID_A + first,
                   f.payload + 5, (size_t)f.len - 5u);
        }
    }
    assert_memory_equal(om, robot.grid.om, SLAM_GRID_CELLS);
    assert_memory_equal(tm, robot.grid.tm, SLAM_GRID_CELLS);
}

/* A UART that takes only part of a frame: counted; the receiver drops the torn frame and
 * finds the next good one. */
static void test_short_writes_are_counted_and_resynchronised(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    static grid_t g;
    telem_status_t st = {0};
    odom_pose_t p = {10, 20, 30u};
    telem_post_pose(&t, 1u, &p);
    fake_hal.uart_room = 7u; /* the first frames get cut */
    telem_idle(&t, &g, &st, 1u);
    assert_true(t.short_writes >= 1u);
    fake_hal.uart_room = 0u;
    telem_post_pose(&t, 2u, &p);
    telem_idle(&t, &g, &st, 2u);
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    bool found = false;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        if (f.type == TELEM_POSE) {
            assert_int_equal(get32(f.payload), 2u); /* the torn one is gone */
            assert_int_equal(get32(f.payload + 4), 10u);
            found = true;
        }
    }
    assert_true(found);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_crc16_and_frame_layout, setup),
        cmocka_unit_test_setup(test_ring_drops_when_full_and_counts, setup),
        cmocka_unit_test_setup(test_robot_stream_decodes, setup),
        cmocka_unit_test_setup(test_short_writes_are_counted_and_resynchronised, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
