/* SPDX-License-Identifier: MIT */
/**
 * @file
 * One tick of a HAL trace (trace.h describes the fields). Apart from trace.h because the
 * MCU's replay HAL decodes the same record and has no stdio.
 */
#ifndef HAL_COMMON_TRACE_TICK_H
#define HAL_COMMON_TRACE_TICK_H

#include <stdint.h>

/** One tick of a trace. */
typedef struct {
    uint16_t enc[2];
    char poll; /**< '-', 'i', 'b', 'e' or 't' */
    uint32_t echo_us;
    char trig; /**< '-', 'o' or 'b' */
    int16_t duty[2];
    uint16_t servo_us;
} trace_tick_t;

#endif /* HAL_COMMON_TRACE_TICK_H */
