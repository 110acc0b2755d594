/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Telemetry: the robot's pose, its sonar readings and its maps as framed bytes on the
 * UART, for a live viewer (tools/telemetry.py) attached to a robot or to the simulator.
 *
 * The tick only posts small events into a ring (telem_post_*: O(1), no I/O); the
 * background loop frames them and writes them with hal_uart_write(), which never blocks,
 * and adds the maps row by row, a status and a hello (the map geometry) now and then.
 *
 * Frame: A5 5A | type | len | payload (len bytes) | CRC-16/CCITT-FALSE of type, len and
 * payload, low byte first. All payload integers are little-endian.
 *
 *   HELLO   1: version u8, a u16, b u16, cell_um u32, origin_x_um i32, origin_y_um i32,
 *              om_max u8, tm_max u8                                    (19 bytes)
 *   POSE    2: ticks u32, x_um i32, y_um i32, heading u32 (binary angle)  (16 bytes)
 *   READING 3: ticks u32, stop u8, outcome u8 (mapper_outcome_t), servo_mdeg i32,
 *              range_um u32 (0 on a timeout), then the pose of the ping:
 *              x_um i32, y_um i32, heading u32                          (26 bytes)
 *   MAP_ROW 4: map u8 (0 OM, 1 TM), row u16 (b), first u16 (a), then the cells
 *   STATUS  5: ticks, pings, echoes, timeouts, om_hits, tick_overruns, saves,
 *              telemetry drops, each u32                                (32 bytes)
 *
 * A receiver resynchronises on A5 5A and drops frames whose CRC fails; a frame the UART
 * could only take in part is counted (short_writes) and left to that check.
 */
#ifndef SLAM_TELEMETRY_H
#define SLAM_TELEMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "slam/grid.h"
#include "slam/odometry.h"

#define TELEM_SYNC0 0xA5u
#define TELEM_SYNC1 0x5Au
#define TELEM_VERSION 1u
#define TELEM_RING 8u               /**< events the tick may post before idle drains them */
#define TELEM_MAP_CELLS 200u        /**< cells per MAP_ROW frame at most */
#define TELEM_FRAME_MAX (4u + 255u + 2u)

/** Frame types. */
typedef enum {
    TELEM_HELLO = 1,
    TELEM_POSE = 2,
    TELEM_READING = 3,
    TELEM_MAP_ROW = 4,
    TELEM_STATUS = 5,
} telem_type_t;

/** An event posted by the tick. */
typedef struct {
    uint8_t type;       /**< TELEM_POSE or TELEM_READING */
    uint8_t stop;       /**< READING: sweep stop */
    uint8_t outcome;    /**< READING: a mapper_outcome_t */
    uint32_t ticks;
    odom_pose_t pose;   /**< POSE: the pose; READING: the pose of the ping */
    int32_t servo_mdeg; /**< READING */
    uint32_t range_um;  /**< READING; 0 on a timeout */
} telem_event_t;

/** Telemetry state: the event ring and the progress of the map rows. */
typedef struct {
    telem_event_t ring[TELEM_RING];
    uint8_t head;            /**< next slot the tick writes (only the tick changes it) */
    uint8_t tail;            /**< next slot idle reads (only idle changes it) */
    uint8_t map;             /**< the map whose rows are being sent: 0 OM, 1 TM */
    uint16_t row;            /**< the next row to send */
    uint16_t first;          /**< the next cell in that row */
    uint32_t last_row_tick;  /**< when the last map row went out */
    uint32_t last_hello_tick;
    uint32_t last_status_tick;
    uint32_t frames;         /**< frames written */
    uint32_t dropped;        /**< events lost because the ring was full */
    uint32_t short_writes;   /**< frames the UART took only in part */
} telem_t;

/** Counters the STATUS frame reports. */
typedef struct {
    uint32_t ticks, pings, echoes, timeouts, om_hits, overruns, saves;
} telem_status_t;

void telem_init(telem_t *t);

/** Post the pose. ISR-safe, O(1); a full ring drops the event and counts it. */
void telem_post_pose(telem_t *t, uint32_t ticks, const odom_pose_t *pose);

/** Post a completed reading. ISR-safe, O(1). */
void telem_post_reading(telem_t *t, uint32_t ticks, uint8_t stop, uint8_t outcome,
                        int32_t servo_mdeg, uint32_t range_um, const odom_pose_t *ping);

/**
 * Background work: frame and write every posted event, then at most one map row segment
 * (one every TELEM_ROW_TICKS), a STATUS every second and a HELLO every five. Not ISR-safe.
 */
void telem_idle(telem_t *t, const grid_t *g, const telem_status_t *st, uint32_t ticks);

/** Ticks between map row frames (bandwidth: about 6 kB/s with 160-cell rows). */
#define TELEM_ROW_TICKS 3u

/**
 * Build one frame.
 * @param buf  at least TELEM_FRAME_MAX bytes
 * @return the frame length
 */
size_t telem_frame(uint8_t *buf, uint8_t type, const uint8_t *payload, uint8_t len);

/** CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF). */
uint16_t telem_crc16(const uint8_t *data, size_t len);

#endif /* SLAM_TELEMETRY_H */
