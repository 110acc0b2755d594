/* SPDX-License-Identifier: MIT */
/* A decoder of telemetry frames for tests, written from the protocol in telemetry.h. */
#ifndef SLAM_TEST_FRAMES_H
#define SLAM_TEST_FRAMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "slam/telemetry.h"

typedef struct {
    uint8_t type;
    uint8_t len;
    uint8_t payload[255];
} frame_t;

/* Finds the next good frame at or after *pos; false at the end of the bytes. Frames
 * whose CRC fails are counted in *bad and skipped. */
static inline bool next_frame(const uint8_t *buf, size_t n, size_t *pos, frame_t *f, unsigned *bad)
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

static inline uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static inline uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

#endif /* SLAM_TEST_FRAMES_H */
