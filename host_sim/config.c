/* SPDX-License-Identifier: MIT */
/* host_sim's firmware configuration: the file, the options, the start pose and the grid. */
#include <math.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "slam/config_fields.h"
#include "host_sim.h"

static const double PI = HOST_SIM_PI;

/* The --set options, and where each configuration value came from (for messages). */
typedef struct {
    const options_t *o;
    cfgtext_where_t cal;  /* lines of the --calibration file */
    cfgtext_where_t file; /* lines of the --config file */
    char keys[HOST_SIM_MAX_SETS][64];
} cfg_origin_t;

/* "--set KEY=VALUE", "FILE:LINE" or NULL: who set a key. */
static const char *origin(const cfg_origin_t *w, const char *key, char *buf, size_t n)
{
    for (size_t i = w->o->nsets; i-- > 0;) {
        if (strcmp(w->keys[i], key) == 0) {
            snprintf(buf, n, "--set %s", w->o->sets[i]);
            return buf;
        }
    }
    unsigned line = cfgtext_where_line(&w->file, key);
    if (line != 0u) {
        snprintf(buf, n, "%s:%u", w->o->config, line);
        return buf;
    }
    line = cfgtext_where_line(&w->cal, key);
    if (line != 0u) {
        snprintf(buf, n, "%s:%u", w->o->calibration, line);
        return buf;
    }
    if (w->o->paper && (strcmp(key, "om_mode") == 0 || strncmp(key, "post_", 5) == 0 ||
                        strncmp(key, "sweep_", 6) == 0)) {
        snprintf(buf, n, "--paper");
        return buf;
    }
    if ((strcmp(key, "cell_um") == 0 && w->o->has_cell) ||
        (strcmp(key, "explore_mode") == 0 && w->o->has_explore) ||
        (strcmp(key, "explore_seed") == 0 && w->o->has_seed)) {
        snprintf(buf, n, "--%s", key[0] == 'c' ? "cell" : key[8] == 'm' ? "explore" : "seed");
        return buf;
    }
    return NULL;
}

/* The keys a calibration file holds: what tools/umbmark.py writes. */
static bool is_calibration_key(const char *key)
{
    return strcmp(key, "cal_left") == 0 || strcmp(key, "cal_right") == 0 ||
           strcmp(key, "cal_base") == 0;
}

/* The grid of a room that fits it: the simulator's since it began, so that the outputs of
 * every such run stay as they were. A larger room grows it by HOST_SIM_GRID_STEP cells (an
 * exploration block) up to the capacity, SLAM_GRID_A x SLAM_GRID_B. */
#define HOST_SIM_GRID 256u
#define HOST_SIM_GRID_STEP 16u
_Static_assert(HOST_SIM_GRID <= SLAM_GRID_A && HOST_SIM_GRID <= SLAM_GRID_B,
               "the simulator's capacity holds its usual grid");

/* One axis of the grid against the room: the start's cell and the cells, each either set
 * (by names where) or chosen. */
typedef struct {
    const char *by_start; /* where start_cell_<axis> was set, or NULL */
    const char *by_cells; /* where grid_<axis> was set, or NULL */
    long start;           /* the start's cell */
    uint16_t cells;       /* the cells along the axis */
} axis_fit_t;

/* grid_origin_um() in metres: the grid's lower-left corner along an axis, for a start at s
 * in cell `start`. */
static double origin_m(double s, long start, double cell)
{
    return s - (double)start * cell - cell / 2.0;
}

/* Chooses the cells (unless set) and the start's cell (unless set) along one axis for a
 * start at s and a room over lo .. hi, m: true when the room fits, f holding them; false
 * with the largest tried. */
static bool fit_axis(axis_fit_t *f, double s, double lo, double hi, double cell, uint32_t cap)
{
    uint32_t n = f->cells != 0u ? f->cells : HOST_SIM_GRID;
    for (;;) {
        long a0 =
            f->by_start != NULL ? f->start : (long)n / 2 + lround((s - (lo + hi) / 2.0) / cell);
        double o0 = origin_m(s, a0, cell);
        bool fits = a0 >= 0 && a0 < (long)n && o0 <= lo && o0 + n * cell >= hi;
        f->start = a0;
        f->cells = (uint16_t)n;
        if (fits || f->by_cells != NULL || n >= cap) {
            return fits;
        }
        n = n + HOST_SIM_GRID_STEP < cap ? n + HOST_SIM_GRID_STEP : cap;
    }
}

/* --calibration FILE: the odometry's factors and nothing else, and at least one of them.
 * 0, or -1 with a message. */
static int load_calibration(const char *path, slam_config_t *cfg, cfgtext_where_t *where)
{
    static const char *const names[] = {
#define FIELD_NAME(name, type, dflt, lo, hi, rule, id, live, words) #name,
        SLAM_CONFIG_FIELDS(FIELD_NAME)
#undef FIELD_NAME
    };
    slam_config_t work = *cfg;
    char err[512];
    if (cfgtext_load(path, &work, NULL, NULL, where, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: --calibration: %s\n", err);
        return -1;
    }
    unsigned set = 0u;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        unsigned line = cfgtext_where_line(where, names[i]);
        if (line != 0u && !is_calibration_key(names[i])) {
            fprintf(stderr,
                    "host_sim: --calibration: %s:%u: %s is not a calibration key (the file "
                    "holds cal_left, cal_right, cal_base); give it with --config or --set\n",
                    path, line, names[i]);
            return -1;
        }
        set += line != 0u ? 1u : 0u;
    }
    if (set == 0u) {
        fprintf(stderr,
                "host_sim: --calibration: %s holds no calibration (cal_left, cal_right, "
                "cal_base); for a run without one, give --calibration none\n",
                path);
        return -1;
    }
    *cfg = work;
    return 0;
}

static int check_config(const cfg_origin_t *w, const slam_config_t *cfg)
{
    char err[512];
    const char *bad = NULL;
    if (cfgtext_check(cfg, &bad, err, sizeof err) == 0) {
        return 0;
    }
    char who[160];
    const char *by = origin(w, bad, who, sizeof who);
    /* Not set by anyone: blame the option or line that set a field its rule compares it
     * with (--set range_min_um=1000000 breaks confidence_radius_um's rule). */
    for (const char *p = cfgtext_partners(bad); by == NULL && p != NULL && *p != '\0';) {
        size_t n = strcspn(p, " ");
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)n, p);
        by = origin(w, name, who, sizeof who);
        p += n + (p[n] == ' ' ? 1u : 0u);
    }
    fprintf(stderr, "host_sim: %s: %s\n", by != NULL ? by : "configuration", err);
    return -1;
}

int build_config(options_t *o, const room_t *room, double sx, double sy, double sth,
                 slam_config_t *cfg)
{
    slam_config_default(cfg);
    /* The start cell is chosen below for the grid the room needs, unless given: cell 0
     * until then, which any grid_a or grid_b given holds (the default, the capacity's
     * middle, would refuse a smaller grid). */
    cfg->start_cell_a = 0u;
    cfg->start_cell_b = 0u;
    static cfg_origin_t w;
    memset(&w, 0, sizeof w);
    w.o = o;
    char err[512];
    /* The order, a later one overriding an earlier one: the calibration (the robot's
     * wheels), the --config file, the options given, each --set. */
    if (o->calibration != NULL && load_calibration(o->calibration, cfg, &w.cal) != 0) {
        return -1;
    }
    if (o->config != NULL &&
        cfgtext_load(o->config, cfg, NULL, NULL, &w.file, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return -1;
    }
    /* A robot's own file (robot.conf) that holds its calibration is where the calibration
     * came from: the report names it, not the calibration file it overrode. */
    bool cal_in_config = o->config != NULL && (cfgtext_where_line(&w.file, "cal_left") != 0u ||
                                               cfgtext_where_line(&w.file, "cal_right") != 0u ||
                                               cfgtext_where_line(&w.file, "cal_base") != 0u);
    if (o->paper) {
        slam_config_paper(cfg);
    }
    uint32_t cell_um = (uint32_t)lround(o->cell_mm * 1000.0);
    if (o->has_cell) {
        cfg->cell_um = cell_um;
    }
    if (o->has_explore) {
        cfg->explore_mode = (uint8_t)o->explore;
    }
    if (o->has_sonar1) {
        /* A fitted second sonar is mapped (--set sonar1_map=0 leaves it unused): its beam,
         * DEG left of the heading, is the servo angle 90 - DEG. */
        cfg->sonar1_map = 1u;
        cfg->sonar1_mdeg = (int32_t)lround((90.0 - o->sonar1_deg) * 1000.0);
    }
    /* The run's seed (1 unless given) seeds the exploration too, unless a file says
     * otherwise: host_sim and host_sim --seed 1 are one run. */
    if (o->has_seed || (cfgtext_where_line(&w.file, "explore_seed") == 0u &&
                        cfgtext_where_line(&w.cal, "explore_seed") == 0u)) {
        cfg->explore_seed = explore_seed_of(o->seed);
    }
    for (size_t i = 0; i < o->nsets; i++) {
        const char *eq = strchr(o->sets[i], '=');
        size_t len = (size_t)(eq - o->sets[i]);
        if (len >= sizeof w.keys[i]) {
            fprintf(stderr, "host_sim: --set %.40s...: key too long\n", o->sets[i]);
            return -1;
        }
        memcpy(w.keys[i], o->sets[i], len);
        w.keys[i][len] = '\0';
        for (size_t k = 0; k < i; k++) {
            if (strcmp(w.keys[k], w.keys[i]) == 0) {
                fprintf(stderr, "host_sim: --set %s: %s is given twice (--set %s)\n", o->sets[i],
                        w.keys[i], o->sets[k]);
                return -1;
            }
        }
        if (cfgtext_set(cfg, w.keys[i], eq + 1, err, sizeof err) != 0) {
            fprintf(stderr, "host_sim: --set: %s\n", err);
            return -1;
        }
        if (o->has_cell && cfg->cell_um != cell_um) {
            fprintf(stderr, "host_sim: --set %s disagrees with --cell %.0f\n", o->sets[i],
                    o->cell_mm);
            return -1;
        }
        if (o->has_explore && cfg->explore_mode != (uint8_t)o->explore) {
            fprintf(stderr, "host_sim: --set %s disagrees with --explore %s\n", o->sets[i],
                    explore_names[o->explore]);
            return -1;
        }
    }
    if (check_config(&w, cfg) != 0) {
        return -1;
    }
    if (cfg->sonar1_map != 0u && !o->has_sonar1) {
        fprintf(stderr, "host_sim: sonar1_map = 1, but the simulated robot has no sonar 1: "
                        "fit one with --sonar1 X Y DEG\n");
        return -1;
    }
    if (o->has_sonar1 && cfg->sonar1_map != 0u) {
        /* The firmware maps it from the swept sonar's mount. */
        double off =
            hypot(o->sonar1_x - cfg->mount_x_um * 1e-6, o->sonar1_y - cfg->mount_y_um * 1e-6);
        if (off >= 0.0005) {
            fprintf(stderr,
                    "host_sim: warning: sonar 1 sits %.0f mm from the servo's axis, where the "
                    "firmware maps it from: its hits land as far off\n",
                    off * 1000.0);
        }
    }

    /* The start pose is the scenario's (the room's, or --start). */
    const struct {
        const char *key;
        int32_t *field;
        int32_t value;
        double shown;
    } start[3] = {
        {"start_x_um", &cfg->start_x_um, to_um(sx), sx},
        {"start_y_um", &cfg->start_y_um, to_um(sy), sy},
        {"start_heading_mdeg", &cfg->start_heading_mdeg,
         (int32_t)lround(remainder(sth, 2.0 * PI) * 180000.0 / PI), sth * 180.0 / PI},
    };
    for (int k = 0; k < 3; k++) {
        char who[160];
        const char *by = origin(&w, start[k].key, who, sizeof who);
        /* A heading a whole turn away (360000 for 0) is the same heading. */
        bool same = *start[k].field == start[k].value ||
                    (k == 2 && ((int64_t)*start[k].field - start[k].value) % 360000 == 0);
        if (by != NULL && !same) {
            fprintf(stderr,
                    "host_sim: %s: %s = %ld disagrees with the run's start pose (%.3f%s): "
                    "the start pose comes from the room file or --start\n",
                    by, start[k].key, (long)*start[k].field, start[k].shown, k < 2 ? " m" : " deg");
            return -1;
        }
        *start[k].field = start[k].value;
    }

    /* The grid: HOST_SIM_GRID cells a side for any room that fits it (every run of the
     * shipped rooms the same as ever), grown a block at a time up to the capacity for a room
     * or a flat that does not, unless grid_a or grid_b was set. The middle of the room at
     * the middle of the grid, unless the start cell was set (to record a trace for a robot
     * with a smaller grid, say). */
    char who_a[160];
    char who_b[160];
    char who_ga[160];
    char who_gb[160];
    const char *by_a = origin(&w, "start_cell_a", who_a, sizeof who_a);
    const char *by_b = origin(&w, "start_cell_b", who_b, sizeof who_b);
    const char *by_ga = origin(&w, "grid_a", who_ga, sizeof who_ga);
    const char *by_gb = origin(&w, "grid_b", who_gb, sizeof who_gb);
    double cell = cfg->cell_um * 1e-6;
    axis_fit_t fx = {by_a, by_ga, by_a != NULL ? (long)cfg->start_cell_a : 0,
                     by_ga != NULL ? grid_cells_a(cfg) : 0u};
    axis_fit_t fy = {by_b, by_gb, by_b != NULL ? (long)cfg->start_cell_b : 0,
                     by_gb != NULL ? grid_cells_b(cfg) : 0u};
    bool fits_x = fit_axis(&fx, sx, room->min_x, room->max_x, cell, SLAM_GRID_A);
    bool fits_y = fit_axis(&fy, sy, room->min_y, room->max_y, cell, SLAM_GRID_B);
    const axis_fit_t *bad = !fits_x ? &fx : &fy;
    if ((!fits_x || !fits_y) && (bad->by_start != NULL || bad->by_cells != NULL)) {
        bool x = bad == &fx;
        double o0 = origin_m(x ? sx : sy, bad->start, cell);
        fprintf(stderr,
                "host_sim: %s: with the start in cell %ld along %s, the grid of %u cells spans "
                "%s = %.3f .. %.3f m and the room %.3f .. %.3f m: the room does not fit\n",
                bad->by_start != NULL ? bad->by_start : bad->by_cells, bad->start, x ? "x" : "y",
                (unsigned)bad->cells, x ? "x" : "y", o0, o0 + bad->cells * cell,
                x ? room->min_x : room->min_y, x ? room->max_x : room->max_y);
        return -1;
    }
    if (!fits_x || !fits_y) {
        fprintf(stderr,
                "host_sim: the room (%.1f x %.1f m) does not fit the largest grid, %ux%u "
                "cells of %.0f mm (%.1f x %.1f m): use a larger --cell or a smaller --crop\n",
                room->max_x - room->min_x, room->max_y - room->min_y, (unsigned)SLAM_GRID_A,
                (unsigned)SLAM_GRID_B, cell * 1e3, SLAM_GRID_A * cell, SLAM_GRID_B * cell);
        return -1;
    }
    cfg->grid_a = fx.cells;
    cfg->grid_b = fy.cells;
    cfg->start_cell_a = (uint16_t)fx.start;
    cfg->start_cell_b = (uint16_t)fy.start;
    if (check_config(&w, cfg) != 0) {
        return -1;
    }
    if (cal_in_config) {
        o->calibration = o->config;
    }
    return 0;
}
