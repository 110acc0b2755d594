/* SPDX-License-Identifier: MIT */
/*
 * Fuzz target: telemetry both ways. The input as bytes a host receives: every frame the
 * test decoder (tests/support) finds must be the firmware's framing of what it decoded.
 * The same bytes as commands the robot receives: the firmware's parser must take only
 * well-formed commands, answer the rest, and its configuration keys must read back what
 * they set and keep the configuration valid. Then the input as events, a grid and a
 * status for the firmware's encoder: the decoder must give back exactly what was posted.
 */
#include <string.h>

#include "fuzz.h"
#include "hal/hal.h"
#include "slam/error.h"
#include "slam/telemetry.h"
#include "telem_decode.h"

/* The UART: what the firmware writes lands here. */
static uint8_t uart[1u << 16];
static size_t uart_len;

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    size_t n = len > sizeof uart - uart_len ? sizeof uart - uart_len : len;
    memcpy(uart + uart_len, data, n);
    uart_len += n;
    return n;
}

static uint32_t take32(const uint8_t **p, const uint8_t *end)
{
    uint32_t v = 0;
    for (int k = 0; k < 4 && *p < end; k++) {
        v |= (uint32_t) * (*p)++ << (8 * k);
    }
    return v;
}

/* Every frame found re-frames to the very bytes it came from. */
static void decode_stream(const uint8_t *data, size_t size)
{
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    while (next_frame(data, size, &pos, &f, &bad)) {
        uint8_t buf[TELEM_FRAME_MAX];
        size_t n = telem_frame(buf, f.type, f.payload, f.len);
        FUZZ_CHECK(n == (size_t)f.len + 6u && pos >= n && memcmp(buf, data + pos - n, n) == 0);
        tdec_msg_t m;
        int rc = tdec_decode(&f, &m);
        FUZZ_CHECK(rc == 0 || rc == -1 || rc == -2 || rc == -3);
        FUZZ_CHECK(rc != 0 || m.type == f.type);
    }
    FUZZ_CHECK(pos <= size);
}

/* The bytes as commands to the robot: what comes out is well formed, every answer the
 * parser writes decodes, and SET/GET keep the configuration valid and read back. */
static void parse_commands(const uint8_t *data, size_t size)
{
    telem_t t;
    telem_init(&t);
    slam_config_t cfg;
    slam_config_default(&cfg);
    uart_len = 0;
    uint32_t ticks = 0;
    for (size_t i = 0; i < size; i++) {
        ticks += data[i] == 0xFFu ? TELEM_RX_TIMEOUT_TICKS + 1u : 1u; /* now and then, late */
        telem_rx_expire(&t, ticks);
        telem_cmd_t c;
        if (!telem_rx_byte(&t, data[i], ticks, &c)) {
            continue;
        }
        FUZZ_CHECK(c.type >= TELEM_CMD_START && c.type <= TELEM_CMD_CALIBRATE);
        if (c.type == TELEM_CMD_SET) {
            slam_config_t before = cfg;
            int rc = telem_config_set(&cfg, c.key, c.value);
            FUZZ_CHECK(slam_config_check(&cfg, NULL) == SLAM_OK);
            if (rc != 0) {
                FUZZ_CHECK(memcmp(&cfg, &before, sizeof cfg) == 0);
            } else {
                uint32_t v = 0;
                FUZZ_CHECK(telem_config_get(&cfg, c.key, &v) == 0 && v == c.value);
            }
        } else if (c.type == TELEM_CMD_GET) {
            uint32_t v = 0;
            int rc = telem_config_get(&cfg, c.key, &v);
            FUZZ_CHECK(rc == 0 || rc == -TELEM_ERR_KEY);
        }
    }
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    while (next_frame(uart, uart_len, &pos, &f, &bad)) {
        tdec_msg_t m;
        FUZZ_CHECK(tdec_decode(&f, &m) == 0 && m.type == TELEM_ERROR);
        FUZZ_CHECK(m.code >= TELEM_ERR_CRC && m.code <= TELEM_ERR_UNSUPPORTED);
    }
    FUZZ_CHECK(bad == 0u && pos == uart_len && t.refused * 9u == uart_len);
}

static grid_t grid;

/* Events from the input through the firmware's encoder, and back. */
static void round_trip(const uint8_t *data, size_t size)
{
    const uint8_t *p = data;
    const uint8_t *end = data + size;
    slam_config_t cfg;
    slam_config_default(&cfg);
    static bool drawn;
    if (!drawn) {
        grid_init(&grid, &cfg);
        for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
            grid.om[i] = (uint8_t)(i * 7u);
            grid.tm[i] = (uint8_t)(i * 3u + 1u);
        }
        drawn = true;
    }
    grid.cell_um = take32(&p, end);
    grid.origin_x_um = (int32_t)take32(&p, end);
    grid.origin_y_um = (int32_t)take32(&p, end);
    cfg.confidence_radius_um = take32(&p, end);
    cfg.mount_yaw_mdeg = (int32_t)take32(&p, end);
    telem_status_t st = {take32(&p, end), take32(&p, end), 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    st.explore_mode = p < end ? *p++ : 0u;
    st.outside = p < end ? *p++ : 0u; /* 0: the 42-byte STATUS, else the 46-byte one */
    telem_t t;
    telem_init(&t);
    telem_event_t posted[TELEM_RING];
    unsigned nposted = 0;
    uint32_t ticks = take32(&p, end);
    while (p < end && nposted < TELEM_RING - 1u) { /* one slot stays empty */
        telem_event_t e = {0};
        e.type = (*p++ & 1u) ? TELEM_READING : TELEM_POSE;
        e.ticks = take32(&p, end);
        e.pose.x_um = (int32_t)take32(&p, end);
        e.pose.y_um = (int32_t)take32(&p, end);
        e.pose.heading = take32(&p, end);
        if (e.type == TELEM_READING) {
            e.stop = p < end ? *p++ : 0u;
            e.outcome = p < end ? *p++ : 0u;
            e.servo_mdeg = (int32_t)take32(&p, end);
            e.range_um = take32(&p, end);
            telem_post_reading(&t, e.ticks, e.stop, e.outcome, e.servo_mdeg, e.range_um, &e.pose);
        } else {
            telem_post_pose(&t, e.ticks, &e.pose);
        }
        posted[nposted++] = e;
    }
    uart_len = 0;
    telem_idle(&t, &grid, &cfg, &st, ticks);
    FUZZ_CHECK(t.dropped == 0u && t.short_writes == 0u);
    size_t pos = 0;
    frame_t f;
    unsigned bad = 0;
    unsigned got = 0;
    unsigned others = 0;
    while (next_frame(uart, uart_len, &pos, &f, &bad)) {
        tdec_msg_t m;
        FUZZ_CHECK(tdec_decode(&f, &m) == 0);
        if (m.type == TELEM_POSE || m.type == TELEM_READING) {
            FUZZ_CHECK(got < nposted);
            const telem_event_t *e = &posted[got++];
            FUZZ_CHECK(m.type == e->type && m.ticks == e->ticks && m.x_um == e->pose.x_um &&
                       m.y_um == e->pose.y_um && m.heading == e->pose.heading);
            FUZZ_CHECK(m.type == TELEM_POSE ||
                       (m.stop == e->stop && m.outcome == e->outcome &&
                        m.servo_mdeg == e->servo_mdeg && m.range_um == e->range_um));
        } else if (m.type == TELEM_HELLO) {
            FUZZ_CHECK(m.version == TELEM_VERSION && m.a == SLAM_GRID_A && m.b == SLAM_GRID_B &&
                       m.cell_um == grid.cell_um && m.origin_x_um == grid.origin_x_um &&
                       m.confidence_radius_um == cfg.confidence_radius_um &&
                       m.mount_yaw_mdeg == cfg.mount_yaw_mdeg);
            others++;
        } else if (m.type == TELEM_STATUS) {
            FUZZ_CHECK(m.status[0] == st.ticks && m.status[1] == st.pings &&
                       m.explore_mode == st.explore_mode && m.outside == st.outside);
            others++;
        } else {
            FUZZ_CHECK(m.type == TELEM_MAP_ROW && m.row < SLAM_GRID_B &&
                       m.first + m.ncells <= SLAM_GRID_A);
            const uint8_t *cells =
                (m.map == 0u ? grid.om : grid.tm) + (uint32_t)m.row * SLAM_GRID_A;
            FUZZ_CHECK(memcmp(m.cells, cells + m.first, m.ncells) == 0);
            others++;
        }
    }
    FUZZ_CHECK(got == nposted && bad == 0u && pos == uart_len);
    FUZZ_CHECK(others >= 1u); /* the first idle call says hello */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    decode_stream(data, size);
    parse_commands(data, size);
    round_trip(data, size);
    return 0;
}
