/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The one rule for numbers written as text, for every reader of the programs that run on
 * an operating system: room files and ROS maps, configurations (--config, --calibration,
 * robot.conf), readings.csv, --commands files, the command lines of host_sim and
 * sonarslam-linux. tools/slamtools/link.py's parse_int() and parse_real() are the same rule in
 * Python, and tests/test_number.c holds both to one table of cases.
 *
 * Numbers are decimal, and a number is the whole of its text:
 *
 *   whole number   [+-]?[0-9]+                                  "42", "-7", "+007"
 *   real number    [+-]?([0-9]+(.[0-9]*)?|.[0-9]+)([eE][+-]?[0-9]+)?
 *                                                               "0.5", "-.5", "5.", "1e-3"
 *
 * Nothing else is a number: no hexadecimal ("0x10", the C library's and Python's int(x, 0)
 * would read 16), no "inf" or "nan", no digit separators ("1_000"), no white space before
 * or after it (a format that separates values with blanks, a room file's line or a
 * configuration's `key = value`, strips its blanks before a value is read; " 5" given
 * whole, as `--set key=' 5'` or `--duration ' 5'`, is refused). A real number whose
 * magnitude overflows a double is out of range; one too small for a double reads as 0.
 */
#ifndef HAL_COMMON_NUMBER_H
#define HAL_COMMON_NUMBER_H

#include <stdint.h>

/** What a reader found. */
typedef enum {
    NUM_OK = 0,     /**< a number within the range; stored */
    NUM_BAD = -1,   /**< not a number by the rule above */
    NUM_RANGE = -2, /**< a number, outside the range asked for */
} num_status_t;

/**
 * A whole number within [lo, hi].
 * @param out  set only with NUM_OK
 */
num_status_t num_int(const char *s, long long lo, long long hi, long long *out);

/** A whole number >= 0 within [lo, hi] (up to 2^64 - 1, which long long cannot hold). */
num_status_t num_uint(const char *s, unsigned long long lo, unsigned long long hi,
                      unsigned long long *out);

/**
 * A real number within [lo, hi] (a whole number is one too).
 * @param out  set only with NUM_OK
 */
num_status_t num_real(const char *s, double lo, double hi, double *out);

/** Whether @p s is a real number by the rule (whatever its size). */
int num_is_real(const char *s);

#endif /* HAL_COMMON_NUMBER_H */
