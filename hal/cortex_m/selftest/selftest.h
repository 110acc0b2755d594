/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The self-test: the firmware's robot_init()/robot_tick() over a recorded scenario through
 * the replay HAL, then a report of OM, TM and the robot's counters. The same file runs on
 * an emulated MCU (selftest_main.c, QEMU) and on the host (tests/stm32f4/host/replay_host.c);
 * their reports up to the `end` line must be byte-identical.
 *
 * Report (text, version 1):
 *
 *     sonarslam-selftest 1
 *     scenario NAME ticks N
 *     grid A B
 *     replay ticks N mismatches M first WHAT|-
 *     robot ticks .. pings .. echoes .. timeouts .. hits .. far .. near .. outside ..
 *           rejected .. ping_errors ..         (one line)
 *     pose X_UM Y_UM HEADING_BAM
 *     uart bytes N crc32 XXXXXXXX              what the firmware wrote to the UART
 *     om crc32 XXXXXXXX bytes A*B
 *     om HEX...                                64 cells a line, row 0 first
 *     tm crc32 XXXXXXXX bytes A*B
 *     tm HEX...
 *     end
 *
 * and, where an instruction counter exists (the MCU), after `end`:
 *
 *     cost nop N
 *     cost ticks N sum S worst W at T
 *     cost HHHH HHHH ...                       robot_tick() instructions, 16 ticks a line
 *
 * The platform supplies selftest_counter() and selftest_print() (on the MCU: the chip's
 * selftest_port.c and selftest_main.c).
 */
#ifndef CM_SELFTEST_H
#define CM_SELFTEST_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/robot.h"

/** A free-running counter: instructions under QEMU -icount (TIM2); 0 on the host. */
uint32_t selftest_counter(void);

/** Print one piece of the report (no newline added). */
void selftest_print(const char *s);

/** A self-test run. */
typedef struct {
    robot_t *robot;
    bool started;              /**< robot_init() accepted the scenario's configuration */
    bool done;                 /**< every tick replayed (or the stream was corrupt) */
    uint32_t nop_cost;         /**< counter delta of measuring an empty function */
    uint32_t cost_sum;         /**< robot_tick() instructions, summed (saturating) */
    uint32_t cost_worst;       /**< the most of one tick */
    uint32_t worst_tick;       /**< which tick (0-based) */
    uint16_t *costs;           /**< per tick, saturated at 65535; may be NULL */
    uint32_t costs_max;        /**< entries in costs */
    uint32_t idle_worst;       /**< the most of one robot_idle() call (selftest_idle()) */
    uint32_t idle_worst_after; /**< the ticks replayed before that call */
} selftest_t;

/**
 * Start the scenario compiled in (replay_scenario): robot_init() with its configuration.
 * @param costs, costs_max  where to keep each tick's cost (NULL, 0: nowhere)
 * @retval 0   ready: call selftest_step() per tick until selftest_done()
 * @retval -1  robot_init() refused the recorded configuration
 */
int selftest_begin(selftest_t *st, robot_t *r, uint16_t *costs, uint32_t costs_max);

/** One tick: decode, robot_tick() (measured), check; a hal_tick_fn. Nothing once done. */
void selftest_step(void *ctx);

/** Whether the scenario has been played to its end. */
bool selftest_done(const selftest_t *st);

/** Whether the run passed: configuration accepted, stream intact, no mismatch. */
bool selftest_passed(const selftest_t *st);

/** Print the report; with_costs adds the instruction counts after `end`. */
void selftest_report(const selftest_t *st, bool with_costs);

/** robot_idle(), measured: the platform's background loop calls this instead. */
void selftest_idle(selftest_t *st);

/**
 * After the report: what one reading costs the mapper (mapper_reading(), free-space rays
 * included), measured over readings of every stop at every 15° of heading, inside the
 * confidence sector just short of rc (the longest ray with a hit) and beyond it (a ray to
 * rc); printed as `cost reading worst W mean M`. Writes into the robot's maps.
 */
void selftest_reading_costs(selftest_t *st);

#endif /* CM_SELFTEST_H */
