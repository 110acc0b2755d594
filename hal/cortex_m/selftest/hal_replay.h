/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The replay HAL: plays a recorded HAL trace back to the firmware, tick by tick, and
 * checks what the firmware does against the record.
 *
 * It implements the HAL calls robot_tick() makes (encoders, sonar poll and trigger: played
 * back; motors and servo: checked) from a scenario compiled into the program, so the same
 * file builds for the MCU and for the host and both run the same ticks. The calls a trace
 * does not record answer the same way on both: hal_time_us() is replay time (10 ms a
 * decoded tick), hal_uart_write() takes every byte and keeps a count and a CRC-32 of them,
 * and hal_uart_read(), map storage and the bump switches are the defaults of hal/defaults
 * (nothing received, no storage: HAL_ENOSYS, no switches), so a program links this file
 * with hal_unsupported. A trace records the paper's servo and sonar (instance 0): the
 * replay has one of each, and answers HAL_EINVAL for any other instance. A scenario
 * is a trace turned into C data by tools/cortex_m.py trace2c; its byte stream, per tick:
 *
 *   byte     bits 0-2 poll ('-' 'i' 'b' 'e' 't' = 0..4), bits 3-4 trigger ('-' 'o' 'b'
 *            = 0..2), bit 5: an output changed; bits 6-7 zero
 *   varint   zigzag of the left encoder's change (mod 2^16) since the previous tick
 *   varint   zigzag of the right encoder's change
 *   varint   echo width in µs, only when poll is 'e'
 *   byte     when an output changed: bit 0 left duty, bit 1 right duty, bit 2 servo;
 *            then for each bit set, in that order, a varint: zigzag duty or servo µs
 *
 * Varints are LEB128 (7 bits a byte, low first, at most 5 bytes). Before the first tick
 * the encoders read 0 and the outputs are 0, as in the recording.
 *
 * Not thread-safe; one replay at a time. Every call is O(1).
 */
#ifndef CM_HAL_REPLAY_H
#define CM_HAL_REPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_common/trace_tick.h"
#include "slam/config.h"

/** A recorded scenario, as trace2c.py generates it. */
typedef struct {
    const char *name;                   /**< the trace's file name, without .trace */
    uint32_t ticks;                     /**< ticks in the stream */
    const uint8_t *stream;              /**< the encoded ticks */
    size_t stream_len;                  /**< bytes in the stream */
    void (*config)(slam_config_t *cfg); /**< the recorded configuration */
} replay_scenario_t;

/** The scenario compiled into this program (the generated file defines it). */
extern const replay_scenario_t replay_scenario;

/** What went wrong first, for the report. */
typedef enum {
    REPLAY_MISMATCH_NONE = 0,
    REPLAY_MISMATCH_POLL,    /**< hal_sonar_poll() called when not recorded, or not called */
    REPLAY_MISMATCH_TRIGGER, /**< hal_sonar_trigger() likewise */
    REPLAY_MISMATCH_DUTY_L,  /**< left motor duty after the tick */
    REPLAY_MISMATCH_DUTY_R,  /**< right motor duty after the tick */
    REPLAY_MISMATCH_SERVO,   /**< servo pulse after the tick */
} replay_mismatch_t;

/** Progress and findings of a replay. */
typedef struct {
    uint32_t ticks;          /**< ticks decoded so far */
    uint32_t mismatches;     /**< outputs or calls that differ from the record */
    uint32_t first_tick;     /**< tick of the first mismatch (0-based) */
    replay_mismatch_t first; /**< what it was */
    int32_t first_expected;  /**< recorded value (calls: 1 called, 0 not) */
    int32_t first_got;       /**< what the firmware did */
    bool corrupt;            /**< the stream did not decode */
    uint32_t uart_bytes;     /**< bytes the firmware wrote to the UART */
    uint32_t uart_crc32;     /**< their CRC-32 (IEEE 802.3) */
} replay_status_t;

/** Start a scenario from its first tick; forgets the previous one. */
void replay_start(const replay_scenario_t *sc);

/**
 * Decode the next tick: the HAL calls of the next robot_tick() answer from it.
 * @param out  the decoded tick (may be NULL)
 * @retval 0   a tick is ready
 * @retval -1  the scenario has no more ticks (and its stream ended exactly there)
 * @retval -2  the stream is corrupt (status().corrupt is set)
 */
int replay_next(trace_tick_t *out);

/** After robot_tick(): compare the calls and outputs with the record, count mismatches. */
void replay_check(void);

/** Where the replay stands. */
replay_status_t replay_status(void);

#endif /* CM_HAL_REPLAY_H */
