/* SPDX-License-Identifier: MIT */
/* Reading a readings.csv: the header's columns by name, then every row checked field by field. */
#define _POSIX_C_SOURCE 200809L /* getline */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "hal_common/number.h"
#include "host_sim.h"

#define READINGS_LINE_MAX 512u

/* The columns a replay needs, in this order, found by name in the header: a log may
 * carry more (the simulator's truth) or order them differently. */
enum { CSV_T, CSV_SERVO, CSV_RANGE, CSV_STATUS, CSV_X, CSV_Y, CSV_TH, CSV_NEEDED };
static const char *const csv_needed[CSV_NEEDED] = {
    "t_s", "servo_deg", "range_m", "status", "odom_x_m", "odom_y_m", "odom_th_rad",
};
#define CSV_MAX_COLUMNS 32

/* Splits a line at commas in place; returns the count, or -1 past CSV_MAX_COLUMNS. */
static int csv_split(char *line, char *field[CSV_MAX_COLUMNS])
{
    int n = 0;
    for (char *p = line;;) {
        if (n == CSV_MAX_COLUMNS) {
            return -1;
        }
        field[n++] = p;
        char *comma = strchr(p, ',');
        if (comma == NULL) {
            return n;
        }
        *comma = '\0';
        p = comma + 1;
    }
}

/* Where each needed column is; -1 when one is missing or the line is no header. */
static int csv_columns(char *header, int col[CSV_NEEDED])
{
    char *field[CSV_MAX_COLUMNS];
    int n = csv_split(header, field);
    for (int k = 0; k < CSV_NEEDED; k++) {
        col[k] = -1;
        for (int i = 0; i < n; i++) {
            if (strcmp(field[i], csv_needed[k]) == 0) {
                col[k] = i;
            }
        }
        if (col[k] < 0) {
            return -1;
        }
    }
    return 0;
}

/* A whole field as a number within [lo, hi] (hal_common/number.h); an empty field is not one. */
static bool parse_num(const char *s, double lo, double hi, double *out)
{
    return num_real(s, lo, hi, out) == NUM_OK;
}

/* One row; NULL, or what is wrong with it. A timeout has an empty range, every other
 * status a range. */
static const char *parse_row(char *line, const int col[CSV_NEEDED], replay_row_t *r)
{
    char *field[CSV_MAX_COLUMNS];
    int n = csv_split(line, field);
    for (int k = 0; k < CSV_NEEDED; k++) {
        if (col[k] >= n) {
            return "a column is missing";
        }
    }
    const char *status = field[col[CSV_STATUS]];
    r->echo = strcmp(status, "timeout") != 0;
    if (r->echo && strcmp(status, "ok") != 0 && strcmp(status, "far") != 0 &&
        strcmp(status, "near") != 0) {
        return "status is not ok, far, near or timeout";
    }
    double t;
    r->range_m = 0.0;
    if (!parse_num(field[col[CSV_T]], 0.0, 1e9, &t)) {
        return "t_s is not a time in seconds";
    }
    if (!parse_num(field[col[CSV_SERVO]], -360.0, 360.0, &r->servo_deg)) {
        return "servo_deg is not an angle in -360..360";
    }
    if (!parse_num(field[col[CSV_X]], -1000.0, 1000.0, &r->x_m) ||
        !parse_num(field[col[CSV_Y]], -1000.0, 1000.0, &r->y_m) ||
        !parse_num(field[col[CSV_TH]], -1000.0, 1000.0, &r->th_rad)) {
        return "the odometry pose is not x, y in -1000..1000 m and a heading in -1000..1000 rad";
    }
    if (r->echo ? !parse_num(field[col[CSV_RANGE]], 0.0, 1000.0, &r->range_m)
                : field[col[CSV_RANGE]][0] != '\0') {
        return r->echo ? "range_m is not a range in 0..1000 m" : "a timeout with a range";
    }
    return NULL;
}

int replay_read(FILE *in, const char *name, replay_row_fn fn, void *ctx, char *err, size_t errlen)
{
    char *line = NULL;
    size_t cap = 0;
    unsigned lineno = 0;
    unsigned rows = 0u;
    int rc = 0;
    int col[CSV_NEEDED];
    ssize_t n;
    errno = 0;
    while ((n = getline(&line, &cap, in)) >= 0) {
        lineno++;
        size_t len = (size_t)n;
        if (line[len - 1u] != '\n') {
            /* Every line a log writes ends in a newline: a last line without one was cut
             * while it was written, and a number cut short still reads as a number. */
            snprintf(err, errlen, "%s:%u: the last line has no newline: the file was cut short",
                     name, lineno);
            rc = -1;
            break;
        }
        if (memchr(line, '\0', len) != NULL) {
            snprintf(err, errlen, "%s:%u: a NUL byte: not a readings.csv", name, lineno);
            rc = -1;
            break;
        }
        while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r')) {
            line[--len] = '\0';
        }
        if (len >= READINGS_LINE_MAX) {
            snprintf(err, errlen, "%s:%u: line longer than %u characters", name, lineno,
                     READINGS_LINE_MAX - 1u);
            rc = -1;
            break;
        }
        if (lineno == 1) {
            if (csv_columns(line, col) != 0) {
                snprintf(err, errlen, "%s:1: not a readings.csv header (it needs the columns %s)",
                         name, CSV_READINGS_HEADER);
                rc = -1;
                break;
            }
            continue;
        }
        replay_row_t row;
        const char *why = parse_row(line, col, &row);
        if (why != NULL) {
            snprintf(err, errlen, "%s:%u: malformed reading: %s", name, lineno, why);
            rc = -1;
            break;
        }
        fn(ctx, &row);
        rows++;
    }
    if (rc == 0 && ferror(in)) {
        snprintf(err, errlen, "%s: read error: %s", name, strerror(errno));
        rc = -1;
    }
    if (rc == 0 && lineno == 0) {
        snprintf(err, errlen, "%s: empty: not a readings.csv", name);
        rc = -1;
    }
    if (rc == 0 && rows == 0u) {
        snprintf(err, errlen, "%s: a header and no reading: nothing to replay", name);
        rc = -1;
    }
    free(line);
    return rc;
}

readq_reading_t replay_reading(const replay_row_t *row)
{
    const readq_reading_t rd = {
        .ping = {to_um(row->x_m), to_um(row->y_m), to_bam(row->th_rad)},
        .range_um = row->echo ? (uint32_t)lround(row->range_m * 1e6) : 0u,
        .servo = fix_bam_from_mdeg((int32_t)lround(row->servo_deg * 1000.0)),
        .echo = row->echo,
    };
    return rd;
}
