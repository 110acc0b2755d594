/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What the loaders of .room files (room_load.c) and ROS maps (room_ros.c) share: limits,
 * messages, lines, numbers, bounds. Private to hal/host.
 */
#ifndef HOST_ROOM_PARSE_H
#define HOST_ROOM_PARSE_H

#include <stdbool.h>
#include <stddef.h>

#include "host/sim.h"

/* What a room may be. Every coordinate lies within ROOM_MAX_COORD_M (sim.h) of the
 * origin; files larger than these are refused before they fill the memory. */
#define ROOM_MAX_PIXELS (1u << 26)       /**< 64 Mpx: 8192 x 8192, 410 m at 5 cm */
#define ROOM_TEXT_MAX ((size_t)64 << 20) /**< a .room file: 64 MiB, over 10^6 walls */
#define ROOM_YAML_MAX ((size_t)1 << 20)  /**< a ROS map's .yaml: 1 MiB */
#define ROOM_PGM_MAX ((size_t)128 << 20) /**< a PGM file: 128 MiB */
#define ROOM_MIN_RES_M 0.001             /**< pixels of 1 mm .. 10 m */
#define ROOM_MAX_RES_M 10.0

/** "PATH:LINE: message" (or "PATH: message" for line 0) into err. */
__attribute__((format(printf, 5, 6))) void room_fail(char *err, size_t errlen, const char *path,
                                                     unsigned line, const char *fmt, ...);

/** Text cut into lines, for the loaders. */
typedef struct {
    char *buf; /**< a copy of the text, cut in place */
    size_t len, pos;
    unsigned lineno; /**< the line room_lines_next() gave last, from 1 */
    const char *path;
} room_lines_t;

/** Take a copy of @p len bytes of text to cut; -1 with "PATH: out of memory". */
int room_lines_open(room_lines_t *l, const char *path, const char *text, size_t len, char *err,
                    size_t errlen);

/**
 * The next line, without its newline.
 * @return 1 a line in *line; 0 the end; -1 a NUL byte in it (no text file has one: err
 *         names the line)
 */
int room_lines_next(room_lines_t *l, char **line, char *err, size_t errlen);

/** Free the copy. */
void room_lines_close(room_lines_t *l);

/**
 * A whole token as a real number, by the rule of hal_common/number.h (decimal only).
 * @return 0; -1 not a number; -2 not finite (inf, nan, or beyond a double); -3 beyond
 *         ROOM_MAX_COORD_M. A number too small for a double reads as 0.
 */
int room_parse_number(const char *tok, double *v);

/** Set the bounding box of a room from its geometry. */
void room_bounds(room_t *r);

/** room_load() of a ROS map (room_ros.c). */
int room_load_ros(room_t *out, const char *path, const room_crop_t *crop, char *err, size_t errlen);

#endif /* HOST_ROOM_PARSE_H */
