/* SPDX-License-Identifier: MIT */
/* host_sim --replay: OM rebuilt from a readings.csv through the firmware's own mapper. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "hal_common/mapexport.h"
#include "host_sim.h"

static grid_t grid;
static mapper_t mapper;
static loc_t loc;

/* The columns a replay needs, in this order, found by name in the header: a log may
 * carry more (the simulator's truth) or order them differently. */
enum { CSV_T, CSV_SERVO, CSV_RANGE, CSV_STATUS, CSV_X, CSV_Y, CSV_TH, CSV_NEEDED };
static const char *const csv_needed[CSV_NEEDED] = {
    "t_s", "servo_deg", "range_m", "status", "odom_x_m", "odom_y_m", "odom_th_rad",
};
#define CSV_MAX_COLUMNS 32

/* Splits a line at commas in place (the newline ends the last field); returns the count. */
static int csv_split(char *line, char *field[CSV_MAX_COLUMNS])
{
    line[strcspn(line, "\r\n")] = '\0';
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

typedef struct {
    double servo, range, x, y, th;
    bool echo;
} replay_row_t;

static bool parse_num(const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || !isfinite(v) || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

/* One row; -1 when a field is missing or malformed. A timeout has an empty range, every
 * other status a range. */
static int parse_row(char *line, const int col[CSV_NEEDED], replay_row_t *r)
{
    char *field[CSV_MAX_COLUMNS];
    int n = csv_split(line, field);
    for (int k = 0; k < CSV_NEEDED; k++) {
        if (col[k] >= n) {
            return -1;
        }
    }
    const char *status = field[col[CSV_STATUS]];
    r->echo = strcmp(status, "timeout") != 0;
    if (r->echo && strcmp(status, "ok") != 0 && strcmp(status, "far") != 0 &&
        strcmp(status, "near") != 0) {
        return -1;
    }
    double t;
    r->range = 0.0;
    bool ok = parse_num(field[col[CSV_T]], 0.0, 1e9, &t) &&
              parse_num(field[col[CSV_SERVO]], -360.0, 360.0, &r->servo) &&
              parse_num(field[col[CSV_X]], -1000.0, 1000.0, &r->x) &&
              parse_num(field[col[CSV_Y]], -1000.0, 1000.0, &r->y) &&
              parse_num(field[col[CSV_TH]], -1000.0, 1000.0, &r->th);
    if (r->echo) {
        ok = ok && parse_num(field[col[CSV_RANGE]], 0.0, 1000.0, &r->range);
    } else {
        ok = ok && field[col[CSV_RANGE]][0] == '\0';
    }
    return ok ? 0 : -1;
}

/* Rebuilds OM from a readings.csv through the same mapper (the config of its run comes
 * from config.txt beside it, or --config). */
int replay(const options_t *o)
{
    char cfgpath[4096];
    if (o->config != NULL) {
        snprintf(cfgpath, sizeof cfgpath, "%s", o->config);
    } else {
        snprintf(cfgpath, sizeof cfgpath, "%s", o->replay);
        char *slash = strrchr(cfgpath, '/');
        snprintf(slash ? slash + 1 : cfgpath, sizeof cfgpath - (size_t)(slash ? slash + 1 - cfgpath : 0),
                 "config.txt");
    }
    slam_config_t cfg;
    slam_config_default(&cfg);
    char err[512];
    if (cfgtext_load(cfgpath, &cfg, NULL, NULL, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    FILE *in = fopen(o->replay, "r");
    if (in == NULL) {
        fprintf(stderr, "host_sim: %s: cannot open: %s\n", o->replay, strerror(errno));
        return EXIT_USAGE;
    }
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    loc_init(&loc, &cfg);
    char line[512];
    unsigned lineno = 0;
    unsigned rows = 0;
    int rc = 0;
    int col[CSV_NEEDED];
    while (fgets(line, sizeof line, in) != NULL) {
        lineno++;
        if (lineno == 1) {
            if (csv_columns(line, col) != 0) {
                fprintf(stderr, "host_sim: %s:1: not a readings.csv header (it needs the "
                                "columns %s)\n", o->replay, CSV_READINGS_HEADER);
                rc = EXIT_USAGE;
                break;
            }
            continue;
        }
        replay_row_t row;
        if (parse_row(line, col, &row) != 0) {
            fprintf(stderr, "host_sim: %s:%u: malformed reading\n", o->replay, lineno);
            rc = EXIT_USAGE;
            break;
        }
        rows++;
        /* Every reading goes the way the robot's went: posted as its tick posts it, then
         * mapped and matched as its background loop does. Every echo goes through the
         * mapper, which sorts it by this configuration's range limits: a replay with
         * another rc maps what the status column calls far. */
        const loc_reading_t rd = {
            .ping = {to_um(row.x), to_um(row.y), to_bam(row.th)},
            .range_um = row.echo ? (uint32_t)lround(row.range * 1e6) : 0u,
            .servo = fix_bam_from_mdeg((int32_t)lround(row.servo * 1000.0)),
            .echo = row.echo,
        };
        (void)loc_post(&loc, &rd);
        loc_idle(&loc, &mapper, &grid);
    }
    fclose(in);
    loc_flush(&loc, &mapper, &grid);
    if (rc != 0) {
        return rc;
    }
    if (make_dirs(o->out) != 0) {
        return 1;
    }
    map_geom_t g = map_geom_of(&grid);
    /* No TM in a log: in OM_MODE_COUNT the replayed map knows no free cell, while the
     * run's knew those the robot drove through; OM_MODE_EVIDENCE keeps its own. */
    static uint8_t img[SLAM_GRID_CELLS];
    mapx_trinary(cfg.om_mode, grid.om, NULL, NULL, SLAM_GRID_A, SLAM_GRID_B, img);
    if (write_map(o->out, "om", &g, img, true) != 0) {
        return 1;
    }
    if (!o->quiet) {
        printf("host_sim: replayed %u readings (%u OM hits) into %s/om.pgm\n", rows,
               mapper.hits, o->out);
    }
    return 0;
}
