/* SPDX-License-Identifier: MIT */
/*
 * host_sim: the robot's unchanged firmware exploring a simulated room. Runs a scenario
 * through robot_init/robot_tick on the host backend, then writes the maps, the
 * trajectories, the sonar log, a score against ground truth and a picture.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "hal/hal.h"
#include "hal_common/config_text.h"
#include "hal_common/trace.h"
#include "host/sim.h"
#include "host_sim.h"
#include "slam/error.h"
#include "slam/postprocess.h"
#include "slam/robot.h"

#ifndef SLAM_SOURCE_DIR
#define SLAM_SOURCE_DIR "."
#endif

static const double PI = 3.14159265358979323846;
#define TICK_S (HAL_TICK_PERIOD_US * 1e-6)
#define TRAJECTORY_EVERY 10u     /* trajectory.csv: one row per 0.1 s */
#define COVERAGE_EVERY 1000u     /* the coverage series: one point per 10 s */
#define EXIT_USAGE 2

/* ---- options -------------------------------------------------------------------------- */

#define MAX_SETS 64

typedef struct {
    const char *room;
    bool has_crop;
    room_crop_t crop;
    bool has_start;
    double start_x, start_y, start_deg;
    double duration_s;
    uint64_t seed;
    double cell_mm;
    int explore;
    const char *out;
    bool ideal;
    const char *errors[MAX_SETS];
    size_t nerrors;
    const char *config;
    const char *sets[MAX_SETS];
    size_t nsets;
    const char *trace;
    const char *telemetry;
    bool realtime;
    const char *replay;
    bool plot;
    bool quiet;
} options_t;

static const char *const explore_names[EXPLORE_MODES] = {"off", "random", "tm", "square"};

static void usage(FILE *f)
{
    fprintf(f,
        "usage: host_sim [options]\n"
        "       host_sim --replay DIR/readings.csv [--config FILE] [--out DIR]\n"
        "\n"
        "Runs the robot's firmware in a simulated room and writes maps, trajectories,\n"
        "the sonar log, a score against ground truth and a picture.\n"
        "\n"
        "scenario:\n"
        "  --room FILE          a .room file or a ROS map .yaml (default: the shipped\n"
        "                       host_sim/rooms/default.room)\n"
        "  --crop X Y W H       take this part of a ROS map (metres, map frame)\n"
        "  --start X Y DEG      start pose (default: the room's, or a free spot)\n"
        "  --duration S         simulated seconds (default 600)\n"
        "  --seed N             seed of every random error and of the exploration (default 1)\n"
        "  --cell MM            grid cell size in mm (default 50)\n"
        "  --explore MODE       random | tm | square | off (default random)\n"
        "  --ideal              turn every error source off\n"
        "  --error NAME=VALUE   one error level (repeatable): ed, eb (wheel diameter ratio,\n"
        "                       wheel base ratio), slip (per m/s² beyond slip_free m/s²),\n"
        "                       noise, sonar_noise (m), dropout, ghost, grazing (deg)\n"
        "  --config FILE        firmware configuration, key = value lines\n"
        "  --set KEY=VALUE      one firmware configuration value (repeatable)\n"
        "outputs:\n"
        "  --out DIR            output folder (default out/sim)\n"
        "  --trace FILE         also record the HAL trace of the run\n"
        "  --telemetry FILE     write the firmware's telemetry bytes (the UART) to FILE\n"
        "                       (watch: tools/telemetry.py view FILE --follow)\n"
        "  --realtime           run at the speed of the real robot, not as fast as possible\n"
        "  --no-plot            do not draw figure.png\n"
        "  --quiet              no progress line and no summary\n"
        "  --help               this text\n"
        "\n"
        "Files written: om.pgm om_post.pgm tm.pgm truth.pgm (+ ROS .yaml each),\n"
        "trajectory.csv readings.csv metrics.json timing.json config.txt figure.png\n"
        "Exit status: 0 done, 1 failed while running, 2 bad options or input.\n");
}

static int fail_usage(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "host_sim: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(host_sim --help lists the options)\n");
    va_end(ap);
    return EXIT_USAGE;
}

static bool parse_double(const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v) || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

static bool parse_u64(const char *s, uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    if (*s == '-') {
        return false;
    }
    unsigned long long v = strtoull(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0) {
        return false;
    }
    *out = v;
    return true;
}

/* Takes the n arguments after an option; false if there are fewer, or if one of them is
 * itself an option (a missing value must not swallow the next option). */
static bool take(int argc, char **argv, int *i, int n)
{
    if (*i + n >= argc) {
        return false;
    }
    for (int k = 1; k <= n; k++) {
        if (strncmp(argv[*i + k], "--", 2) == 0) {
            return false;
        }
    }
    *i += n;
    return true;
}

static int parse_options(int argc, char **argv, options_t *o)
{
    *o = (options_t){
        .room = SLAM_SOURCE_DIR "/host_sim/rooms/default.room",
        .duration_s = 600.0,
        .seed = 1u,
        .cell_mm = 50.0,
        .explore = EXPLORE_RANDOM,
        .out = "out/sim",
        .plot = true,
    };
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--room") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--room needs a file");
            }
            o->room = argv[i];
        } else if (strcmp(a, "--crop") == 0) {
            if (!take(argc, argv, &i, 4)) {
                return fail_usage("--crop needs X Y W H in metres");
            }
            double *v[4] = {&o->crop.x, &o->crop.y, &o->crop.w, &o->crop.h};
            for (int k = 0; k < 4; k++) {
                if (!parse_double(argv[i - 3 + k], -1e6, 1e6, v[k])) {
                    return fail_usage("--crop: '%s' is not a number", argv[i - 3 + k]);
                }
            }
            if (o->crop.w <= 0.0 || o->crop.h <= 0.0) {
                return fail_usage("--crop: W and H must be positive");
            }
            o->has_crop = true;
        } else if (strcmp(a, "--start") == 0) {
            if (!take(argc, argv, &i, 3)) {
                return fail_usage("--start needs X Y DEG");
            }
            if (!parse_double(argv[i - 2], -1e6, 1e6, &o->start_x) ||
                !parse_double(argv[i - 1], -1e6, 1e6, &o->start_y) ||
                !parse_double(argv[i], -360.0, 360.0, &o->start_deg)) {
                return fail_usage("--start: expected X Y in metres and DEG in -360..360");
            }
            o->has_start = true;
        } else if (strcmp(a, "--duration") == 0) {
            if (!take(argc, argv, &i, 1) || !parse_double(argv[i], 0.01, 1e6, &o->duration_s)) {
                return fail_usage("--duration needs seconds between 0.01 and 1000000");
            }
        } else if (strcmp(a, "--seed") == 0) {
            if (!take(argc, argv, &i, 1) || !parse_u64(argv[i], &o->seed)) {
                return fail_usage("--seed needs a whole number >= 0");
            }
        } else if (strcmp(a, "--cell") == 0) {
            if (!take(argc, argv, &i, 1) || !parse_double(argv[i], 5.0, 1000.0, &o->cell_mm) ||
                o->cell_mm != floor(o->cell_mm)) {
                return fail_usage("--cell needs whole millimetres between 5 and 1000");
            }
        } else if (strcmp(a, "--explore") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--explore needs a mode");
            }
            o->explore = -1;
            for (int m = 0; m < EXPLORE_MODES; m++) {
                if (strcmp(argv[i], explore_names[m]) == 0) {
                    o->explore = m;
                }
            }
            if (o->explore < 0) {
                return fail_usage("--explore: unknown mode '%s' (random, tm, square, off)", argv[i]);
            }
        } else if (strcmp(a, "--out") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--out needs a folder");
            }
            o->out = argv[i];
        } else if (strcmp(a, "--ideal") == 0) {
            o->ideal = true;
        } else if (strcmp(a, "--error") == 0 || strcmp(a, "--set") == 0) {
            bool err = a[2] == 'e';
            if (!take(argc, argv, &i, 1) || strchr(argv[i], '=') == NULL) {
                return fail_usage("%s needs NAME=VALUE", a);
            }
            size_t *n = err ? &o->nerrors : &o->nsets;
            if (*n == MAX_SETS) {
                return fail_usage("too many %s options", a);
            }
            (err ? o->errors : o->sets)[(*n)++] = argv[i];
        } else if (strcmp(a, "--config") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--config needs a file");
            }
            o->config = argv[i];
        } else if (strcmp(a, "--trace") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--trace needs a file");
            }
            o->trace = argv[i];
        } else if (strcmp(a, "--telemetry") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--telemetry needs a file");
            }
            o->telemetry = argv[i];
        } else if (strcmp(a, "--realtime") == 0) {
            o->realtime = true;
        } else if (strcmp(a, "--replay") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--replay needs a readings.csv");
            }
            o->replay = argv[i];
        } else if (strcmp(a, "--no-plot") == 0) {
            o->plot = false;
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = true;
        } else {
            return fail_usage("unknown option '%s'", a);
        }
    }
    return 0;
}

/* ---- the scenario --------------------------------------------------------------------- */

/* --error NAME=VALUE onto the error levels. */
static int apply_error(sim_errors_t *e, const char *nv)
{
    static const struct {
        const char *name;
        size_t offset;
        double lo, hi;
    } names[] = {
        {"ed", offsetof(sim_errors_t, wheel_ratio_ed), 0.8, 1.2},
        {"eb", offsetof(sim_errors_t, wheel_base_eb), 0.8, 1.2},
        {"slip", offsetof(sim_errors_t, slip_per_mps2), 0.0, 1.0},
        {"slip_free", offsetof(sim_errors_t, slip_free_mps2), 0.0, 100.0},
        {"noise", offsetof(sim_errors_t, wheel_noise), 0.0, 1.0},
        {"sonar_noise", offsetof(sim_errors_t, sonar_noise_m), 0.0, 1.0},
        {"dropout", offsetof(sim_errors_t, sonar_dropout), 0.0, 1.0},
        {"ghost", offsetof(sim_errors_t, sonar_ghost), 0.0, 1.0},
        {"grazing", offsetof(sim_errors_t, grazing_deg), 0.0, 90.0},
    };
    const char *eq = strchr(nv, '=');
    size_t len = (size_t)(eq - nv);
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (strlen(names[i].name) == len && strncmp(nv, names[i].name, len) == 0) {
            double v;
            if (!parse_double(eq + 1, names[i].lo, names[i].hi, &v)) {
                fprintf(stderr, "host_sim: --error %s: the value must lie in %g..%g\n",
                        names[i].name, names[i].lo, names[i].hi);
                return -1;
            }
            memcpy((char *)e + names[i].offset, &v, sizeof v);
            return 0;
        }
    }
    fprintf(stderr, "host_sim: --error: unknown error source '%.*s' (ed, eb, slip, slip_free, "
                    "noise, sonar_noise, dropout, ghost, grazing)\n", (int)len, nv);
    return -1;
}

static int32_t to_um(double m)
{
    return (int32_t)lround(m * 1e6);
}

static bam32_t to_bam(double rad)
{
    double turns = rad / (2.0 * PI);
    turns -= floor(turns);
    return (bam32_t)(uint64_t)llround(turns * 4294967296.0);
}

static double bam_rad(bam32_t b)
{
    return (double)b * (2.0 * PI / 4294967296.0);
}

/* The firmware configuration of a run: defaults, the config file, the options, and the
 * start pose and start cell that put the room in the middle of the grid. */
static int build_config(const options_t *o, const room_t *room, double sx, double sy,
                        double sth, slam_config_t *cfg)
{
    slam_config_default(cfg);
    char err[512];
    if (o->config != NULL && cfgtext_load(o->config, cfg, NULL, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return -1;
    }
    cfg->cell_um = (uint32_t)lround(o->cell_mm * 1000.0);
    cfg->explore_mode = (uint8_t)o->explore;
    cfg->explore_seed = (uint32_t)(o->seed ^ (o->seed >> 32)) | 1u;
    bool start_cell_set = false;
    for (size_t i = 0; i < o->nsets; i++) {
        char key[64];
        const char *eq = strchr(o->sets[i], '=');
        size_t len = (size_t)(eq - o->sets[i]);
        if (len >= sizeof key) {
            fprintf(stderr, "host_sim: --set: key too long\n");
            return -1;
        }
        memcpy(key, o->sets[i], len);
        key[len] = '\0';
        if (cfgtext_set(cfg, key, eq + 1, err, sizeof err) != 0) {
            fprintf(stderr, "host_sim: --set: %s\n", err);
            return -1;
        }
        start_cell_set |= strncmp(key, "start_cell_", 11) == 0;
    }
    cfg->start_x_um = to_um(sx);
    cfg->start_y_um = to_um(sy);
    cfg->start_heading_mdeg = (int32_t)lround(remainder(sth, 2.0 * PI) * 180000.0 / PI);
    /* Put the middle of the room at the middle of the grid, unless the start cell was set
     * (to record a trace for a robot with a smaller grid, say). */
    double cell = cfg->cell_um * 1e-6;
    double cx = (room->min_x + room->max_x) / 2.0;
    double cy = (room->min_y + room->max_y) / 2.0;
    long a0 = (long)SLAM_GRID_A / 2 + lround((sx - cx) / cell);
    long b0 = (long)SLAM_GRID_B / 2 + lround((sy - cy) / cell);
    if (start_cell_set) {
        a0 = cfg->start_cell_a;
        b0 = cfg->start_cell_b;
    }
    double ox = sx - (double)a0 * cell - cell / 2.0;
    double oy = sy - (double)b0 * cell - cell / 2.0;
    if (a0 < 0 || b0 < 0 || a0 >= (long)SLAM_GRID_A || b0 >= (long)SLAM_GRID_B ||
        ox > room->min_x || oy > room->min_y || ox + SLAM_GRID_A * cell < room->max_x ||
        oy + SLAM_GRID_B * cell < room->max_y) {
        fprintf(stderr,
                "host_sim: the room (%.1f x %.1f m) does not fit the %ux%u grid of %.0f mm "
                "cells (%.1f x %.1f m): use a larger --cell or a smaller --crop\n",
                room->max_x - room->min_x, room->max_y - room->min_y, (unsigned)SLAM_GRID_A,
                (unsigned)SLAM_GRID_B, cell * 1e3, SLAM_GRID_A * cell, SLAM_GRID_B * cell);
        return -1;
    }
    cfg->start_cell_a = (uint16_t)a0;
    cfg->start_cell_b = (uint16_t)b0;
    const char *bad = NULL;
    if (slam_config_check(cfg, &bad) != SLAM_OK) {
        fprintf(stderr, "host_sim: configuration: %s is out of its valid range\n", bad);
        return -1;
    }
    return 0;
}

/* The robot as built matches the firmware's nominal configuration; the error levels make
 * the real one differ. */
static void build_params(const slam_config_t *cfg, sim_params_t *p)
{
    sim_params_default(p);
    p->wheel_diameter_m = cfg->wheel_diameter_left_um * 1e-6;
    p->wheel_base_m = cfg->wheel_base_um * 1e-6;
    p->counts_per_rev = cfg->encoder_counts_per_rev;
    p->top_speed_mps = cfg->top_speed_mm_s * 1e-3;
    p->sonar_x_m = cfg->mount_x_um * 1e-6;
    p->sonar_y_m = cfg->mount_y_um * 1e-6;
    p->servo_pulse_0_us = cfg->servo_pulse_0deg_us;
    p->servo_pulse_180_us = cfg->servo_pulse_180deg_us;
}

/* ---- the run -------------------------------------------------------------------------- */

static robot_t robot;        /* the firmware's state, as a robot program owns it */
static grid_t ideal_grid;    /* the same readings mapped from the true poses */
static mapper_t ideal_mapper;

static void tick_callback(void *ctx)
{
    robot_tick(ctx);
}

/* Everything measured while the robot runs. */
typedef struct {
    map_geom_t geom;
    uint8_t *truth;
    uint8_t *observable;
    uint8_t *reachable;
    uint8_t *seen;
    uint32_t reachable_cells;
    uint32_t visited_cells;
    double time_to[3];        /* to 50, 80, 90 % of the reachable cells; < 0: not reached */
    double series[4096][2];   /* (t, coverage) */
    size_t nseries;
    double max_pos_err, max_th_err, final_pos_err, final_th_err, path_m;
    double last_x, last_y;
    double marked_x, marked_y;  /* the sonar position last marked observable around */
} run_t;

static const double coverage_marks[3] = {0.5, 0.8, 0.9};

/* Free cells whose centre the robot's centre can reach from the start (4-connected,
 * clear of obstacles by the body radius): the cells exploration could visit. */
static void reachable_cells(const room_t *room, const sim_params_t *p, run_t *r, uint32_t start)
{
    const map_geom_t *g = &r->geom;
    size_t n = (size_t)g->a * g->b;
    uint32_t *queue = malloc(n * sizeof *queue);
    if (queue == NULL) {
        return;
    }
    size_t head = 0;
    size_t tail = 0;
    r->reachable[start] = 1u;
    queue[tail++] = start;
    while (head < tail) {
        uint32_t c = queue[head++];
        uint32_t x = c % g->a;
        uint32_t y = c / g->a;
        const int32_t dx[4] = {1, -1, 0, 0};
        const int32_t dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; k++) {
            int64_t nx = (int64_t)x + dx[k];
            int64_t ny = (int64_t)y + dy[k];
            if (nx < 0 || ny < 0 || nx >= g->a || ny >= g->b) {
                continue;
            }
            uint32_t nc = (uint32_t)ny * g->a + (uint32_t)nx;
            if (r->reachable[nc] || r->truth[nc]) {
                continue;
            }
            double wx = g->origin_x + ((double)nx + 0.5) * g->cell_m;
            double wy = g->origin_y + ((double)ny + 0.5) * g->cell_m;
            if (!room_disc_free(room, wx, wy, p->body_radius_m)) {
                continue;
            }
            r->reachable[nc] = 1u;
            queue[tail++] = nc;
        }
    }
    r->reachable_cells = (uint32_t)tail;
    free(queue);
}

static double wrap_pi(double a)
{
    return remainder(a, 2.0 * PI);
}

/* After each tick: odometry error, coverage, and the reading of the tick if any. */
static void observe_tick(run_t *r, const sim_t *sim, const sim_truth_t *before,
                         const sim_params_t *p, FILE *readings, FILE *trajectory, uint64_t tick,
                         bool last)
{
    /* The firmware read its encoders at the start of the period: compare its pose with
     * the truth of that instant, not with the world already advanced by the period. */
    const sim_truth_t tr = *before;
    double t = (double)tick * TICK_S;
    double ox = robot.pose.x_um * 1e-6;
    double oy = robot.pose.y_um * 1e-6;
    double oth = bam_rad(robot.pose.heading);
    double ep = hypot(ox - tr.x, oy - tr.y);
    double eth = fabs(wrap_pi(oth - tr.th));
    r->max_pos_err = ep > r->max_pos_err ? ep : r->max_pos_err;
    r->max_th_err = eth > r->max_th_err ? eth : r->max_th_err;
    r->final_pos_err = ep;
    r->final_th_err = eth;
    r->path_m += hypot(tr.x - r->last_x, tr.y - r->last_y);
    r->last_x = tr.x;
    r->last_y = tr.y;

    /* Coverage: TM > 0 on a reachable cell. */
    grid_cell_t c;
    if (grid_cell_of(&robot.grid, robot.pose.x_um, robot.pose.y_um, &c) == SLAM_OK) {
        uint32_t i = grid_index(c);
        if (!r->seen[i]) {
            r->seen[i] = 1u;
            r->visited_cells += r->reachable[i];
            for (int k = 0; k < 3; k++) {
                if (r->time_to[k] < 0.0 &&
                    r->visited_cells >= coverage_marks[k] * r->reachable_cells) {
                    r->time_to[k] = t;
                }
            }
        }
    }
    if (((tick + 1u) % COVERAGE_EVERY == 0u || last) && r->nseries < 4096u) {
        r->series[r->nseries][0] = t;
        r->series[r->nseries][1] = r->reachable_cells ? (double)r->visited_cells / r->reachable_cells : 0.0;
        r->nseries++;
    }

    if (tick % TRAJECTORY_EVERY == 0u || last) {
        char line[160];
        char *e = fmt_fixed(line, t, 2, ',');
        e = fmt_fixed(e, ox, 6, ',');
        e = fmt_fixed(e, oy, 6, ',');
        e = fmt_fixed(e, wrap_pi(oth), 6, ',');
        e = fmt_fixed(e, tr.x, 6, ',');
        e = fmt_fixed(e, tr.y, 6, ',');
        e = fmt_fixed(e, wrap_pi(tr.th), 6, '\n');
        fwrite(line, 1, (size_t)(e - line), trajectory);
    }

    const sweep_out_t *sw = &robot.last;
    if (!sw->reading_ready) {
        return;
    }
    /* The reading of this tick, with the pose of its ping: odometry and truth. */
    sim_ping_t ping = sim_last_ping(sim);
    const odom_pose_t *op = &robot.mapper.ping_pose;
    double sx = ping.x + p->sonar_x_m * cos(ping.th) - p->sonar_y_m * sin(ping.th);
    double sy = ping.y + p->sonar_x_m * sin(ping.th) + p->sonar_y_m * cos(ping.th);
    /* Cells within rc of a sonar position are observable; a new disc only once the
     * sonar has moved by a cell (the disc's edge is then within a cell of exact). */
    if (hypot(sx - r->marked_x, sy - r->marked_y) >= r->geom.cell_m) {
        mark_disc(&r->geom, r->observable, sx, sy, robot.cfg.confidence_radius_um * 1e-6);
        r->marked_x = sx;
        r->marked_y = sy;
    }
    char line[256];
    char *e = fmt_fixed(line, t, 2, ',');
    e = fmt_fixed(e, sw->reading.servo_mdeg / 1000.0, 3, ',');
    if (sw->reading.echo) {
        uint32_t d = sonar_range_um(&robot.mapper.sonar, sw->reading.echo_us);
        e = fmt_fixed(e, d * 1e-6, 6, ',');
        memcpy(e, "ok,", 3);
        e += 3;
        odom_pose_t truth_pose = {to_um(ping.x), to_um(ping.y), to_bam(ping.th)};
        (void)mapper_reading(&ideal_mapper, &ideal_grid, &truth_pose, sw->reading.servo, d);
    } else {
        memcpy(e, ",timeout,", 9);
        e += 9;
    }
    /* Ten decimals of a radian are finer than half a binary angle unit (7e-10 rad), so
     * the replay recovers the exact heading. */
    e = fmt_fixed(e, op->x_um * 1e-6, 6, ',');
    e = fmt_fixed(e, op->y_um * 1e-6, 6, ',');
    e = fmt_fixed(e, bam_rad(op->heading), 10, ',');
    e = fmt_fixed(e, ping.x, 6, ',');
    e = fmt_fixed(e, ping.y, 6, ',');
    e = fmt_fixed(e, wrap_pi(ping.th), 6, '\n');
    fwrite(line, 1, (size_t)(e - line), readings);
}

/* ---- after the run -------------------------------------------------------------------- */

typedef struct {
    score_t raw, threshold, templ, insert;
} chain_scores_t;

/* Scores a map after each post-processing step; leaves the final map in out. */
static void score_chain(const run_t *r, const uint8_t *om, const slam_config_t *cfg,
                        uint8_t *out, uint8_t *scratch, chain_scores_t *s)
{
    const map_geom_t *g = &r->geom;
    size_t n = (size_t)g->a * g->b;
    score_map(g, om, r->truth, r->observable, &s->raw);
    memcpy(out, om, n);
    post_threshold(out, g->a, g->b, cfg->post_threshold, cfg->om_max);
    score_map(g, out, r->truth, r->observable, &s->threshold);
    post_template(out, g->a, g->b, cfg->post_template_k, scratch);
    score_map(g, out, r->truth, r->observable, &s->templ);
    post_insert(out, g->a, g->b, cfg->om_max, scratch);
    score_map(g, out, r->truth, r->observable, &s->insert);
}

static void json_score(FILE *f, const char *name, const score_t *s, bool comma)
{
    fprintf(f,
            "      \"%s\": {\"precision\": %.4f, \"recall\": %.4f, \"f1\": %.4f, "
            "\"mapped\": %u, \"true_positive\": %u, \"observable\": %u, \"matched\": %u}%s\n",
            name, s->precision, s->recall, s->f1, s->mapped, s->true_pos, s->observable,
            s->matched, comma ? "," : "");
}

static void json_chain(FILE *f, const char *name, const chain_scores_t *c, bool comma)
{
    fprintf(f, "    \"%s\": {\n", name);
    json_score(f, "raw", &c->raw, true);
    json_score(f, "threshold", &c->threshold, true);
    json_score(f, "template", &c->templ, true);
    json_score(f, "insert", &c->insert, false);
    fprintf(f, "    }%s\n", comma ? "," : "");
}

static void json_time(FILE *f, const char *name, double t, bool comma)
{
    if (t < 0.0) {
        fprintf(f, "    \"%s\": null%s\n", name, comma ? "," : "");
    } else {
        fprintf(f, "    \"%s\": %.2f%s\n", name, t, comma ? "," : "");
    }
}

/* The post-processing parameters over their whole range: F1 for every TH and K. */
#define SWEEP_K 9u
typedef struct {
    uint8_t th_count;
    score_t s[256][SWEEP_K];
    uint8_t best_th, best_k;
} post_sweep_t;

static void sweep_post(const run_t *r, const uint8_t *om, const slam_config_t *cfg,
                       uint8_t *out, uint8_t *scratch, post_sweep_t *ps)
{
    ps->th_count = cfg->om_max;
    double best = -1.0;
    for (uint8_t th = 0; th < cfg->om_max; th++) {
        for (uint8_t k = 0; k < SWEEP_K; k++) {
            post_params_t pp = {.threshold = th, .om_max = cfg->om_max, .k = k};
            (void)post_run(om, out, r->geom.a, r->geom.b, &pp, scratch);
            score_map(&r->geom, out, r->truth, r->observable, &ps->s[th][k]);
            if (ps->s[th][k].f1 > best) {
                best = ps->s[th][k].f1;
                ps->best_th = th;
                ps->best_k = k;
            }
        }
    }
}

static void json_sweep(FILE *f, const post_sweep_t *ps)
{
    const char *what[3] = {"precision", "recall", "f1"};
    fprintf(f, "  \"post_sweep\": {\n    \"threshold\": [0");
    for (unsigned th = 1; th < ps->th_count; th++) {
        fprintf(f, ", %u", th);
    }
    fprintf(f, "],\n    \"k\": [0, 1, 2, 3, 4, 5, 6, 7, 8],\n");
    for (int w = 0; w < 3; w++) {
        fprintf(f, "    \"%s\": [", what[w]);
        for (unsigned th = 0; th < ps->th_count; th++) {
            fprintf(f, "%s[", th ? ", " : "");
            for (unsigned k = 0; k < SWEEP_K; k++) {
                const score_t *s = &ps->s[th][k];
                double v = w == 0 ? s->precision : w == 1 ? s->recall : s->f1;
                fprintf(f, "%s%.4f", k ? ", " : "", v);
            }
            fprintf(f, "]");
        }
        fprintf(f, "],\n");
    }
    const score_t *b = &ps->s[ps->best_th][ps->best_k];
    fprintf(f, "    \"best\": {\"threshold\": %u, \"k\": %u, \"precision\": %.4f, "
               "\"recall\": %.4f, \"f1\": %.4f}\n  },\n",
            ps->best_th, ps->best_k, b->precision, b->recall, b->f1);
}

/* Grid cells an MCU would need to hold this room, plus a cell of margin each side. */
static uint32_t cells_needed(double span_m, double cell_m)
{
    return (uint32_t)ceil(span_m / cell_m) + 2u;
}

static int write_metrics(const options_t *o, const room_t *room, const run_t *r,
                         const slam_config_t *cfg, const sim_errors_t *e, const sim_t *sim,
                         const chain_scores_t *odo, const chain_scores_t *ideal,
                         const post_sweep_t *ps)
{
    FILE *f = open_out(o->out, "metrics.json");
    if (f == NULL) {
        return -1;
    }
    sim_truth_t tr = sim_truth(sim);
    fprintf(f, "{\n  \"scenario\": {\n");
    fprintf(f, "    \"room\": \"%s\",\n", o->room);
    if (o->has_crop) {
        fprintf(f, "    \"crop\": [%.3f, %.3f, %.3f, %.3f],\n", o->crop.x, o->crop.y, o->crop.w, o->crop.h);
    } else {
        fprintf(f, "    \"crop\": null,\n");
    }
    fprintf(f, "    \"room_bounds\": [%.3f, %.3f, %.3f, %.3f],\n", room->min_x, room->min_y,
            room->max_x, room->max_y);
    fprintf(f, "    \"start\": [%.3f, %.3f, %.2f],\n", cfg->start_x_um * 1e-6,
            cfg->start_y_um * 1e-6, cfg->start_heading_mdeg / 1000.0);
    fprintf(f, "    \"duration_s\": %.2f,\n    \"seed\": %llu,\n    \"cell_mm\": %.0f,\n",
            o->duration_s, (unsigned long long)o->seed, o->cell_mm);
    fprintf(f, "    \"explore\": \"%s\",\n    \"ideal\": %s,\n", explore_names[o->explore],
            o->ideal ? "true" : "false");
    fprintf(f, "    \"accel_mm_s2\": %u,\n", cfg->accel_mm_s2);
    fprintf(f, "    \"post\": {\"threshold\": %u, \"k\": %u, \"om_max\": %u},\n",
            cfg->post_threshold, cfg->post_template_k, cfg->om_max);
    fprintf(f, "    \"errors\": {\"ed\": %.6g, \"eb\": %.6g, \"slip\": %.6g, \"slip_free\": %.6g, "
               "\"noise\": %.6g, \"sonar_noise\": %.6g, \"dropout\": %.6g, \"ghost\": %.6g, "
               "\"grazing\": %.6g},\n",
            e->wheel_ratio_ed, e->wheel_base_eb, e->slip_per_mps2, e->slip_free_mps2, e->wheel_noise,
            e->sonar_noise_m, e->sonar_dropout, e->sonar_ghost, e->grazing_deg);
    fprintf(f, "    \"grid\": {\"a\": %u, \"b\": %u, \"origin\": [%.6f, %.6f]}\n  },\n",
            r->geom.a, r->geom.b, r->geom.origin_x, r->geom.origin_y);

    fprintf(f, "  \"maps\": {\n");
    json_chain(f, "odometry", odo, true);
    json_chain(f, "perfect_odometry", ideal, false);
    fprintf(f, "  },\n");
    json_sweep(f, ps);

    fprintf(f, "  \"odometry\": {\n    \"final_position_m\": %.4f,\n    \"max_position_m\": %.4f,\n"
               "    \"final_heading_deg\": %.3f,\n    \"max_heading_deg\": %.3f,\n"
               "    \"path_m\": %.3f\n  },\n",
            r->final_pos_err, r->max_pos_err, r->final_th_err * 180.0 / PI,
            r->max_th_err * 180.0 / PI, r->path_m);

    fprintf(f, "  \"exploration\": {\n    \"reachable_cells\": %u,\n    \"visited_cells\": %u,\n"
               "    \"coverage\": %.4f,\n", r->reachable_cells, r->visited_cells,
            r->reachable_cells ? (double)r->visited_cells / r->reachable_cells : 0.0);
    json_time(f, "time_to_50_s", r->time_to[0], true);
    json_time(f, "time_to_80_s", r->time_to[1], true);
    json_time(f, "time_to_90_s", r->time_to[2], true);
    fprintf(f, "    \"series\": [");
    for (size_t i = 0; i < r->nseries; i++) {
        fprintf(f, "%s[%.1f, %.4f]", i ? ", " : "", r->series[i][0], r->series[i][1]);
    }
    fprintf(f, "]\n  },\n");

    const sweep_t *sw = &robot.sweep;
    const mapper_t *m = &robot.mapper;
    fprintf(f, "  \"robot\": {\"ticks\": %u, \"pings\": %u, \"echoes\": %u, \"timeouts\": %u, "
               "\"om_hits\": %u, \"beyond_rc\": %u, \"too_close\": %u, \"outside_grid\": %u, "
               "\"collisions\": %u, \"turns\": %u, \"avoidances\": %u},\n",
            robot.ticks, sw->pings, sw->echoes, sw->timeouts, m->hits, m->far, m->near,
            m->outside, tr.collisions, robot.explore.turns, robot.explore.avoidances);

    double span_x = room->max_x - room->min_x;
    double span_y = room->max_y - room->min_y;
    uint32_t na = cells_needed(span_x, r->geom.cell_m);
    uint32_t nb = cells_needed(span_y, r->geom.cell_m);
    size_t state = sizeof(robot_t) - 2u * (size_t)SLAM_GRID_CELLS;
    fprintf(f, "  \"ram\": {\"grid_a\": %u, \"grid_b\": %u, \"maps_bytes\": %lu, "
               "\"state_bytes\": %zu, \"total_bytes\": %lu}\n}\n",
            na, nb, 2ul * na * nb, state, 2ul * na * nb + state);
    return close_out(f, o->out, "metrics.json");
}

/* Draws figure.png with tools/plot_run.py; a missing Python or matplotlib is a warning. */
static void plot(const char *out, bool quiet)
{
    const char *script = SLAM_SOURCE_DIR "/tools/plot_run.py";
    char *argv[] = {"/usr/bin/python3", (char *)script, (char *)out, NULL};
    pid_t pid;
    extern char **environ;
    if (access(argv[0], X_OK) != 0 || access(script, R_OK) != 0 ||
        posix_spawn(&pid, argv[0], NULL, NULL, argv, environ) != 0) {
        fprintf(stderr, "host_sim: cannot run %s; no figure (tools/install-deps.sh sim)\n", script);
        return;
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "host_sim: %s failed; no figure\n", script);
    } else if (!quiet) {
        printf("  figure          %s/figure.png\n", out);
    }
}

static void print_summary(const options_t *o, const run_t *r, const chain_scores_t *odo,
                          const chain_scores_t *ideal, const post_sweep_t *ps, double wall_s,
                          uint64_t ticks, const sim_t *sim)
{
    sim_truth_t tr = sim_truth(sim);
    printf("\nsonarslam host_sim: %s, %.0f s, seed %llu, %.0f mm cells, %s exploration%s\n",
           o->room, o->duration_s, (unsigned long long)o->seed, o->cell_mm,
           explore_names[o->explore], o->ideal ? ", ideal" : "");
    printf("  simulated %llu ticks in %.2f s of wall time: %.0fx real time\n",
           (unsigned long long)ticks, wall_s, wall_s > 0 ? (double)ticks * TICK_S / wall_s : 0.0);
    printf("\n  map (vs truth)        precision  recall     F1   | perfect odometry F1\n");
    const char *names[4] = {"raw OM", "+ threshold", "+ template", "+ insert (final)"};
    const score_t *a[4] = {&odo->raw, &odo->threshold, &odo->templ, &odo->insert};
    const score_t *b[4] = {&ideal->raw, &ideal->threshold, &ideal->templ, &ideal->insert};
    for (int i = 0; i < 4; i++) {
        printf("  %-20s    %6.3f  %6.3f  %6.3f   |  %6.3f\n", names[i], a[i]->precision,
               a[i]->recall, a[i]->f1, b[i]->f1);
    }
    const score_t *best = &ps->s[ps->best_th][ps->best_k];
    printf("  best TH=%u K=%u          %6.3f  %6.3f  %6.3f\n", ps->best_th, ps->best_k,
           best->precision, best->recall, best->f1);
    printf("\n  odometry error  final %.3f m, %.2f deg; max %.3f m, %.2f deg (path %.1f m)\n",
           r->final_pos_err, r->final_th_err * 180.0 / PI, r->max_pos_err,
           r->max_th_err * 180.0 / PI, r->path_m);
    printf("  coverage        %.1f %% of %u reachable cells visited; collisions %u\n",
           r->reachable_cells ? 100.0 * r->visited_cells / r->reachable_cells : 0.0,
           r->reachable_cells, tr.collisions);
    printf("  outputs         %s/\n", o->out);
}

/* ---- replay --------------------------------------------------------------------------- */

/* Rebuilds OM from a readings.csv through the same mapper (the config of its run comes
 * from config.txt beside it, or --config). */
static int replay(const options_t *o)
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
    grid_init(&robot.grid, &cfg);
    mapper_init(&robot.mapper, &cfg);
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
        if (strcmp(status, "ok") != 0) {
            continue;
        }
        odom_pose_t p = {to_um(x), to_um(y), to_bam(th)};
        bam32_t sv = fix_bam_from_mdeg((int32_t)lround(servo * 1000.0));
        (void)mapper_reading(&robot.mapper, &robot.grid, &p, sv, (uint32_t)lround(range * 1e6));
    }
    fclose(in);
    if (rc != 0) {
        return rc;
    }
    if (make_dirs(o->out) != 0) {
        return 1;
    }
    map_geom_t g = {SLAM_GRID_A, SLAM_GRID_B, cfg.cell_um * 1e-6, robot.grid.origin_x_um * 1e-6,
                    robot.grid.origin_y_um * 1e-6};
    double th = (cfg.post_threshold + 0.5) / cfg.om_max;
    if (write_map(o->out, "om", &g, robot.grid.om, cfg.om_max, th, 0.5 / cfg.om_max) != 0) {
        return 1;
    }
    if (!o->quiet) {
        printf("host_sim: replayed %u readings (%u OM hits) into %s/om.pgm\n", rows,
               robot.mapper.hits, o->out);
    }
    return 0;
}

/* ---- main ----------------------------------------------------------------------------- */

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    options_t o;
    int rc = parse_options(argc, argv, &o);
    if (rc != 0) {
        return rc;
    }
    if (o.replay != NULL) {
        return replay(&o);
    }

    /* Everything that can be wrong with the input is checked before anything is written. */
    room_t room;
    char err[1024];
    if (room_load(&room, o.room, o.has_crop ? &o.crop : NULL, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    sim_params_t params;
    sim_params_default(&params);
    double sx = room.start_x;
    double sy = room.start_y;
    double sth = room.start_th;
    if (o.has_start) {
        sx = o.start_x;
        sy = o.start_y;
        sth = o.start_deg * PI / 180.0;
        if (!room_disc_free(&room, sx, sy, params.body_radius_m)) {
            fprintf(stderr, "host_sim: --start %.3f %.3f is inside or against an obstacle\n", sx, sy);
            room_free(&room);
            return EXIT_USAGE;
        }
    } else if (!room.has_start &&
               room_find_start(&room, params.body_radius_m + 0.05, &sx, &sy, &sth) != 0) {
        fprintf(stderr, "host_sim: %s: no free start pose; give one with --start\n", o.room);
        room_free(&room);
        return EXIT_USAGE;
    }
    sim_errors_t errors;
    if (o.ideal) {
        sim_errors_ideal(&errors);
    } else {
        sim_errors_default(&errors);
    }
    for (size_t i = 0; i < o.nerrors; i++) {
        if (apply_error(&errors, o.errors[i]) != 0) {
            room_free(&room);
            return EXIT_USAGE;
        }
    }
    slam_config_t cfg;
    if (build_config(&o, &room, sx, sy, sth, &cfg) != 0) {
        room_free(&room);
        return EXIT_USAGE;
    }
    build_params(&cfg, &params);
    /* The world starts the robot at the room's start pose: the one chosen above. */
    room.start_x = sx;
    room.start_y = sy;
    room.start_th = sth;
    const char *bad_param = NULL;
    if (sim_params_check(&params, &errors, &bad_param) != 0) {
        fprintf(stderr, "host_sim: the simulated robot refuses %s\n", bad_param);
        room_free(&room);
        return EXIT_USAGE;
    }
    sim_t *sim = sim_create(&room, &params, &errors, o.seed);
    if (sim == NULL) {
        fprintf(stderr, "host_sim: the robot does not fit at the start pose (%.3f, %.3f)\n", sx, sy);
        room_free(&room);
        return EXIT_USAGE;
    }

    if (make_dirs(o.out) != 0) {
        room_free(&room);
        return 1;
    }
    FILE *cfgf = open_out(o.out, "config.txt");
    if (cfgf == NULL) {
        room_free(&room);
        return 1;
    }
    fprintf(cfgf, "# firmware configuration of this run (host_sim --replay reads it)\n");
    cfgtext_write(cfgf, &cfg);
    if (close_out(cfgf, o.out, "config.txt") != 0) {
        room_free(&room);
        return 1;
    }
    FILE *readings = open_out(o.out, "readings.csv");
    FILE *trajectory = open_out(o.out, "trajectory.csv");
    FILE *trace = NULL;
    if (o.trace != NULL) {
        trace = fopen(o.trace, "w");
        if (trace == NULL) {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", o.trace, strerror(errno));
        }
    }
    FILE *telemetry = NULL;
    if (o.telemetry != NULL) {
        telemetry = fopen(o.telemetry, "wb");
        if (telemetry == NULL) {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", o.telemetry, strerror(errno));
        }
    }
    run_t *r = calloc(1, sizeof *r);
    size_t ncells = (size_t)SLAM_GRID_CELLS;
    uint8_t *bufs = calloc(7u, ncells);
    uint8_t *scratch = calloc(2u, SLAM_GRID_A);
    if (readings == NULL || trajectory == NULL || (o.trace != NULL && trace == NULL) ||
        (o.telemetry != NULL && telemetry == NULL) || r == NULL || bufs == NULL ||
        scratch == NULL) {
        fprintf(stderr, "host_sim: cannot start the run (out of memory, or an output file)\n");
        return 1;
    }
    fprintf(readings, "t,servo_deg,range_m,status,odom_x,odom_y,odom_th,true_x,true_y,true_th\n");
    fprintf(trajectory, "t,odom_x,odom_y,odom_th,true_x,true_y,true_th\n");

    hal_host_attach(sim);
    if (hal_init() != HAL_OK || robot_init(&robot, &cfg) != SLAM_OK ||
        hal_tick_start(tick_callback, &robot) != HAL_OK) {
        fprintf(stderr, "host_sim: the firmware did not start\n");
        return 1;
    }
    grid_init(&ideal_grid, &cfg);
    mapper_init(&ideal_mapper, &cfg);
    if (trace != NULL) {
        trace_write_header(trace, &cfg);
        hal_host_trace(trace);
    }
    if (telemetry != NULL) {
        setvbuf(telemetry, NULL, _IONBF, 0); /* a viewer may be following the file */
        hal_host_uart_sink(telemetry);
    }

    r->geom = (map_geom_t){SLAM_GRID_A, SLAM_GRID_B, cfg.cell_um * 1e-6,
                           robot.grid.origin_x_um * 1e-6, robot.grid.origin_y_um * 1e-6};
    r->truth = bufs;
    r->observable = bufs + ncells;
    r->reachable = bufs + 2u * ncells;
    r->seen = bufs + 3u * ncells;
    uint8_t *post = bufs + 4u * ncells;
    uint8_t *ideal_post = bufs + 5u * ncells;
    uint8_t *work = bufs + 6u * ncells;
    room_rasterize(&room, r->geom.origin_x, r->geom.origin_y, r->geom.cell_m, r->geom.a,
                   r->geom.b, r->truth);
    grid_cell_t start;
    (void)grid_cell_of(&robot.grid, cfg.start_x_um, cfg.start_y_um, &start);
    reachable_cells(&room, &params, r, grid_index(start));
    r->time_to[0] = r->time_to[1] = r->time_to[2] = -1.0;
    r->last_x = sx;
    r->last_y = sy;
    r->marked_x = r->marked_y = INFINITY;

    uint64_t ticks = (uint64_t)llround(o.duration_s / TICK_S);
    bool progress = !o.quiet && isatty(STDERR_FILENO);
    double t0 = wall_now();
    for (uint64_t k = 0; k < ticks; k++) {
        sim_truth_t before = sim_truth(sim);
        hal_host_step();
        robot_idle(&robot); /* the robot's background loop runs between ticks */
        observe_tick(r, sim, &before, &params, readings, trajectory, k, k + 1u == ticks);
        if (o.realtime) {
            double ahead = (double)(k + 1u) * TICK_S - (wall_now() - t0);
            if (ahead > 0.0) {
                struct timespec ts = {(time_t)ahead, (long)((ahead - floor(ahead)) * 1e9)};
                nanosleep(&ts, NULL);
            }
        }
        if (progress && (k % 4096u == 0u || k + 1u == ticks)) {
            double done = (double)(k + 1u) / (double)ticks;
            int bar = (int)(done * 30.0);
            double w = wall_now() - t0;
            fprintf(stderr, "\r  simulating %7.1f s / %.0f s [%-30.*s] %3.0f%%  %6.0fx real time ",
                    (double)(k + 1u) * TICK_S, o.duration_s, bar,
                    "##############################", done * 100.0,
                    w > 0 ? (double)(k + 1u) * TICK_S / w : 0.0);
        }
    }
    double wall_s = wall_now() - t0;
    if (progress) {
        fprintf(stderr, "\n");
    }
    if (telemetry != NULL) {
        hal_host_uart_sink(NULL);
        if (fclose(telemetry) != 0) {
            fprintf(stderr, "host_sim: writing %s failed\n", o.telemetry);
            return 1;
        }
    }
    if (trace != NULL) {
        hal_host_trace(NULL); /* writes the end line */
        if (fclose(trace) != 0) {
            fprintf(stderr, "host_sim: writing %s failed\n", o.trace);
            return 1;
        }
    }
    int bad = close_out(readings, o.out, "readings.csv") | close_out(trajectory, o.out, "trajectory.csv");

    chain_scores_t odo;
    chain_scores_t ideal;
    score_chain(r, robot.grid.om, &cfg, post, scratch, &odo);
    score_chain(r, ideal_grid.om, &cfg, ideal_post, scratch, &ideal);
    post_sweep_t *ps = calloc(1, sizeof *ps);
    if (ps == NULL) {
        return 1;
    }
    sweep_post(r, robot.grid.om, &cfg, work, scratch, ps);

    double om_th = (cfg.post_threshold + 0.5) / cfg.om_max;
    double om_free = 0.5 / cfg.om_max;
    bad |= write_map(o.out, "om", &r->geom, robot.grid.om, cfg.om_max, om_th, om_free);
    bad |= write_map(o.out, "om_post", &r->geom, post, cfg.om_max, 0.5, 0.25);
    bad |= write_map(o.out, "om_ideal", &r->geom, ideal_grid.om, cfg.om_max, om_th, om_free);
    bad |= write_map(o.out, "tm", &r->geom, robot.grid.tm, cfg.tm_max, 0.99, 0.01);
    bad |= write_map(o.out, "truth", &r->geom, r->truth, 1u, 0.65, 0.196);
    bad |= write_metrics(&o, &room, r, &cfg, &errors, sim, &odo, &ideal, ps);
    FILE *tf = open_out(o.out, "timing.json");
    if (tf != NULL) {
        fprintf(tf, "{\"wall_s\": %.3f, \"ticks\": %llu, \"ticks_per_s\": %.0f, "
                    "\"real_time_factor\": %.0f}\n",
                wall_s, (unsigned long long)ticks, wall_s > 0 ? (double)ticks / wall_s : 0.0,
                wall_s > 0 ? (double)ticks * TICK_S / wall_s : 0.0);
        bad |= close_out(tf, o.out, "timing.json");
    }
    if (!o.quiet) {
        print_summary(&o, r, &odo, &ideal, ps, wall_s, ticks, sim);
    }
    if (o.plot && bad == 0) {
        plot(o.out, o.quiet);
    }
    free(ps);
    free(scratch);
    free(bufs);
    free(r);
    sim_destroy(sim);
    room_free(&room);
    return bad ? 1 : 0;
}
