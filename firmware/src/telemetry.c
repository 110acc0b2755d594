/* SPDX-License-Identifier: MIT */
/* Telemetry: events from the tick, framed and written by the background loop. */
#include "slam/telemetry.h"

#include <string.h>

#include "hal/hal.h"

#define TELEM_TICKS_PER_S (1000000u / HAL_TICK_PERIOD_US)

/*
 * CRC-16/CCITT-FALSE. Where memory is plenty (a 64-bit processor: the simulator, a 64-bit
 * Linux robot) a byte at a time from a 512-byte table: every frame sent is checked, and a
 * nibble at a time it was 6 % of a simulated run (when frames were built whether anything
 * read them or not). On an MCU a nibble at a time from 32 bytes: measured on the STM32F4,
 * the byte table costs 456 bytes of flash and takes nothing off a budget (the tick never
 * runs the CRC, and the worst background-loop call, a match, loses 0.2 %). Either way the
 * same CRC; a build may set TELEM_CRC_BYTE_TABLE to 0 or 1 itself.
 */
#ifndef TELEM_CRC_BYTE_TABLE
#if UINTPTR_MAX > 0xFFFFFFFFu
#define TELEM_CRC_BYTE_TABLE 1
#else
#define TELEM_CRC_BYTE_TABLE 0
#endif
#endif

#if TELEM_CRC_BYTE_TABLE
/* crc16_table[b]: the CRC register's change when byte b leaves its top (poly 0x1021). */
static const uint16_t crc16_table[256] = {
    0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u, 0x60C6u, 0x70E7u, 0x8108u, 0x9129u,
    0xA14Au, 0xB16Bu, 0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu, 0x1231u, 0x0210u, 0x3273u, 0x2252u,
    0x52B5u, 0x4294u, 0x72F7u, 0x62D6u, 0x9339u, 0x8318u, 0xB37Bu, 0xA35Au, 0xD3BDu, 0xC39Cu,
    0xF3FFu, 0xE3DEu, 0x2462u, 0x3443u, 0x0420u, 0x1401u, 0x64E6u, 0x74C7u, 0x44A4u, 0x5485u,
    0xA56Au, 0xB54Bu, 0x8528u, 0x9509u, 0xE5EEu, 0xF5CFu, 0xC5ACu, 0xD58Du, 0x3653u, 0x2672u,
    0x1611u, 0x0630u, 0x76D7u, 0x66F6u, 0x5695u, 0x46B4u, 0xB75Bu, 0xA77Au, 0x9719u, 0x8738u,
    0xF7DFu, 0xE7FEu, 0xD79Du, 0xC7BCu, 0x48C4u, 0x58E5u, 0x6886u, 0x78A7u, 0x0840u, 0x1861u,
    0x2802u, 0x3823u, 0xC9CCu, 0xD9EDu, 0xE98Eu, 0xF9AFu, 0x8948u, 0x9969u, 0xA90Au, 0xB92Bu,
    0x5AF5u, 0x4AD4u, 0x7AB7u, 0x6A96u, 0x1A71u, 0x0A50u, 0x3A33u, 0x2A12u, 0xDBFDu, 0xCBDCu,
    0xFBBFu, 0xEB9Eu, 0x9B79u, 0x8B58u, 0xBB3Bu, 0xAB1Au, 0x6CA6u, 0x7C87u, 0x4CE4u, 0x5CC5u,
    0x2C22u, 0x3C03u, 0x0C60u, 0x1C41u, 0xEDAEu, 0xFD8Fu, 0xCDECu, 0xDDCDu, 0xAD2Au, 0xBD0Bu,
    0x8D68u, 0x9D49u, 0x7E97u, 0x6EB6u, 0x5ED5u, 0x4EF4u, 0x3E13u, 0x2E32u, 0x1E51u, 0x0E70u,
    0xFF9Fu, 0xEFBEu, 0xDFDDu, 0xCFFCu, 0xBF1Bu, 0xAF3Au, 0x9F59u, 0x8F78u, 0x9188u, 0x81A9u,
    0xB1CAu, 0xA1EBu, 0xD10Cu, 0xC12Du, 0xF14Eu, 0xE16Fu, 0x1080u, 0x00A1u, 0x30C2u, 0x20E3u,
    0x5004u, 0x4025u, 0x7046u, 0x6067u, 0x83B9u, 0x9398u, 0xA3FBu, 0xB3DAu, 0xC33Du, 0xD31Cu,
    0xE37Fu, 0xF35Eu, 0x02B1u, 0x1290u, 0x22F3u, 0x32D2u, 0x4235u, 0x5214u, 0x6277u, 0x7256u,
    0xB5EAu, 0xA5CBu, 0x95A8u, 0x8589u, 0xF56Eu, 0xE54Fu, 0xD52Cu, 0xC50Du, 0x34E2u, 0x24C3u,
    0x14A0u, 0x0481u, 0x7466u, 0x6447u, 0x5424u, 0x4405u, 0xA7DBu, 0xB7FAu, 0x8799u, 0x97B8u,
    0xE75Fu, 0xF77Eu, 0xC71Du, 0xD73Cu, 0x26D3u, 0x36F2u, 0x0691u, 0x16B0u, 0x6657u, 0x7676u,
    0x4615u, 0x5634u, 0xD94Cu, 0xC96Du, 0xF90Eu, 0xE92Fu, 0x99C8u, 0x89E9u, 0xB98Au, 0xA9ABu,
    0x5844u, 0x4865u, 0x7806u, 0x6827u, 0x18C0u, 0x08E1u, 0x3882u, 0x28A3u, 0xCB7Du, 0xDB5Cu,
    0xEB3Fu, 0xFB1Eu, 0x8BF9u, 0x9BD8u, 0xABBBu, 0xBB9Au, 0x4A75u, 0x5A54u, 0x6A37u, 0x7A16u,
    0x0AF1u, 0x1AD0u, 0x2AB3u, 0x3A92u, 0xFD2Eu, 0xED0Fu, 0xDD6Cu, 0xCD4Du, 0xBDAAu, 0xAD8Bu,
    0x9DE8u, 0x8DC9u, 0x7C26u, 0x6C07u, 0x5C64u, 0x4C45u, 0x3CA2u, 0x2C83u, 0x1CE0u, 0x0CC1u,
    0xEF1Fu, 0xFF3Eu, 0xCF5Du, 0xDF7Cu, 0xAF9Bu, 0xBFBAu, 0x8FD9u, 0x9FF8u, 0x6E17u, 0x7E36u,
    0x4E55u, 0x5E74u, 0x2E93u, 0x3EB2u, 0x0ED1u, 0x1EF0u};

uint16_t telem_crc16(const uint8_t *data, size_t len)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)((crc << 8) ^ crc16_table[(crc >> 8) ^ data[i]]);
    }
    return crc;
}
#else
static const uint16_t crc16_table[16] = {
    0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u, 0x60C6u, 0x70E7u,
    0x8108u, 0x9129u, 0xA14Au, 0xB16Bu, 0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu,
};

uint16_t telem_crc16(const uint8_t *data, size_t len)
{
    uint16_t crc = 0xFFFFu;
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)((crc << 4) ^ crc16_table[((crc >> 12) ^ (data[i] >> 4)) & 0xFu]);
        crc = (uint16_t)((crc << 4) ^ crc16_table[((crc >> 12) ^ data[i]) & 0xFu]);
    }
    return crc;
}
#endif

/* Header and CRC around a payload already at frame + 4; returns the frame's length. */
static size_t wrap(uint8_t *frame, uint8_t type, size_t len)
{
    frame[0] = TELEM_SYNC0;
    frame[1] = TELEM_SYNC1;
    frame[2] = type;
    frame[3] = (uint8_t)len;
    uint16_t crc = telem_crc16(frame + 2, len + 2u);
    frame[4u + len] = (uint8_t)crc;
    frame[5u + len] = (uint8_t)(crc >> 8);
    return len + 6u;
}

size_t telem_frame(uint8_t *buf, uint8_t type, const uint8_t *payload, uint8_t len)
{
    if (len > 0u) { /* a command without a payload may pass NULL */
        memmove(buf + 4, payload, len);
    }
    return wrap(buf, type, len);
}

void telem_init(telem_t *t)
{
    memset(t, 0, sizeof *t);
    /* The first idle call says hello. */
    t->last_hello_tick = UINT32_MAX - 5u * TELEM_TICKS_PER_S;
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

/* Every frame is built in place: the payload at frame + 4, then the header and the CRC
 * around it, so one buffer of TELEM_FRAME_MAX bytes is the only stack it takes. */
#define PAYLOAD(frame) ((frame) + 4)

static void send(telem_t *t, uint8_t *frame, uint8_t type, size_t len)
{
    size_t n = wrap(frame, type, len);
    if (hal_uart_write(frame, n) != n) {
        t->short_writes++;
    } else {
        t->frames++;
    }
}

static void send_event(telem_t *t, uint8_t *frame, const telem_event_t *e)
{
    uint8_t *p = put32(PAYLOAD(frame), e->ticks);
    if (e->type == TELEM_READING) {
        p = put8(p, e->stop);
        p = put8(p, e->outcome);
        p = put32(p, (uint32_t)e->servo_mdeg);
        p = put32(p, e->range_um);
    }
    p = put32(p, (uint32_t)e->pose.x_um);
    p = put32(p, (uint32_t)e->pose.y_um);
    p = put32(p, e->pose.heading);
    send(t, frame, e->type, (size_t)(p - PAYLOAD(frame)));
}

static void send_hello(telem_t *t, uint8_t *frame, const grid_t *g, const slam_config_t *cfg)
{
    uint8_t *p = put8(PAYLOAD(frame), TELEM_VERSION);
    p = put16(p, g->a_cells);
    p = put16(p, g->b_cells);
    p = put32(p, g->cell_um);
    p = put32(p, (uint32_t)g->origin_x_um);
    p = put32(p, (uint32_t)g->origin_y_um);
    p = put8(p, g->om_max);
    p = put8(p, g->tm_max);
    p = put32(p, cfg->confidence_radius_um);
    p = put32(p, cfg->range_min_um);
    p = put32(p, (uint32_t)cfg->mount_x_um);
    p = put32(p, (uint32_t)cfg->mount_y_um);
    p = put32(p, (uint32_t)cfg->mount_yaw_mdeg);
    p = put8(p, g->mode);
    p = put8(p, g->hit);
    p = put8(p, g->miss);
    send(t, frame, TELEM_HELLO, (size_t)(p - PAYLOAD(frame)));
}

static void send_status(telem_t *t, uint8_t *frame, const telem_status_t *st)
{
    const uint32_t v[10] = {st->ticks,   st->pings,    st->echoes, st->timeouts,
                            st->om_hits, st->overruns, st->saves,  t->dropped + t->short_writes,
                            t->commands, t->refused};
    uint8_t *p = PAYLOAD(frame);
    for (unsigned i = 0; i < 10u; i++) {
        p = put32(p, v[i]);
    }
    p = put8(p, st->explore_mode);
    p = put8(p, st->flags);
    /* Only when there is something to say: a home that fits sends what it always sent. */
    if (st->outside != 0u) {
        p = put32(p, st->outside);
    }
    send(t, frame, TELEM_STATUS, (size_t)(p - PAYLOAD(frame)));
}

/* The cells of the map row segment at (row, first). */
static uint16_t map_row_cells(const telem_t *t, const grid_t *g)
{
    uint16_t n = (uint16_t)(g->a_cells - t->first);
    return n > TELEM_MAP_CELLS ? (uint16_t)TELEM_MAP_CELLS : n;
}

/* The map row segment at (map, row, first): OM then TM, round and round. */
static void send_map_row(telem_t *t, uint8_t *frame, const grid_t *g)
{
    uint16_t n = map_row_cells(t, g);
    const uint8_t *cells =
        (t->map == 0u ? g->om : g->tm) + (uint32_t)t->row * g->a_cells + t->first;
    uint8_t *p = put8(PAYLOAD(frame), t->map);
    p = put16(p, t->row);
    p = put16(p, t->first);
    memcpy(p, cells, n);
    send(t, frame, TELEM_MAP_ROW, 5u + n);
}

/* The segment after, whether the last was sent or not. */
static void next_map_row(telem_t *t, const grid_t *g)
{
    t->first = (uint16_t)(t->first + map_row_cells(t, g));
    if (t->first >= g->a_cells) {
        t->first = 0u;
        if (++t->row >= g->b_cells) {
            t->row = 0u;
            t->map ^= 1u;
        }
    }
}

void telem_map_restart(telem_t *t)
{
    t->map = 0u;
    t->row = 0u;
    t->first = 0u;
    t->hello_due = true;
}

/* Where nothing reads the link (hal_uart_has_reader()), each frame is counted as written,
 * as a UART that takes every byte counts it, and never built: the simulator without a
 * sink spent a tenth of its background loop framing bytes for nobody. */
static bool unheard(telem_t *t, bool heard)
{
    if (!heard) {
        t->frames++;
    }
    return !heard;
}

void telem_idle(telem_t *t, const grid_t *g, const slam_config_t *cfg, const telem_status_t *st,
                uint32_t ticks)
{
    uint8_t frame[TELEM_FRAME_MAX];
    bool heard = hal_uart_has_reader();
    uint8_t tail = t->tail;
    while (tail != __atomic_load_n(&t->head, __ATOMIC_ACQUIRE)) {
        uint8_t slot = tail;
        tail = (uint8_t)((tail + 1u) % TELEM_RING);
        if (unheard(t, heard)) {
            __atomic_store_n(&t->tail, tail, __ATOMIC_RELEASE);
            continue;
        }
        telem_event_t e = t->ring[slot]; /* out before the slot goes back to the tick */
        __atomic_store_n(&t->tail, tail, __ATOMIC_RELEASE);
        send_event(t, frame, &e);
    }
    if (t->hello_due || ticks - t->last_hello_tick >= 5u * TELEM_TICKS_PER_S) {
        t->hello_due = false;
        t->last_hello_tick = ticks;
        if (!unheard(t, heard)) {
            send_hello(t, frame, g, cfg);
        }
    }
    if (ticks - t->last_status_tick >= TELEM_TICKS_PER_S) {
        t->last_status_tick = ticks;
        if (!unheard(t, heard)) {
            send_status(t, frame, st);
        }
    }
    if (ticks - t->last_row_tick >= TELEM_ROW_TICKS) {
        t->last_row_tick = ticks;
        if (!unheard(t, heard)) {
            send_map_row(t, frame, g);
        }
        next_map_row(t, g);
    }
}

/* ---- commands ------------------------------------------------------------------------- */

/* Each key's row of config_fields.h plus one (0: no such key), with KEY_LIVE when SET may
 * change it while the robot runs. The fields are read and written through config.c, which
 * knows where each row lies and how it is stored. */
#define KEY_LIVE 0x80u
#define KEY_FIXED 0x00u
_Static_assert(SLAM_CONFIG_ROWS < KEY_LIVE, "a row number fits below the live bit");

static const uint8_t config_keys[TELEM_CONFIG_KEY_MAX + 1u] = {
#define KEY(name, type, dflt, lo, hi, rule, id, live, words)                                       \
    [id] = (uint8_t)((SLAM_CONFIG_ROW_##name + 1u) | KEY_##live),
    TELEM_CONFIG_KEYS(KEY)
#undef KEY
};

/* The row of a key; -1: no such key. */
static int config_row(uint8_t key)
{
    if (key > TELEM_CONFIG_KEY_MAX || config_keys[key] == 0u) {
        return -1;
    }
    return (int)(config_keys[key] & ~KEY_LIVE) - 1;
}

int telem_config_get(const slam_config_t *cfg, uint8_t key, uint32_t *value)
{
    int row = config_row(key);
    if (row < 0) {
        return -(int)TELEM_ERR_KEY;
    }
    *value = slam_config_field_get(cfg, (unsigned)row);
    return 0;
}

int telem_config_set(slam_config_t *cfg, uint8_t key, uint32_t value)
{
    int row = config_row(key);
    if (row < 0) {
        return -(int)TELEM_ERR_KEY;
    }
    if ((config_keys[key] & KEY_LIVE) == 0u) {
        return -(int)TELEM_ERR_FIXED;
    }
    slam_config_t c = *cfg;
    if (!slam_config_field_set(&c, (unsigned)row, value) || slam_config_check(&c, NULL) != 0) {
        return -(int)TELEM_ERR_RANGE;
    }
    *cfg = c;
    return 0;
}

/* The payload length of each command, from TELEM_CMD_START on. */
static const uint8_t cmd_len[] = {0u, 0u, 1u, 1u, 5u, 0u, 0u, 0u};
#define CMD_FIRST TELEM_CMD_START
#define CMD_COUNT (sizeof cmd_len / sizeof cmd_len[0])

/* A reply: a few bytes of payload, framed and written at once. */
static void reply(telem_t *t, uint8_t type, const uint8_t *payload, uint8_t len)
{
    uint8_t frame[6u + TELEM_CMD_PAYLOAD_MAX];
    memcpy(PAYLOAD(frame), payload, len);
    send(t, frame, type, len);
}

void telem_send_ack(telem_t *t, uint8_t command)
{
    t->commands++;
    reply(t, TELEM_ACK, &command, 1u);
}

void telem_send_error(telem_t *t, uint8_t command, uint8_t code, uint8_t key)
{
    t->refused++;
    const uint8_t p[3] = {command, code, key};
    reply(t, TELEM_ERROR, p, sizeof p);
}

void telem_send_config(telem_t *t, const slam_config_t *cfg, uint8_t key)
{
    uint32_t value = 0u;
    (void)telem_config_get(cfg, key, &value);
    uint8_t p[5];
    put32(put8(p, key), value);
    t->commands++;
    reply(t, TELEM_CONFIG, p, sizeof p);
}

static void rx_drop(telem_t *t, uint8_t n)
{
    t->rx_len = (uint8_t)(t->rx_len - n);
    /* Forward, a byte at a time: the few bytes kept move down over the ones dropped
     * (and the image needs no memmove for them). */
    for (uint8_t i = 0; i < t->rx_len; i++) {
        t->rx[i] = t->rx[i + n];
    }
}

bool telem_rx_byte(telem_t *t, uint8_t byte, uint32_t ticks, telem_cmd_t *cmd)
{
    if (t->rx_len == sizeof t->rx) {
        rx_drop(t, 1u); /* cannot happen: a full buffer is always a whole frame */
    }
    t->rx[t->rx_len++] = byte;
    t->rx_tick = ticks;
    /* Resynchronise on A5 5A; a frame that cannot be a command is refused as soon as its
     * header says so, so the buffer never needs more than the longest command. */
    while (t->rx_len > 0u) {
        if (t->rx[0] != TELEM_SYNC0 || (t->rx_len >= 2u && t->rx[1] != TELEM_SYNC1)) {
            rx_drop(t, 1u);
            continue;
        }
        if (t->rx_len < 4u) {
            return false;
        }
        uint8_t type = t->rx[2];
        uint8_t len = t->rx[3];
        if (len > TELEM_CMD_PAYLOAD_MAX) {
            telem_send_error(t, type, TELEM_ERR_LENGTH, 0u);
            rx_drop(t, 2u);
            continue;
        }
        uint8_t n = (uint8_t)(6u + len);
        if (t->rx_len < n) {
            return false;
        }
        uint16_t crc = (uint16_t)(t->rx[4u + len] | t->rx[5u + len] << 8);
        bool crc_ok = crc == telem_crc16(t->rx + 2, len + 2u);
        telem_cmd_t c = {.type = type, .key = len >= 1u ? t->rx[4] : 0u, .value = 0u};
        if (len == 5u) {
            c.value = (uint32_t)t->rx[5] | (uint32_t)t->rx[6] << 8 | (uint32_t)t->rx[7] << 16 |
                      (uint32_t)t->rx[8] << 24;
        }
        rx_drop(t, n); /* the whole frame: a damaged one must not eat the next command */
        if (!crc_ok) {
            telem_send_error(t, type, TELEM_ERR_CRC, 0u);
        } else if (type < CMD_FIRST || type >= CMD_FIRST + CMD_COUNT) {
            telem_send_error(t, type, TELEM_ERR_COMMAND, 0u);
        } else if (len != cmd_len[type - CMD_FIRST]) {
            telem_send_error(t, type, TELEM_ERR_LENGTH, 0u);
        } else {
            *cmd = c;
            return true;
        }
    }
    return false;
}

void telem_rx_expire(telem_t *t, uint32_t ticks)
{
    if (t->rx_len == 0u || ticks - t->rx_tick < TELEM_RX_TIMEOUT_TICKS) {
        return;
    }
    if (t->rx_len >= 3u) {
        telem_send_error(t, t->rx[2], TELEM_ERR_LENGTH, 0u);
    }
    t->rx_len = 0u; /* a lone sync is noise: nothing to answer */
}
