/* SPDX-License-Identifier: MIT */
/**
 * @file
 * HAL traces: what the firmware saw and did at the HAL, tick by tick, so a run can be
 * replayed on another machine (an emulated MCU) and its maps compared byte for byte.
 *
 * Format (text, version 1):
 *
 *     sonarslam-trace 1
 *     config <key> <raw>          one line per slam_config_t field (cfgtext_write_raw)
 *     tick <enc_l> <enc_r> <poll> <echo_us> <trig> <duty_l> <duty_r> <servo_us>
 *     ...                         one line per robot_tick(), in order
 *     end <ticks>
 *
 * Inputs, which a replay HAL plays back:
 *   enc_l, enc_r  the 16-bit encoder counters hal_encoder_count() returned in the tick
 *   poll          what hal_sonar_poll() of sonar 0 returned: '-' not called, 'i' idle,
 *                 'b' busy, 'e' echo, 't' timeout
 *   echo_us       the echo width returned with 'e' (0 otherwise)
 *   trig          hal_sonar_trigger() of sonar 0: '-' not called, 'o' HAL_OK, 'b' HAL_EBUSY
 * Outputs, which a replay checks:
 *   duty_l, duty_r  the motor duties in force after the tick
 *   servo_us        the pulse of servo 0 in force after the tick
 *
 * Version 1 records the paper's servo and sonar (HAL instance 0), the only ones the firmware
 * uses, and no bump switch: a firmware that uses another instance or the switches needs a
 * version 2 whose tick lines carry them (the replay HAL answers HAL_EINVAL for any other
 * instance and "no switches", so such a trace would not replay; the host HAL warns when it
 * records one).
 */
#ifndef HAL_COMMON_TRACE_H
#define HAL_COMMON_TRACE_H

#include <stdint.h>
#include <stdio.h>

#include "hal_common/trace_tick.h"
#include "slam/config.h"

/** Write the header: the version line and the configuration. */
void trace_write_header(FILE *f, const slam_config_t *cfg);

/** Write one tick line. */
void trace_write_tick(FILE *f, const trace_tick_t *t);

/** Write the end line. */
void trace_write_end(FILE *f, uint64_t ticks);

/**
 * Read a whole trace.
 * @param cfg    out: the configuration (starting from the defaults)
 * @param ticks  out: a malloc'd array of *n ticks (free it)
 * @param err    out: on failure "FILE:LINE: message"
 * @return 0, or -1 with nothing allocated
 */
int trace_read(const char *path, slam_config_t *cfg, trace_tick_t **ticks, size_t *n, char *err,
               size_t errlen);

#endif /* HAL_COMMON_TRACE_H */
