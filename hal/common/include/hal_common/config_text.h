/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The core's configuration as text: `key = value` lines, for the programs that run on an
 * operating system (the simulator, the Linux robot program, tools).
 *
 * Keys are the field names of `slam_config_t`. Values are decimal integers; the UMBmark
 * factors (cal_left, cal_right, cal_base) are decimal fractions such as 0.9901. A file
 * may hold other keys (a backend's pins, say): the loader hands those to a callback.
 * Range checks are slam_config_check()'s; this layer checks syntax and type limits.
 */
#ifndef HAL_COMMON_CONFIG_TEXT_H
#define HAL_COMMON_CONFIG_TEXT_H

#include <stddef.h>
#include <stdio.h>

#include "slam/config.h"

/**
 * Set one field from its text.
 * @param err, errlen  out: on failure, a message naming the key and the problem
 * @retval 0   set
 * @retval -1  unknown key (err says so; cfg unchanged)
 * @retval -2  bad value: not a number, trailing junk, or beyond the field's type (cfg unchanged)
 */
int cfgtext_set(slam_config_t *cfg, const char *key, const char *value, char *err, size_t errlen);

/** Write every field as `key = value` lines that cfgtext_set() reads back exactly. */
void cfgtext_write(FILE *f, const slam_config_t *cfg);

/**
 * Write every field as `PREFIXkey raw` lines with the raw integer of each field (Q30
 * factors as their integer too): a form a generator can turn into a C initialiser.
 */
void cfgtext_write_raw(FILE *f, const slam_config_t *cfg, const char *prefix);

/**
 * Set one field from its raw integer, as cfgtext_write_raw() wrote it.
 * @retval 0 set; -1 unknown key; -2 the value does not fit the field (cfg unchanged)
 */
int cfgtext_set_raw(slam_config_t *cfg, const char *key, long long raw, char *err,
                    size_t errlen);

/**
 * A handler for keys that are not slam_config_t fields.
 * @return 0 when the key was taken; -1 unknown key; -2 bad value (write a message to err)
 */
typedef int (*cfgtext_other_fn)(void *ctx, const char *key, const char *value, char *err,
                                size_t errlen);

/**
 * Read a `key = value` file on top of @p cfg ('#' starts a comment; blank lines ignored),
 * then check the result with slam_config_check().
 * @param other  handler for keys that are not core fields, or NULL (they are errors)
 * @param err    out: on failure "FILE:LINE: message", or "FILE: message"
 * @retval 0   loaded and valid; cfg holds the result
 * @retval -1  the file could not be read, or a line is wrong, or the result is invalid;
 *             cfg is unchanged
 */
int cfgtext_load(const char *path, slam_config_t *cfg, cfgtext_other_fn other, void *ctx,
                 char *err, size_t errlen);

/** Trim white space at both ends of @p s, in place; returns the new start. */
char *cfgtext_trim(char *s);

#endif /* HAL_COMMON_CONFIG_TEXT_H */
