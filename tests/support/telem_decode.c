/* SPDX-License-Identifier: MIT */
/* The payloads of telemetry frames unpacked by type, from the protocol in slam/telemetry.h. */
#include "telem_decode.h"

#include <stdbool.h>
#include <string.h>

#include "slam/telemetry.h"

/* The payload length of each frame type the robot sends; 0 for one it does not. */
static uint8_t length_of(uint8_t type)
{
    switch (type) {
    case TELEM_HELLO:
        return 42u;
    case TELEM_POSE:
        return 16u;
    case TELEM_READING:
        return 26u;
    case TELEM_STATUS:
        return 42u;
    case TELEM_ACK:
        return 1u;
    case TELEM_ERROR:
        return 3u;
    case TELEM_CONFIG:
        return 5u;
    default:
        return 0u;
    }
}

int tdec_decode(const frame_t *f, tdec_msg_t *m)
{
    memset(m, 0, sizeof *m);
    m->type = f->type;
    const uint8_t *p = f->payload;
    if (f->type == TELEM_MAP_ROW) {
        if (f->len < 5u || f->len > 5u + TELEM_MAP_CELLS) {
            return -2;
        }
        m->map = p[0];
        m->row = get16(p + 1);
        m->first = get16(p + 3);
        m->ncells = (uint8_t)(f->len - 5u);
        m->cells = f->payload + 5;
        return m->map > 1u ? -3 : 0;
    }
    uint8_t want = length_of(f->type);
    if (want == 0u) {
        return -1;
    }
    /* A STATUS carries the points outside the grid in 4 bytes more once there are any. */
    if (f->len != want && !(f->type == TELEM_STATUS && f->len == want + 4u)) {
        return -2;
    }
    switch (f->type) {
    case TELEM_HELLO:
        m->version = p[0];
        m->a = get16(p + 1);
        m->b = get16(p + 3);
        m->cell_um = get32(p + 5);
        m->origin_x_um = (int32_t)get32(p + 9);
        m->origin_y_um = (int32_t)get32(p + 13);
        m->om_max = p[17];
        m->tm_max = p[18];
        m->confidence_radius_um = get32(p + 19);
        m->range_min_um = get32(p + 23);
        m->mount_x_um = (int32_t)get32(p + 27);
        m->mount_y_um = (int32_t)get32(p + 31);
        m->mount_yaw_mdeg = (int32_t)get32(p + 35);
        m->om_mode = p[39];
        m->om_hit = p[40];
        m->om_miss = p[41];
        return m->a == 0u || m->b == 0u ? -3 : 0;
    case TELEM_POSE:
    case TELEM_READING: {
        bool reading = f->type == TELEM_READING;
        m->ticks = get32(p);
        p += 4;
        if (reading) {
            m->stop = p[0];
            m->outcome = p[1];
            m->servo_mdeg = (int32_t)get32(p + 2);
            m->range_um = get32(p + 6);
            p += 10;
        }
        m->x_um = (int32_t)get32(p);
        m->y_um = (int32_t)get32(p + 4);
        m->heading = get32(p + 8);
        return 0;
    }
    case TELEM_STATUS:
        for (unsigned i = 0; i < 10u; i++) {
            m->status[i] = get32(p + 4u * i);
        }
        m->explore_mode = p[40];
        m->flags = p[41];
        m->outside = f->len > 42u ? get32(p + 42) : 0u;
        return 0;
    case TELEM_ACK:
        m->command = p[0];
        return 0;
    case TELEM_ERROR:
        m->command = p[0];
        m->code = p[1];
        m->key = p[2];
        return 0;
    default: /* TELEM_CONFIG */
        m->key = p[0];
        m->value = get32(p + 1);
        return 0;
    }
}
