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
 *              om_max u8, tm_max u8, then what a replay of the readings needs:
 *              confidence_radius_um u32, range_min_um u32, mount_x_um i32,
 *              mount_y_um i32, mount_yaw_mdeg i32, then what an OM cell holds:
 *              om_mode u8, om_hit u8, om_miss u8 (grid.h)               (42 bytes)
 *   POSE    2: ticks u32, x_um i32, y_um i32, heading u32 (binary angle)  (16 bytes)
 *   READING 3: ticks u32, stop u8, outcome u8 (mapper_outcome_t), servo_mdeg i32,
 *              range_um u32 (0 on a timeout), then the pose of the ping:
 *              x_um i32, y_um i32, heading u32                          (26 bytes)
 *   MAP_ROW 4: map u8 (0 OM, 1 TM), row u16 (b), first u16 (a), then the cells
 *   STATUS  5: ticks, pings, echoes, timeouts, om_hits, tick_overruns, saves,
 *              telemetry drops, commands taken, commands refused, each u32; then
 *              explore_mode u8, flags u8 (TELEM_FLAG_*)                 (42 bytes)
 *              and, once any point has fallen outside the grid (the home does not
 *              fit: grid_t.rejected), that count, outside u32           (46 bytes)
 *   ACK     6: command u8: a command was taken                          (1 byte)
 *   ERROR   7: command u8 (the type received), code u8 (telem_error_t), key u8 (GET and
 *              SET; else 0): a command was refused and changed nothing  (3 bytes)
 *   CONFIG  8: key u8, value u32: a configuration value in force, the answer to GET
 *              and to SET                                               (5 bytes)
 *
 * Commands come the other way, framed the same way, and are parsed by the background
 * loop (never the tick). Each is answered: ACK, CONFIG or ERROR.
 *
 *   START     0x10: (no payload) drive again after STOP
 *   STOP      0x11: (none) stand still; the sweep goes on mapping
 *   MODE      0x12: explore_mode u8; exploration restarts from the pose where it stands
 *   GET       0x13: key u8 (TELEM_CONFIG_KEYS)
 *   SET       0x14: key u8, value u32 (two's complement for a signed field); checked with
 *                   the whole configuration, applied once the robot stands
 *   SAVE      0x15: (none) save the maps now
 *   SEND_MAP  0x16: (none) a HELLO, then OM and TM again from their first row
 *   CALIBRATE 0x17: (none) the calibration run (robot.h), from where the robot stands
 *
 * A receiver resynchronises on A5 5A and drops frames whose CRC fails; a frame the UART
 * could only take in part is counted (short_writes) and left to that check. A command
 * with a bad CRC, a length other than its own, an unknown type, an unknown key or a value
 * out of range is answered with ERROR and changes nothing; so is a frame that stops
 * arriving for TELEM_RX_TIMEOUT_TICKS before it is complete.
 */
#ifndef SLAM_TELEMETRY_H
#define SLAM_TELEMETRY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/config_fields.h"
#include "slam/grid.h"
#include "slam/odometry.h"

#define TELEM_SYNC0 0xA5u
#define TELEM_SYNC1 0x5Au
#define TELEM_VERSION 3u
#define TELEM_RING 8u        /**< events the tick may post before idle drains them */
#define TELEM_MAP_CELLS 200u /**< cells per MAP_ROW frame at most */
#define TELEM_FRAME_MAX (4u + 255u + 2u)

/** Frame types. */
typedef enum {
    TELEM_HELLO = 1,
    TELEM_POSE = 2,
    TELEM_READING = 3,
    TELEM_MAP_ROW = 4,
    TELEM_STATUS = 5,
    TELEM_ACK = 6,
    TELEM_ERROR = 7,
    TELEM_CONFIG = 8,
} telem_type_t;

/** Command types (host to robot). */
typedef enum {
    TELEM_CMD_START = 0x10,
    TELEM_CMD_STOP = 0x11,
    TELEM_CMD_MODE = 0x12,
    TELEM_CMD_GET = 0x13,
    TELEM_CMD_SET = 0x14,
    TELEM_CMD_SAVE = 0x15,
    TELEM_CMD_SEND_MAP = 0x16,
    TELEM_CMD_CALIBRATE = 0x17,
} telem_cmd_type_t;

/** Why a command was refused (the code of an ERROR frame). */
typedef enum {
    TELEM_ERR_CRC = 1,         /**< the CRC does not match */
    TELEM_ERR_LENGTH = 2,      /**< the length is not the command's, or the frame ended early */
    TELEM_ERR_COMMAND = 3,     /**< no such command */
    TELEM_ERR_KEY = 4,         /**< no such configuration key */
    TELEM_ERR_RANGE = 5,       /**< the value is out of range: the configuration would not
                                    pass slam_config_check() */
    TELEM_ERR_FIXED = 6,       /**< the key takes effect only at start (grid, sweep, start pose) */
    TELEM_ERR_UNSUPPORTED = 7, /**< not on this robot (SAVE without storage) */
} telem_error_t;

/** STATUS flags. */
#define TELEM_FLAG_STOPPED 0x01u /**< STOP is in force */
#define TELEM_FLAG_PENDING 0x02u /**< a command waits for the robot to stand */
#define TELEM_FLAG_EXPLORED                                                                        \
    0x04u /**< the exploration is done: it found no frontier it could                              \
               reach, and stands (explore_explored()) */

#define TELEM_CMD_PAYLOAD_MAX 5u /**< SET: key, value */
#define TELEM_CMD_FRAME_MAX (6u + TELEM_CMD_PAYLOAD_MAX)
#define TELEM_RX_TIMEOUT_TICKS 20u /**< a command frame incomplete this long is refused */

/**
 * The configuration keys GET and SET address: the rows of config_fields.h,
 * X(name, type, default, lo, hi, rule, id, live, words), of which the keys use the field
 * (name), how it is stored (type: a Q30 factor travels as its raw I32), the key (id) and
 * whether SET may change it while the robot runs (live: LIVE, or FIXED for a key that
 * takes effect only at robot_init(), which SET refuses with TELEM_ERR_FIXED). The ids are
 * the protocol: never renumber one; a new field's row gives it a new one.
 */
#define TELEM_CONFIG_KEYS(X) SLAM_CONFIG_FIELDS(X)

/** The highest key id. */
#define TELEM_CONFIG_KEY_MAX SLAM_CONFIG_ID_MAX
/** Keys the robot itself sets: MODE and CALIBRATE set explore_mode; a new explore_seed
 *  restarts the exploration's random stream. */
#define TELEM_KEY_EXPLORE_MODE ((uint8_t)SLAM_CONFIG_ID_explore_mode)
#define TELEM_KEY_EXPLORE_SEED ((uint8_t)SLAM_CONFIG_ID_explore_seed)

/** An event posted by the tick. */
typedef struct {
    uint8_t type;    /**< TELEM_POSE or TELEM_READING */
    uint8_t stop;    /**< READING: sweep stop */
    uint8_t outcome; /**< READING: a mapper_outcome_t */
    uint32_t ticks;
    odom_pose_t pose;   /**< POSE: the pose; READING: the pose of the ping */
    int32_t servo_mdeg; /**< READING */
    uint32_t range_um;  /**< READING; 0 on a timeout */
} telem_event_t;

/** A command as received: its type and, for MODE, GET and SET, its key and value. */
typedef struct {
    uint8_t type;   /**< a telem_cmd_type_t */
    uint8_t key;    /**< GET, SET: the key; MODE: the mode */
    uint32_t value; /**< SET: the value */
} telem_cmd_t;

/** Telemetry state: the event ring, the progress of the map rows, the command parser. */
typedef struct {
    telem_event_t ring[TELEM_RING];
    uint8_t head;           /**< next slot the tick writes (only the tick changes it) */
    uint8_t tail;           /**< next slot idle reads (only idle changes it) */
    uint8_t map;            /**< the map whose rows are being sent: 0 OM, 1 TM */
    uint16_t row;           /**< the next row to send */
    uint16_t first;         /**< the next cell in that row */
    uint32_t last_row_tick; /**< when the last map row went out */
    uint32_t last_hello_tick;
    uint32_t last_status_tick;
    bool hello_due;                  /**< SEND_MAP: a HELLO at the next telem_idle() */
    uint32_t frames;                 /**< frames written */
    uint32_t dropped;                /**< events lost because the ring was full */
    uint32_t short_writes;           /**< frames the UART took only in part */
    uint8_t rx[TELEM_CMD_FRAME_MAX]; /**< a command frame being received */
    uint8_t rx_len;                  /**< its bytes so far */
    uint32_t rx_tick;                /**< when its last byte came */
    uint32_t commands;               /**< commands taken */
    uint32_t refused;                /**< commands refused (ERROR frames sent) */
} telem_t;

/** What the STATUS frame reports besides the telemetry's own counters. */
typedef struct {
    uint32_t ticks, pings, echoes, timeouts, om_hits, overruns, saves;
    uint8_t explore_mode;
    uint8_t flags;    /**< TELEM_FLAG_* */
    uint32_t outside; /**< points that fell outside the grid (grid_t.rejected) */
} telem_status_t;

void telem_init(telem_t *t);

/** Post the pose. ISR-safe, O(1); a full ring drops the event and counts it. */
void telem_post_pose(telem_t *t, uint32_t ticks, const odom_pose_t *pose);

/** Post a completed reading. ISR-safe, O(1). */
void telem_post_reading(telem_t *t, uint32_t ticks, uint8_t stop, uint8_t outcome,
                        int32_t servo_mdeg, uint32_t range_um, const odom_pose_t *ping);

/**
 * Background work: frame and write every posted event, then at most one map row segment
 * (one every TELEM_ROW_TICKS), a STATUS every second and a HELLO every five. Where nothing
 * reads the UART (hal_uart_has_reader()) the same frames are only counted, as written, and
 * the map rows move on as if sent. Not ISR-safe.
 * @param cfg  the configuration in force (HELLO carries the sonar's part of it)
 */
void telem_idle(telem_t *t, const grid_t *g, const slam_config_t *cfg, const telem_status_t *st,
                uint32_t ticks);

/** SEND_MAP: a HELLO at the next telem_idle(), then the map rows from OM's first row. */
void telem_map_restart(telem_t *t);

/* ---- commands (background loop only) -------------------------------------------------- */

/**
 * Take one received byte. A frame with a bad CRC, a wrong length or an unknown type is
 * answered with ERROR here and dropped.
 * @param ticks  the tick count now (for TELEM_RX_TIMEOUT_TICKS)
 * @param cmd    out: the command, when one is complete
 * @return true when @p cmd holds a complete, well-formed command
 */
bool telem_rx_byte(telem_t *t, uint8_t byte, uint32_t ticks, telem_cmd_t *cmd);

/** Refuse (ERROR, TELEM_ERR_LENGTH) a command frame no byte has come for in
 *  TELEM_RX_TIMEOUT_TICKS. */
void telem_rx_expire(telem_t *t, uint32_t ticks);

/** Answer a command: ACK. */
void telem_send_ack(telem_t *t, uint8_t command);

/** Refuse a command: ERROR with a telem_error_t and the key (0 when none). */
void telem_send_error(telem_t *t, uint8_t command, uint8_t code, uint8_t key);

/** Answer GET or SET: CONFIG with the value of @p key in @p cfg (a known key). */
void telem_send_config(telem_t *t, const slam_config_t *cfg, uint8_t key);

/**
 * A configuration value by key id, widened to 32 bits (sign-extended when signed).
 * @retval 0               *value holds it
 * @retval -TELEM_ERR_KEY  no such key
 */
int telem_config_get(const slam_config_t *cfg, uint8_t key, uint32_t *value);

/**
 * Set one configuration value by key id, keeping the configuration valid.
 * @retval 0                   set; @p cfg passes slam_config_check()
 * @retval -TELEM_ERR_KEY      no such key
 * @retval -TELEM_ERR_FIXED    the key takes effect only at robot_init()
 * @retval -TELEM_ERR_RANGE    the value does not fit the field, or the configuration
 *                             would fail slam_config_check()
 * On error @p cfg is unchanged.
 */
int telem_config_set(slam_config_t *cfg, uint8_t key, uint32_t value);

/** Ticks between map row frames (bandwidth: about 6 kB/s with 160-cell rows). */
#define TELEM_ROW_TICKS 3u

/**
 * Build one frame.
 * @param buf      at least TELEM_FRAME_MAX bytes
 * @param payload  len bytes (may be NULL when len is 0); it may lie at buf + 4
 * @return the frame length
 */
size_t telem_frame(uint8_t *buf, uint8_t type, const uint8_t *payload, uint8_t len);

/** CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF). */
uint16_t telem_crc16(const uint8_t *data, size_t len);

#endif /* SLAM_TELEMETRY_H */
