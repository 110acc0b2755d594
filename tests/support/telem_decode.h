/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The payloads of telemetry frames unpacked by type, written from the protocol in
 * slam/telemetry.h, for the tests and the fuzzer; test_frames.h finds the frames.
 */
#ifndef SLAM_TEST_TELEM_DECODE_H
#define SLAM_TEST_TELEM_DECODE_H

#include <stdint.h>

#include "test_frames.h"

/** A frame's payload, unpacked; the fields of its type are set, the others zero. */
typedef struct {
    uint8_t type;
    /* HELLO */
    uint8_t version, om_max, tm_max, om_mode, om_hit, om_miss;
    uint16_t a, b;
    uint32_t cell_um, confidence_radius_um, range_min_um;
    int32_t origin_x_um, origin_y_um, mount_x_um, mount_y_um, mount_yaw_mdeg;
    /* POSE and READING */
    uint32_t ticks;
    int32_t x_um, y_um;
    uint32_t heading;
    uint8_t stop, outcome;
    int32_t servo_mdeg;
    uint32_t range_um;
    /* MAP_ROW: ncells cells of map (0 OM, 1 TM) from (first, row), inside the frame */
    uint8_t map;
    uint16_t row, first;
    uint8_t ncells;
    const uint8_t *cells;
    /* STATUS: ticks, pings, echoes, timeouts, om_hits, overruns, saves, drops, commands
     * taken, commands refused; then the explore mode and the flags, and the points
     * outside the grid (0 when the frame has none) */
    uint32_t status[10];
    uint8_t explore_mode, flags;
    uint32_t outside;
    /* ACK, ERROR, CONFIG */
    uint8_t command, code, key;
    uint32_t value;
} tdec_msg_t;

/**
 * Unpack a frame's payload.
 * @retval 0   unpacked
 * @retval -1  an unknown type
 * @retval -2  a length that is not its type's (a MAP_ROW: 5 bytes and at most 200 cells)
 * @retval -3  a value no robot sends (a MAP_ROW's map other than 0 or 1, a HELLO of a
 *             grid of no cells)
 */
int tdec_decode(const frame_t *f, tdec_msg_t *m);

#endif /* SLAM_TEST_TELEM_DECODE_H */
