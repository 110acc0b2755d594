/* SPDX-License-Identifier: MIT */
/* host_sim --replay: OM rebuilt from a readings.csv through the firmware's own mapper. */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "hal_common/mapexport.h"
#include "host_sim.h"

static grid_t grid;
static mapper_t mapper;

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
    if (cfgtext_load(cfgpath, &cfg, NULL, NULL, err, sizeof err) != 0) {
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
    char line[512];
    unsigned lineno = 0;
    unsigned rows = 0;
    int rc = 0;
    while (fgets(line, sizeof line, in) != NULL) {
        lineno++;
        if (lineno == 1) {
            if (strncmp(line, "t,servo_deg,range_m,status,", 27) != 0) {
                fprintf(stderr, "host_sim: %s:1: not a readings.csv header\n", o->replay);
                rc = EXIT_USAGE;
                break;
            }
            continue;
        }
        double t, servo, range = 0.0, x, y, th;
        char status[16];
        int n = 0;
        if (strstr(line, ",timeout,") != NULL) {
            n = sscanf(line, "%lf,%lf,,%15[a-z],%lf,%lf,%lf", &t, &servo, status, &x, &y, &th);
            n = n == 6 ? 7 : n;
        } else {
            n = sscanf(line, "%lf,%lf,%lf,%15[a-z],%lf,%lf,%lf", &t, &servo, &range, status, &x,
                       &y, &th);
        }
        if (n != 7 || !isfinite(servo) || !isfinite(range) || !isfinite(x) || !isfinite(y) ||
            !isfinite(th) || range < 0.0 || range > 1000.0 || fabs(x) > 1000.0 || fabs(y) > 1000.0) {
            fprintf(stderr, "host_sim: %s:%u: malformed reading\n", o->replay, lineno);
            rc = EXIT_USAGE;
            break;
        }
        rows++;
        odom_pose_t p = {to_um(x), to_um(y), to_bam(th)};
        if (strcmp(status, "ok") != 0) {
            mapper_timeout(&mapper, &grid, &p);
            continue;
        }
        bam32_t sv = fix_bam_from_mdeg((int32_t)lround(servo * 1000.0));
        (void)mapper_reading(&mapper, &grid, &p, sv, (uint32_t)lround(range * 1e6));
    }
    fclose(in);
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
