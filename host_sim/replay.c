/* SPDX-License-Identifier: MIT */
/* host_sim --replay: OM rebuilt from a readings.csv through the firmware's own mapper. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hal_common/config_text.h"
#include "hal_common/mapexport.h"
#include "host_sim.h"

static grid_t grid;
static mapper_t mapper;
static loc_t loc;

/* Every reading goes the way the robot's went: mapped and matched as its background loop
 * does, or mapped by the mapper alone with the pose correction off. Every echo goes
 * through the mapper, which sorts it by this configuration's range limits: a replay with
 * another rc maps what the status column calls far. */
static void replay_row(void *ctx, const replay_row_t *row)
{
    unsigned *rows = ctx;
    (*rows)++;
    const readq_reading_t rd = replay_reading(row);
    if (loc.on) {
        loc_reading(&loc, &mapper, &grid, &rd);
    } else {
        readq_map(&rd, &mapper, &grid);
    }
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
        snprintf(slash ? slash + 1 : cfgpath,
                 sizeof cfgpath - (size_t)(slash ? slash + 1 - cfgpath : 0), "config.txt");
    }
    slam_config_t cfg;
    slam_config_default(&cfg);
    char err[512];
    cfgtext_where_t where;
    if (cfgtext_load(cfgpath, &cfg, NULL, NULL, &where, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    /* A config.txt from before the grid's size was a key: the simulator's grid was then
     * 256 x 256 cells. */
    if (cfgtext_where_line(&where, "grid_a") == 0u && cfgtext_where_line(&where, "grid_b") == 0u) {
        cfg.grid_a = 256u;
        cfg.grid_b = 256u;
    }
    /* Where the map goes: --out, else a folder "replay" beside the log, never out/sim,
     * whose om.pgm belongs to the last simulation. A folder holding a simulation's outputs
     * is refused: its om.pgm would stop matching its metrics, logs and truth. */
    char outdir[4096];
    if (o->has_out) {
        snprintf(outdir, sizeof outdir, "%s", o->out);
    } else {
        const char *slash = strrchr(o->replay, '/');
        snprintf(outdir, sizeof outdir, "%.*sreplay",
                 slash != NULL ? (int)(slash + 1 - o->replay) : 0, o->replay);
    }
    char metrics[4200];
    snprintf(metrics, sizeof metrics, "%s/metrics.json", outdir);
    struct stat st;
    if (stat(metrics, &st) == 0) {
        fprintf(stderr,
                "host_sim: --out %s holds a simulation's outputs (metrics.json): the replay's "
                "om.pgm would replace the run's and leave its folder inconsistent; give "
                "another --out\n",
                outdir);
        return EXIT_USAGE;
    }
    static const char *const names[] = {"om.pgm", "om.yaml", NULL};
    if (check_out_dir("--out", outdir, names) != 0) {
        return EXIT_USAGE;
    }
    FILE *in = cfgtext_open_file(o->replay, err, sizeof err);
    if (in == NULL) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    loc_init(&loc, &cfg);
    unsigned rows = 0;
    int rc = replay_read(in, o->replay, replay_row, &rows, err, sizeof err);
    fclose(in);
    if (rc != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    loc_flush(&loc, &mapper, &grid);
    if (make_dirs(outdir) != 0) {
        return 1;
    }
    map_geom_t g = map_geom_of(&grid);
    /* No TM in a log: in OM_MODE_COUNT the replayed map knows no free cell, while the
     * run's knew those the robot drove through; OM_MODE_EVIDENCE keeps its own. */
    static uint8_t img[SLAM_GRID_CELLS];
    mapx_trinary(cfg.om_mode, grid.om, NULL, NULL, grid.a_cells, grid.b_cells, img);
    if (write_map(outdir, "om", &g, img, true) != 0 || outputs_commit() != 0) {
        outputs_discard();
        return 1;
    }
    if (!o->quiet) {
        printf("host_sim: replayed %u readings (%u OM hits) into %s/om.pgm\n", rows, mapper.hits,
               outdir);
    }
    return 0;
}
