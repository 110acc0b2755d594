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
 *
 * One file describes one robot for every program: the core's keys come first, then a
 * program's own keys under a `[section]` line named for it (cfgtext_sections[]:
 * `[linux]` for sonarslam-linux's wiring and devices). A program reads the core's keys
 * and its own section (cfgtext_parse_in()) and skips the others' sections, so the
 * simulator takes the Linux robot's file as it is, and both agree on whose each key is: a
 * core key inside a section, or a program's key before the first section, is an error.
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
int cfgtext_set_raw(slam_config_t *cfg, const char *key, long long raw, char *err, size_t errlen);

/** Lines longer than this (the newline included) are refused. */
#define CFGTEXT_LINE_MAX 512u

/** Configuration files larger than this are refused (1 MiB). */
#define CFGTEXT_FILE_MAX ((size_t)1 << 20)

/** The most core keys there can be (one line number each in cfgtext_where_t). */
#define CFGTEXT_MAX_KEYS 64u

/** Where a file set each core key: the line, or 0 when it did not. */
typedef struct {
    unsigned line[CFGTEXT_MAX_KEYS];
} cfgtext_where_t;

/** The line that set @p key (0: not set, not a core key, or @p w NULL). */
unsigned cfgtext_where_line(const cfgtext_where_t *w, const char *key);

/**
 * What slam_config_check() accepts for a key, in words ("1..255", "400..2600, and not
 * equal to servo_pulse_0deg_us"...), for messages; NULL for an unknown key.
 */
const char *cfgtext_rule(const char *key);

/**
 * The other fields the rule of @p key compares it with ("range_min_um" for
 * confidence_radius_um), space-separated; NULL for none or an unknown key.
 */
const char *cfgtext_partners(const char *key);

/**
 * slam_config_check() with a message that gives the key, its value and its valid range,
 * and the values of the fields its rule compares it with.
 * @param key  out (may be NULL): the first bad key, a static string
 * @return 0, or -1 with err set ("KEY = VALUE is out of its valid range: RULE", then
 *         "(OTHER = VALUE, ...)" when a rule compares it with others)
 */
int cfgtext_check(const slam_config_t *cfg, const char **key, char *err, size_t errlen);

/**
 * A handler for keys that are not slam_config_t fields.
 * @param line  the line of the file that holds the key
 * @return 0 when the key was taken; -1 unknown key; -2 bad value (write a message to err)
 */
typedef int (*cfgtext_other_fn)(void *ctx, const char *key, const char *value, unsigned line,
                                char *err, size_t errlen);

/**
 * Read `key = value` text held in memory on top of @p cfg ('#' starts a comment; blank
 * lines ignored), then check the result with slam_config_check().
 *
 * Refused, naming @p name and the line: a NUL byte, a line of CFGTEXT_LINE_MAX characters
 * or more, a line without '=', an unknown key (unless @p other takes it), a bad value, a
 * core key given twice, an unknown `[section]`, a core key inside a section; and a result
 * slam_config_check() refuses, naming the key, its value, its valid range and the line
 * that set it. The other keys of every known section are skipped (another program's).
 * @param name   the file's name, for messages
 * @param text   @p len bytes (need not end in a NUL)
 * @param other  handler for keys that are not core fields, or NULL (they are errors)
 * @param where  out (may be NULL): the line of every core key the text set
 * @param err    out: on failure "NAME:LINE: message", or "NAME: message"
 * @retval 0   read and valid; cfg holds the result
 * @retval -1  a line is wrong, or the result is invalid; cfg and where are unchanged
 */
int cfgtext_parse(const char *name, const char *text, size_t len, slam_config_t *cfg,
                  cfgtext_other_fn other, void *ctx, cfgtext_where_t *where, char *err,
                  size_t errlen);

/** The section names a file may hold, NULL-terminated: "linux". */
extern const char *const cfgtext_sections[];

/**
 * cfgtext_parse() for a program with a section of its own.
 * @param section  the caller's section (one of cfgtext_sections[]), or NULL for a program
 *                 with none: then every section is skipped, and @p other takes the keys
 *                 before the first section that are not core keys, as cfgtext_parse() does
 * @param other    with a section: the handler of its keys (none given: they are errors);
 *                 keys before the first section are then core keys only
 * Refused besides: an unknown `[section]`, a core key in any section, a key before the
 * first section that is not a core key (the message says where it belongs). The keys of
 * another program's section are skipped, but each line there must still be `key = value`.
 */
int cfgtext_parse_in(const char *name, const char *text, size_t len, const char *section,
                     slam_config_t *cfg, cfgtext_other_fn other, void *ctx, cfgtext_where_t *where,
                     char *err, size_t errlen);

/** cfgtext_parse_in() on a file, as cfgtext_load(). */
int cfgtext_load_in(const char *path, const char *section, slam_config_t *cfg,
                    cfgtext_other_fn other, void *ctx, cfgtext_where_t *where, char *err,
                    size_t errlen);

/**
 * cfgtext_parse() on a file of at most CFGTEXT_FILE_MAX bytes.
 * @retval 0   loaded and valid; cfg holds the result
 * @retval -1  the file could not be read or is too large (err says so), or as
 *             cfgtext_parse(); cfg is unchanged
 */
int cfgtext_load(const char *path, slam_config_t *cfg, cfgtext_other_fn other, void *ctx,
                 cfgtext_where_t *where, char *err, size_t errlen);

/**
 * Open an input file for reading: a regular file only. A directory, a FIFO, a device or a
 * socket is refused, and opening never waits (a FIFO without a writer would block for
 * ever, /dev/zero never ends): every input of these programs is a file read to its end.
 * @return the file, or NULL with "PATH: reason" in err
 */
FILE *cfgtext_open_file(const char *path, char *err, size_t errlen);

/**
 * A whole file into memory, with a NUL after its @p len bytes; refused when it is not a
 * regular file (cfgtext_open_file()) or holds more than @p limit bytes (never reading more
 * than one byte beyond).
 * @return the text (free() it), or NULL with "PATH: reason" in err
 */
char *cfgtext_read_file(const char *path, size_t limit, size_t *len, char *err, size_t errlen);

/** Trim white space at both ends of @p s, in place; returns the new start. */
char *cfgtext_trim(char *s);

/**
 * Make a message that quotes input safe to print: in place, every byte that is not
 * printable ASCII or part of a printable UTF-8 character (control bytes, DEL, C1 controls,
 * broken UTF-8) becomes "\xNN", so a file cannot retitle or drive the terminal that shows
 * its error. The result is cut to fit @p cap bytes with its NUL, at a whole character or
 * escape. Escaping twice changes nothing more. Every message of this library that quotes
 * input is escaped so; the room loaders and host_sim use it for theirs.
 */
void cfgtext_escape(char *s, size_t cap);

#endif /* HAL_COMMON_CONFIG_TEXT_H */
