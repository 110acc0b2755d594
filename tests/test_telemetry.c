/* SPDX-License-Identifier: MIT */
/* Tests of telemetry: frames and CRC, the event ring, a decoder that resynchronises, the
 * maps rebuilt from MAP_ROW frames, the command parser and the configuration keys. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "fake_hal.h"
#include "slam/error.h"
#include "slam/robot.h"
#include "slam/telemetry.h"
#include "telem_decode.h"

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
    telem_idle(&t, &g, &cfg, &st, 0u);
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
            assert_int_equal(f.len, 42u);
            assert_int_equal(f.payload[0], TELEM_VERSION);
            assert_int_equal(get16(f.payload + 1), SLAM_GRID_A);
            assert_int_equal(get32(f.payload + 5), cfg.cell_um);
            assert_int_equal(get32(f.payload + 19), cfg.confidence_radius_um);
            assert_int_equal(get32(f.payload + 23), cfg.range_min_um);
            assert_int_equal(get32(f.payload + 27), (uint32_t)cfg.mount_x_um);
            break;
        case TELEM_POSE:
            assert_int_equal(f.len, 16u);
            last_pose_tick = get32(f.payload);
            break;
        case TELEM_READING:
            assert_int_equal(f.len, 26u);
            assert_true(f.payload[4] < cfg.sweep_stops);  /* stop */
            assert_int_equal(f.payload[5], MAPPER_HIT);   /* all within rc */
            assert_true(get32(f.payload + 10) > 400000u); /* range about 0.5 m */
            break;
        case TELEM_MAP_ROW: {
            uint16_t row = get16(f.payload + 1);
            uint16_t first = get16(f.payload + 3);
            uint8_t n = (uint8_t)(f.len - 5u);
            assert_true(row < SLAM_GRID_B && first + n <= SLAM_GRID_A);
            memcpy((f.payload[0] == 0u ? om : tm) + (uint32_t)row * SLAM_GRID_A + first,
                   f.payload + 5, n);
            break;
        }
        default:
            assert_int_equal(f.len, 42u);
            assert_int_equal(f.payload[40], EXPLORE_OFF);
            assert_int_equal(f.payload[41], 0u); /* neither stopped nor waiting */
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

/* A robot driven for a while, echoes at every stop: its telemetry's state after. */
static void drive_robot(uint32_t ticks)
{
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    for (uint32_t t = 0; t < ticks; t++) {
        fake_hal.encoder[0] = (uint16_t)(fake_hal.encoder[0] + 1u);
        fake_hal.encoder[1] = (uint16_t)(fake_hal.encoder[1] + 1u);
        if (robot.sweep.phase == SWEEP_WAIT) {
            fake_hal.sonar_next = HAL_SONAR_ECHO;
            fake_hal.sonar_echo_us = 3000u + 100u * robot.sweep.seq;
        }
        robot_tick(&robot);
        robot_idle(&robot);
    }
}

/* Nothing reads the UART: no frame is built or written, and the telemetry's state (the
 * frames counted, the ring, the map rows' place, when the next HELLO and STATUS are due)
 * is what it is when every frame goes out whole. */
static void test_no_reader_counts_the_frames_it_skips(void **state)
{
    (void)state;
    drive_robot(3000u);
    static telem_t heard;
    heard = robot.telem;
    assert_true(heard.frames > 300u && fake_hal.uart_len > 0u);
    fake_hal_reset();
    fake_hal.uart_no_reader = true;
    drive_robot(3000u);
    assert_int_equal(fake_hal.uart_len, 0u);
    assert_int_equal(robot.telem.frames, heard.frames);
    assert_memory_equal(&robot.telem, &heard, sizeof heard);
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
    telem_idle(&t, &g, &cfg, &st, 1u);
    assert_true(t.short_writes >= 1u);
    fake_hal.uart_room = 0u;
    telem_post_pose(&t, 2u, &p);
    telem_idle(&t, &g, &cfg, &st, 2u);
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

/* Every frame the firmware sends unpacks by its type (tests/support/telem_decode.c); a
 * frame with a good CRC and the wrong length for its type, or an unknown type, is refused
 * rather than read past its end. */
static void test_decoder_checks_lengths(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    static grid_t g;
    grid_init(&g, &cfg);
    telem_status_t st = {7u, 6u, 5u, 4u, 3u, 2u, 1u, 2u, 0u, 0u};
    odom_pose_t p = {-5, 6, 0x80000000u};
    telem_post_pose(&t, 9u, &p);
    telem_post_reading(&t, 10u, 2u, 1u, -155000, 123456u, &p);
    telem_idle(&t, &g, &cfg, &st, 100u);
    telem_send_ack(&t, TELEM_CMD_STOP);
    telem_send_error(&t, TELEM_CMD_SET, TELEM_ERR_KEY, 99u);
    telem_send_config(&t, &cfg, 3u);
    size_t pos = 0;
    frame_t f;
    tdec_msg_t m;
    unsigned bad = 0;
    unsigned kinds = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        assert_int_equal(tdec_decode(&f, &m), 0);
        kinds |= 1u << m.type;
        if (m.type == TELEM_READING) {
            assert_int_equal(m.servo_mdeg, -155000);
            assert_int_equal(m.range_um, 123456u);
            assert_int_equal(m.x_um, -5);
            assert_int_equal(m.heading, 0x80000000u);
        } else if (m.type == TELEM_STATUS) {
            assert_int_equal(m.status[0], 7u);
            assert_int_equal(m.explore_mode, 2u);
        } else if (m.type == TELEM_HELLO) {
            assert_int_equal(m.a, SLAM_GRID_A);
            assert_int_equal(m.cell_um, cfg.cell_um);
            assert_int_equal(m.confidence_radius_um, cfg.confidence_radius_um);
            assert_int_equal(m.om_mode, cfg.om_mode);
        } else if (m.type == TELEM_ERROR) {
            assert_int_equal(m.key, 99u);
        } else if (m.type == TELEM_CONFIG) {
            assert_int_equal(m.value, cfg.wheel_base_um);
        }
    }
    assert_int_equal(kinds, (1u << TELEM_HELLO) | (1u << TELEM_POSE) | (1u << TELEM_READING) |
                                (1u << TELEM_MAP_ROW) | (1u << TELEM_STATUS) | (1u << TELEM_ACK) |
                                (1u << TELEM_ERROR) | (1u << TELEM_CONFIG));
    uint8_t buf[TELEM_FRAME_MAX];
    uint8_t pl[48] = {0};
    const struct {
        uint8_t type, len;
        int rc;
    } cases[] = {
        {TELEM_POSE, 15u, -2},
        {TELEM_POSE, 17u, -2},
        {TELEM_READING, 16u, -2},
        {TELEM_HELLO, 19u, -2},
        {TELEM_STATUS, 32u, -2},
        {TELEM_MAP_ROW, 4u, -2},
        {TELEM_MAP_ROW, 5u, -3},
        {TELEM_ACK, 0u, -2},
        {TELEM_CONFIG, 4u, -2},
        {9u, 3u, -1},
        {0u, 0u, -1},
    };
    pl[0] = 2u; /* a MAP_ROW of map 2 */
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t n = telem_frame(buf, cases[i].type, pl, cases[i].len);
        pos = 0;
        bad = 0;
        assert_true(next_frame(buf, n, &pos, &f, &bad));
        assert_int_equal(tdec_decode(&f, &m), cases[i].rc);
    }
}

/* A home that does not fit is told over the link: once a point has fallen outside the
 * grid, the robot's STATUS carries the count (46 bytes); before, it is the 42 bytes it
 * always was. */
static void test_status_tells_points_outside_the_grid(void **state)
{
    (void)state;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    uint32_t statuses[2] = {0, 0};
    uint32_t outside = 0;
    for (int round = 0; round < 2; round++) {
        if (round == 1) {
            /* A wall far beyond the grid's edge, as a hit the mapper places. */
            int32_t far = robot.grid.origin_x_um - (int32_t)robot.grid.cell_um;
            assert_int_equal(grid_om_hit(&robot.grid, far, 0), SLAM_EOUTSIDE);
            assert_int_equal(grid_om_hit(&robot.grid, 0, far), SLAM_EOUTSIDE);
        }
        fake_hal.uart_len = 0;
        for (uint32_t t = 0; t < 200u; t++) { /* two seconds: a STATUS every one */
            robot_tick(&robot);
            robot_idle(&robot);
        }
        size_t pos = 0;
        frame_t f;
        tdec_msg_t m;
        unsigned bad = 0;
        while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
            if (f.type == TELEM_STATUS) {
                assert_int_equal(f.len, round == 0 ? 42u : 46u);
                assert_int_equal(tdec_decode(&f, &m), 0);
                statuses[round]++;
                outside = m.outside;
            }
        }
        assert_int_equal(outside, round == 0 ? 0u : 2u);
    }
    assert_true(statuses[0] > 0u && statuses[1] > 0u);

    /* The decoder takes both forms and no other length near them. */
    uint8_t buf[TELEM_FRAME_MAX];
    uint8_t pl[46] = {0};
    pl[42] = 7u;
    for (uint8_t len = 40u; len <= 46u; len++) {
        size_t n = telem_frame(buf, TELEM_STATUS, pl, len);
        size_t pos = 0;
        frame_t f;
        tdec_msg_t m;
        unsigned bad = 0;
        assert_true(next_frame(buf, n, &pos, &f, &bad));
        assert_int_equal(tdec_decode(&f, &m), len == 42u || len == 46u ? 0 : -2);
        if (len == 46u) {
            assert_int_equal(m.outside, 7u);
        }
    }
}

/* ---- commands ---------------------------------------------------------------------------- */

/* A command frame as a host sends it. */
static size_t cmd_frame(uint8_t *buf, uint8_t type, const uint8_t *payload, uint8_t len)
{
    return telem_frame(buf, type, payload, len);
}

/* Feeds bytes; returns how many commands came out (the last in *out). */
static unsigned feed(telem_t *t, const uint8_t *b, size_t n, uint32_t ticks, telem_cmd_t *out)
{
    unsigned got = 0;
    for (size_t i = 0; i < n; i++) {
        telem_cmd_t c;
        if (telem_rx_byte(t, b[i], ticks, &c)) {
            *out = c;
            got++;
        }
    }
    return got;
}

/* The ERROR frames written so far, as (command, code) pairs; returns how many. */
static unsigned errors_sent(uint8_t cmds[], uint8_t codes[], unsigned max)
{
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    unsigned n = 0;
    while (next_frame(fake_hal.uart, fake_hal.uart_len, &pos, &f, &bad)) {
        if (f.type == TELEM_ERROR && n < max) {
            assert_int_equal(f.len, 3u);
            cmds[n] = f.payload[0];
            codes[n] = f.payload[1];
            n++;
        }
    }
    return n;
}

static void test_every_command_parses(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    static const struct {
        uint8_t type, len;
        uint8_t payload[5];
    } cmds[] = {
        {TELEM_CMD_START, 0, {0}},
        {TELEM_CMD_STOP, 0, {0}},
        {TELEM_CMD_MODE, 1, {2}},
        {TELEM_CMD_GET, 1, {36}},
        {TELEM_CMD_SET, 5, {36, 0x96, 0, 0, 0}},
        {TELEM_CMD_SAVE, 0, {0}},
        {TELEM_CMD_SEND_MAP, 0, {0}},
        {TELEM_CMD_CALIBRATE, 0, {0}},
    };
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        uint8_t buf[16];
        size_t n = cmd_frame(buf, cmds[i].type, cmds[i].payload, cmds[i].len);
        telem_cmd_t c = {0};
        /* Noise before a frame is skipped: the parser finds A5 5A. */
        static const uint8_t noise[5] = {0x00, 0xA5, 0x13, 0x5A, 0xFF};
        assert_int_equal(feed(&t, noise, sizeof noise, 0u, &c), 0u);
        assert_int_equal(feed(&t, buf, n, 0u, &c), 1u);
        assert_int_equal(c.type, cmds[i].type);
        if (cmds[i].len >= 1u) {
            assert_int_equal(c.key, cmds[i].payload[0]);
        }
        if (cmds[i].type == TELEM_CMD_SET) {
            assert_int_equal(c.value, 150u);
        }
    }
    uint8_t ec[4], codes[4];
    assert_int_equal(errors_sent(ec, codes, 4), 0u);
    assert_int_equal(t.refused, 0u);
}

static void test_malformed_commands_are_refused(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    telem_cmd_t c;
    uint8_t buf[300];
    const uint8_t set[5] = {36, 0x96, 0, 0, 0};

    /* A bad CRC. */
    size_t n = cmd_frame(buf, TELEM_CMD_SET, set, 5u);
    buf[n - 1] ^= 0x40u;
    assert_int_equal(feed(&t, buf, n, 0u, &c), 0u);
    /* A CRC-valid frame of the wrong length for its command. */
    n = cmd_frame(buf, TELEM_CMD_SET, set, 4u);
    assert_int_equal(feed(&t, buf, n, 0u, &c), 0u);
    n = cmd_frame(buf, TELEM_CMD_START, set, 1u);
    assert_int_equal(feed(&t, buf, n, 0u, &c), 0u);
    /* Longer than any command: refused from its header, without waiting for the rest. */
    static uint8_t big[200];
    n = cmd_frame(buf, TELEM_CMD_SET, big, 200u);
    assert_int_equal(feed(&t, buf, 4u, 0u, &c), 0u);
    assert_int_equal(t.refused, 4u);
    assert_int_equal(feed(&t, buf + 4, n - 4u, 0u, &c), 0u);
    /* An unknown command, and a telemetry type sent the wrong way. */
    n = cmd_frame(buf, 0x42u, NULL, 0u);
    assert_int_equal(feed(&t, buf, n, 0u, &c), 0u);
    n = cmd_frame(buf, TELEM_HELLO, NULL, 0u);
    assert_int_equal(feed(&t, buf, n, 0u, &c), 0u);
    /* A frame that stops coming: refused once TELEM_RX_TIMEOUT_TICKS have passed. */
    n = cmd_frame(buf, TELEM_CMD_GET, set, 1u);
    assert_int_equal(feed(&t, buf, n - 2u, 100u, &c), 0u);
    telem_rx_expire(&t, 100u + TELEM_RX_TIMEOUT_TICKS - 1u);
    assert_int_equal(t.refused, 6u);
    telem_rx_expire(&t, 100u + TELEM_RX_TIMEOUT_TICKS);
    assert_int_equal(t.refused, 7u);

    uint8_t ec[8], codes[8];
    assert_int_equal(errors_sent(ec, codes, 8), 7u);
    static const uint8_t want_cmd[7] = {TELEM_CMD_SET, TELEM_CMD_SET, TELEM_CMD_START,
                                        TELEM_CMD_SET, 0x42u,         TELEM_HELLO,
                                        TELEM_CMD_GET};
    static const uint8_t want_code[7] = {TELEM_ERR_CRC,    TELEM_ERR_LENGTH,  TELEM_ERR_LENGTH,
                                         TELEM_ERR_LENGTH, TELEM_ERR_COMMAND, TELEM_ERR_COMMAND,
                                         TELEM_ERR_LENGTH};
    assert_memory_equal(ec, want_cmd, 7u);
    assert_memory_equal(codes, want_code, 7u);

    /* After all that, a good command still parses. */
    n = cmd_frame(buf, TELEM_CMD_STOP, NULL, 0u);
    assert_int_equal(feed(&t, buf, n, 200u, &c), 1u);
    assert_int_equal(c.type, TELEM_CMD_STOP);
}

/* Random noise: never a command (a random frame would need the right CRC), and the parser
 * never holds more than the longest command. */
static void test_noise_never_makes_a_command(void **state)
{
    (void)state;
    telem_t t;
    telem_init(&t);
    uint32_t x = 12345u;
    unsigned got = 0;
    for (unsigned i = 0; i < 200000u; i++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        /* Plenty of sync bytes, to exercise every state. */
        uint8_t b = (x & 0x300u) == 0u ? 0xA5u : (x & 0x300u) == 0x100u ? 0x5Au : (uint8_t)x;
        telem_cmd_t c;
        got += telem_rx_byte(&t, b, i / 10u, &c);
        assert_true(t.rx_len <= TELEM_CMD_FRAME_MAX);
        if ((i & 63u) == 0u) {
            fake_hal.uart_len = 0u; /* keep the fake UART from filling up */
        }
    }
    assert_int_equal(got, 0u);
    assert_true(t.refused > 1000u);
}

static void test_config_keys_get_and_set(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    /* Every key reads back its field; setting a live key to its own value is accepted. */
    unsigned live = 0;
    for (unsigned k = 1; k <= TELEM_CONFIG_KEY_MAX; k++) {
        uint32_t v = 0;
        assert_int_equal(telem_config_get(&c, (uint8_t)k, &v), 0);
        int rc = telem_config_set(&c, (uint8_t)k, v);
        assert_true(rc == 0 || rc == -(int)TELEM_ERR_FIXED);
        live += rc == 0;
    }
#define LIVE_ROW(name, type, dflt, lo, hi, rule, id, live, words) +((#live)[0] == 'L')
    assert_int_equal(live, 0u TELEM_CONFIG_KEYS(LIVE_ROW)); /* 32 of the first 52 */
#undef LIVE_ROW
    slam_config_t d;
    slam_config_default(&d);
    assert_memory_equal(&c, &d, sizeof c);
    uint32_t v;
    assert_int_equal(telem_config_get(&c, 3u, &v), 0);
    assert_int_equal(v, c.wheel_base_um);
    assert_int_equal(telem_config_get(&c, 24u, &v), 0);
    assert_int_equal(v, (uint32_t)c.mount_yaw_mdeg);
    assert_int_equal(telem_config_get(&c, TELEM_KEY_EXPLORE_MODE, &v), 0);
    assert_int_equal(v, c.explore_mode);
    assert_int_equal(telem_config_get(&c, TELEM_KEY_EXPLORE_SEED, &v), 0);
    assert_int_equal(v, c.explore_seed);
    /* A signed field takes a two's complement value. */
    assert_int_equal(telem_config_set(&c, 24u, (uint32_t)-5000), 0);
    assert_int_equal(c.mount_yaw_mdeg, -5000);
    assert_int_equal(telem_config_set(&c, 40u, 150u), 0);
    assert_int_equal(c.cruise_mm_s, 150u);

    /* Refused, and nothing changes. */
    slam_config_t before = c;
    assert_int_equal(telem_config_set(&c, 0u, 1u), -(int)TELEM_ERR_KEY);
    assert_int_equal(telem_config_set(&c, TELEM_CONFIG_KEY_MAX + 1u, 1u), -(int)TELEM_ERR_KEY);
    assert_int_equal(telem_config_set(&c, 255u, 1u), -(int)TELEM_ERR_KEY);
    assert_int_equal(telem_config_get(&c, TELEM_CONFIG_KEY_MAX + 1u, &v), -(int)TELEM_ERR_KEY);
    assert_int_equal(telem_config_set(&c, 11u, 100000u), -(int)TELEM_ERR_FIXED); /* cell_um */
    assert_int_equal(telem_config_set(&c, 39u, EXPLORE_MODES), -(int)TELEM_ERR_RANGE);
    assert_int_equal(telem_config_set(&c, 45u, 256u), -(int)TELEM_ERR_RANGE);   /* u8 */
    assert_int_equal(telem_config_set(&c, 40u, 65536u), -(int)TELEM_ERR_RANGE); /* u16 */
    assert_int_equal(telem_config_set(&c, 40u, 5000u), -(int)TELEM_ERR_RANGE);  /* > top speed */
    assert_int_equal(telem_config_set(&c, 3u, 0u), -(int)TELEM_ERR_RANGE);
    assert_int_equal(telem_config_set(&c, 5u, 0x7FFFFFFFu), -(int)TELEM_ERR_RANGE); /* cal */
    assert_memory_equal(&c, &before, sizeof c);
}

/* The keys as released: a key in use keeps its id for ever (a host tool and a robot of
 * other versions must mean the same field by it). New keys need no line here. */
static const char *const released_keys[] = {
    NULL,
    "wheel_diameter_left_um",
    "wheel_diameter_right_um",
    "wheel_base_um",
    "encoder_counts_per_rev",
    "cal_left",
    "cal_right",
    "cal_base",
    "start_x_um",
    "start_y_um",
    "start_heading_mdeg",
    "cell_um",
    "start_cell_a",
    "start_cell_b",
    "om_max",
    "tm_max",
    "om_mode",
    "om_hit",
    "om_miss",
    "confidence_radius_um",
    "range_min_um",
    "sound_speed_mm_per_s",
    "mount_x_um",
    "mount_y_um",
    "mount_yaw_mdeg",
    "sweep_first_mdeg",
    "sweep_last_mdeg",
    "sweep_stops",
    "settle_ticks",
    "echo_timeout_ticks",
    "servo_pulse_0deg_us",
    "servo_pulse_180deg_us",
    "post_threshold",
    "post_template_k",
    "post_insert",
    "top_speed_mm_s",
    "accel_mm_s2",
    "motion_kp_q8",
    "motion_ki_q8",
    "explore_mode",
    "cruise_mm_s",
    "turn_mm_s",
    "avoid_um",
    "clearance_um",
    "square_side_um",
    "square_laps",
    "explore_seed",
    "save_period_s",
    "localize",
    "ping_interval_ticks",
    "follow_um",
    "umbmark_runs",
    "umbmark_pause_s",
    "grid_a",
    "grid_b",
    "sonar1_map",
    "sonar1_mdeg",
};

/* Every row's key reads and writes its own field with the row's type and liveness, and
 * no released key changed its field. */
static void test_config_keys_are_the_rows(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        uint8_t id;
        size_t offset, size;
        bool live;
    } rows[] = {
#define ROW(name, type, dflt, lo, hi, rule, id, live, words)                                       \
    {#name, id, offsetof(slam_config_t, name), sizeof cfg.name, (#live)[0] == 'L'},
        TELEM_CONFIG_KEYS(ROW)
#undef ROW
    };
    unsigned max = 0u;
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        max = rows[i].id > max ? rows[i].id : max;
        if (rows[i].id < sizeof released_keys / sizeof released_keys[0]) {
            assert_string_equal(rows[i].name, released_keys[rows[i].id]);
        }
        /* GET reads the field's bytes: mark them and see the mark come back. */
        slam_config_t c;
        slam_config_default(&c);
        uint32_t before = 0u;
        assert_int_equal(telem_config_get(&c, rows[i].id, &before), 0);
        memset((uint8_t *)&c + rows[i].offset, 0x5A, rows[i].size);
        uint32_t v = 0u;
        assert_int_equal(telem_config_get(&c, rows[i].id, &v), 0);
        assert_int_equal(v, rows[i].size == 1u   ? 0x5Au
                            : rows[i].size == 2u ? 0x5A5Au
                                                 : 0x5A5A5A5Au);
        /* SET of the value in force: taken when live, TELEM_ERR_FIXED when not. */
        slam_config_default(&c);
        assert_int_equal(telem_config_set(&c, rows[i].id, before),
                         rows[i].live ? 0 : -(int)TELEM_ERR_FIXED);
    }
    for (size_t k = 1; k < sizeof released_keys / sizeof released_keys[0]; k++) {
        uint32_t v;
        assert_int_equal(telem_config_get(&cfg, (uint8_t)k, &v), 0); /* none dropped */
    }
    assert_int_equal(max, TELEM_CONFIG_KEY_MAX);
    assert_int_equal(TELEM_KEY_EXPLORE_MODE, 39u);
    assert_int_equal(TELEM_KEY_EXPLORE_SEED, 46u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_crc16_and_frame_layout, setup),
        cmocka_unit_test_setup(test_ring_drops_when_full_and_counts, setup),
        cmocka_unit_test_setup(test_robot_stream_decodes, setup),
        cmocka_unit_test_setup(test_short_writes_are_counted_and_resynchronised, setup),
        cmocka_unit_test_setup(test_no_reader_counts_the_frames_it_skips, setup),
        cmocka_unit_test_setup(test_decoder_checks_lengths, setup),
        cmocka_unit_test_setup(test_status_tells_points_outside_the_grid, setup),
        cmocka_unit_test_setup(test_every_command_parses, setup),
        cmocka_unit_test_setup(test_malformed_commands_are_refused, setup),
        cmocka_unit_test_setup(test_noise_never_makes_a_command, setup),
        cmocka_unit_test_setup(test_config_keys_get_and_set, setup),
        cmocka_unit_test_setup(test_config_keys_are_the_rows, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
