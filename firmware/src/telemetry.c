/* SPDX-License-Identifier: MIT */
/* Telemetry: events from the tick, framed and written by the background loop. */
#include "slam/telemetry.h"

#include <string.h>

#include "hal/hal.h"

#define TELEM_TICKS_PER_S (1000000u / HAL_TICK_PERIOD_US)

static const uint16_t crc16_nibble[16] = {
    0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u, 0x60C6u, 0x70E7u,
    0x8108u, 0x9129u, 0xA14Au, 0xB16Bu, 0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu,
};

uint16_t telem_crc16(const uint8_t *data, size_t len)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)((crc << 4) ^ crc16_nibble[((crc >> 12) ^ (data[i] >> 4)) & 0xFu]);
        crc = (uint16_t)((crc << 4) ^ crc16_nibble[((crc >> 12) ^ (data[i] & 0xFu)) & 0xFu]);
    }
    return crc;
}

size_t telem_frame(uint8_t *buf, uint8_t type, const uint8_t *payload, uint8_t len)
{
    buf[0] = TELEM_SYNC0;
    buf[1] = TELEM_SYNC1;
    buf[2] = type;
    buf[3] = len;
    memcpy(buf + 4, payload, len);
    uint16_t crc = telem_crc16(buf + 2, (size_t)len + 2u);
    buf[4u + len] = (uint8_t)crc;
    buf[5u + len] = (uint8_t)(crc >> 8);
    return (size_t)len + 6u;
}

void telem_init(telem_t *t)
{
    memset(t, 0, sizeof *t);
    /* The first idle call says hello. */
    t->last_hello_tick = UINT32_MAX - 5u * TELEM_TICKS_PER_S;
}

/* The ring has one producer (the tick) and one consumer (idle), which on Linux run on
 * different cores: an index is published with release order after its slot is written,
 * and read with acquire order before the slot is read. */
static void post(telem_t *t, const telem_event_t *e)
{
    uint8_t head = t->head;
    uint8_t next = (uint8_t)((head + 1u) % TELEM_RING);
    if (next == __atomic_load_n(&t->tail, __ATOMIC_ACQUIRE)) {
        t->dropped++;
        return;
    }
    t->ring[head] = *e;
    __atomic_store_n(&t->head, next, __ATOMIC_RELEASE);
}

void telem_post_pose(telem_t *t, uint32_t ticks, const odom_pose_t *pose)
{
    telem_event_t e = {.type = TELEM_POSE, .ticks = ticks, .pose = *pose};
    post(t, &e);
}

void telem_post_reading(telem_t *t, uint32_t ticks, uint8_t stop, uint8_t outcome,
                        int32_t servo_mdeg, uint32_t range_um, const odom_pose_t *ping)
{
    telem_event_t e = {.type = TELEM_READING, .stop = stop, .outcome = outcome, .ticks = ticks,
                       .pose = *ping, .servo_mdeg = servo_mdeg, .range_um = range_um};
    post(t, &e);
}

/* Little-endian packing. */
static uint8_t *put8(uint8_t *p, uint8_t v)
{
    *p = v;
    return p + 1;
}

static uint8_t *put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    return p + 2;
}

static uint8_t *put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
    return p + 4;
}

static void send(telem_t *t, uint8_t type, const uint8_t *payload, size_t len)
{
    uint8_t frame[TELEM_FRAME_MAX];
    size_t n = telem_frame(frame, type, payload, (uint8_t)len);
    if (hal_uart_write(frame, n) != n) {
        t->short_writes++;
    } else {
        t->frames++;
    }
}

static void send_event(telem_t *t, const telem_event_t *e)
{
    uint8_t pl[32];
    uint8_t *p = put32(pl, e->ticks);
    if (e->type == TELEM_READING) {
        p = put8(p, e->stop);
        p = put8(p, e->outcome);
        p = put32(p, (uint32_t)e->servo_mdeg);
        p = put32(p, e->range_um);
    }
    p = put32(p, (uint32_t)e->pose.x_um);
    p = put32(p, (uint32_t)e->pose.y_um);
    p = put32(p, e->pose.heading);
    send(t, e->type, pl, (size_t)(p - pl));
}

static void send_hello(telem_t *t, const grid_t *g)
{
    uint8_t pl[19];
    uint8_t *p = put8(pl, TELEM_VERSION);
    p = put16(p, SLAM_GRID_A);
    p = put16(p, SLAM_GRID_B);
    p = put32(p, g->cell_um);
    p = put32(p, (uint32_t)g->origin_x_um);
    p = put32(p, (uint32_t)g->origin_y_um);
    p = put8(p, g->om_max);
    p = put8(p, g->tm_max);
    send(t, TELEM_HELLO, pl, (size_t)(p - pl));
}

static void send_status(telem_t *t, const telem_status_t *st)
{
    uint8_t pl[32];
    const uint32_t v[8] = {st->ticks, st->pings, st->echoes, st->timeouts,
                           st->om_hits, st->overruns, st->saves, t->dropped + t->short_writes};
    uint8_t *p = pl;
    for (unsigned i = 0; i < 8u; i++) {
        p = put32(p, v[i]);
    }
    send(t, TELEM_STATUS, pl, sizeof pl);
}

/* The next segment of the map rows, OM then TM, round and round. */
static void send_map_row(telem_t *t, const grid_t *g)
{
    uint8_t pl[5u + TELEM_MAP_CELLS];
    uint16_t n = (uint16_t)(SLAM_GRID_A - t->first);
    n = n > TELEM_MAP_CELLS ? (uint16_t)TELEM_MAP_CELLS : n;
    const uint8_t *cells = (t->map == 0u ? g->om : g->tm) + (uint32_t)t->row * SLAM_GRID_A + t->first;
    uint8_t *p = put8(pl, t->map);
    p = put16(p, t->row);
    p = put16(p, t->first);
    memcpy(p, cells, n);
    send(t, TELEM_MAP_ROW, pl, 5u + n);
    t->first = (uint16_t)(t->first + n);
    if (t->first >= SLAM_GRID_A) {
        t->first = 0u;
        if (++t->row >= SLAM_GRID_B) {
            t->row = 0u;
            t->map ^= 1u;
        }
    }
}

void telem_idle(telem_t *t, const grid_t *g, const telem_status_t *st, uint32_t ticks)
{
    uint8_t tail = t->tail;
    while (tail != __atomic_load_n(&t->head, __ATOMIC_ACQUIRE)) {
        telem_event_t e = t->ring[tail];
        tail = (uint8_t)((tail + 1u) % TELEM_RING);
        __atomic_store_n(&t->tail, tail, __ATOMIC_RELEASE);
        send_event(t, &e);
    }
    if (ticks - t->last_hello_tick >= 5u * TELEM_TICKS_PER_S) {
        t->last_hello_tick = ticks;
        send_hello(t, g);
    }
    if (ticks - t->last_status_tick >= TELEM_TICKS_PER_S) {
        t->last_status_tick = ticks;
        send_status(t, st);
    }
    if (ticks - t->last_row_tick >= TELEM_ROW_TICKS) {
        t->last_row_tick = ticks;
        send_map_row(t, g);
    }
}
