/* SPDX-License-Identifier: MIT */
/*
 * host_sim: the robot's unchanged firmware exploring a simulated room. Runs a scenario
 * through robot_init/robot_tick on the host backend, then writes the maps, the
 * trajectories, the sonar log, a score against ground truth and a picture.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "hal/hal.h"
#include "hal_common/config_text.h"
#include "hal_common/mapexport.h"
#include "hal_common/trace.h"
#include "host_sim.h"
#include "slam/error.h"

static const double PI = HOST_SIM_PI;
#define TRAJECTORY_EVERY 10u     /* trajectory.csv: one row per 0.1 s */
#define COVERAGE_EVERY 1000u     /* the coverage series: one point per 10 s */

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

    /* The perfect-odometry maps' TM, at the true pose. */
    (void)grid_tm_visit(&ideal_grid, to_um(tr.x), to_um(tr.y));

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
    sim_truth_t after = sim_truth(sim);
    clearance_tick(r, after.x, after.y);
    touch_tick(r, after.contact, after.x, after.y, after.th, t, ep, eth);
    if (((tick + 1u) % COVERAGE_EVERY == 0u || last) && r->nseries < 4096u) {
        r->series[r->nseries][0] = t;
        r->series[r->nseries][1] = r->reachable_cells ? (double)r->visited_cells / r->reachable_cells : 0.0;
        r->series[r->nseries][2] = r->wall_cells ? (double)r->walls_covered / r->wall_cells : 0.0;
        r->nseries++;
    }

    if (tick % TRAJECTORY_EVERY == 0u || last) {
        char line[192];
        char *e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
        e = fmt_fixed(e, ox, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, oy, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, wrap_pi(oth), CSV_HEADING_DECIMALS, ',');
        e = fmt_fixed(e, tr.x, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, tr.y, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, wrap_pi(tr.th), CSV_HEADING_DECIMALS, '\n');
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
    walls_ping(r, sx, sy, ping.bearing, t);
    char line[256];
    char *e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
    e = fmt_fixed(e, sw->reading.servo_mdeg / 1000.0, CSV_SERVO_DECIMALS, ',');
    uint32_t d = 0u;
    odom_pose_t truth_pose = {to_um(ping.x), to_um(ping.y), to_bam(ping.th)};
    if (sw->reading.echo) {
        d = sonar_range_um(&robot.mapper.sonar, sw->reading.echo_us);
        e = fmt_fixed(e, d * 1e-6, CSV_LENGTH_DECIMALS, ',');
        (void)mapper_reading(&ideal_mapper, &ideal_grid, &truth_pose, sw->reading.servo, d);
    } else {
        *e++ = ',';
        mapper_timeout(&ideal_mapper, &ideal_grid, &truth_pose);
    }
    const char *status = reading_status(&robot.mapper.sonar, sw->reading.echo, d);
    size_t n = strlen(status);
    memcpy(e, status, n);
    e += n;
    *e++ = ',';
    e = fmt_fixed(e, op->x_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, op->y_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(bam_rad(op->heading)), CSV_HEADING_DECIMALS, ',');
    e = fmt_fixed(e, ping.x, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, ping.y, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(ping.th), CSV_HEADING_DECIMALS, '\n');
    fwrite(line, 1, (size_t)(e - line), readings);
    if (r->estimates != NULL) {
        /* Where the robot believed the ping was (odometry and the correction of the tick),
         * for a mapper outside this program to map from the firmware's estimate. */
        odom_pose_t est = loc_tick_pose(&robot.loc, op);
        e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
        e = fmt_fixed(e, est.x_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, est.y_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, wrap_pi(bam_rad(est.heading)), CSV_HEADING_DECIMALS, '\n');
        fwrite(line, 1, (size_t)(e - line), r->estimates);
    }
}

/* ---- main ----------------------------------------------------------------------------- */

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The start pose must lie inside the room: rays in eight directions all meet a wall. */
static int check_enclosed(const options_t *o, const room_t *room, double sx, double sy)
{
    double dir_deg = 0.0;
    if (room_encloses(room, sx, sy, &dir_deg)) {
        return 0;
    }
    char who[1100];
    if (o->has_start) {
        snprintf(who, sizeof who, "--start %g %g", sx, sy);
    } else if (room->start_line != 0u) {
        snprintf(who, sizeof who, "%s:%u: start pose (%g, %g)", o->room, room->start_line, sx, sy);
    } else {
        snprintf(who, sizeof who, "%s: start pose (%g, %g)", o->room, sx, sy);
    }
    fprintf(stderr, "host_sim: %s is outside the room: a ray toward %.0f deg meets no wall\n",
            who, dir_deg);
    return -1;
}

/* What a run holds; freed in one place whatever happened. */
typedef struct {
    room_t room;
    sim_t *sim;
    FILE *readings, *trajectory, *trace, *telemetry;
    run_t *r;
    uint8_t *bufs, *scratch;
    post_sweep_t *ps;
    commands_t commands;
    experimenter_t tape;
} held_t;

static void release(held_t *h)
{
    hal_host_uart_sink(NULL);
    if (h->trace != NULL) {
        hal_host_trace(NULL);
        fclose(h->trace);
    }
    if (h->telemetry != NULL) {
        fclose(h->telemetry);
    }
    if (h->readings != NULL) {
        fclose(h->readings);
    }
    if (h->trajectory != NULL) {
        fclose(h->trajectory);
    }
    if (h->tape.csv != NULL) {
        fclose(h->tape.csv);
    }
    hal_host_attach(NULL);
    if (h->r != NULL && h->r->estimates != NULL) {
        fclose(h->r->estimates);
    }
    free(h->ps);
    free(h->scratch);
    free(h->bufs);
    free(h->r);
    sim_destroy(h->sim);
    room_free(&h->room);
    commands_free(&h->commands);
}

/* A write error in a file being written as the robot runs: say which, once. */
static bool write_failed(FILE *f, const char *name)
{
    if (f != NULL && ferror(f)) {
        fprintf(stderr, "host_sim: writing %s failed: %s\n", name, strerror(errno));
        return true;
    }
    return false;
}

/* Checks the input, then the outputs, then runs: 0, EXIT_USAGE or 1. */
static int run(options_t *o, held_t *h)
{
    /* Everything that can be wrong with the input is checked before anything is written. */
    char err[1024];
    if (room_load(&h->room, o->room, o->has_crop ? &o->crop : NULL, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    room_t *room = &h->room;
    sim_params_t params;
    sim_params_default(&params);
    double sx = room->start_x;
    double sy = room->start_y;
    double sth = room->start_th;
    if (o->has_start) {
        sx = o->start_x;
        sy = o->start_y;
        sth = o->start_deg * PI / 180.0;
        if (!room_disc_free(room, sx, sy, params.body_radius_m)) {
            fprintf(stderr, "host_sim: --start %g %g is inside or against an obstacle\n", sx, sy);
            return EXIT_USAGE;
        }
    } else if (!room->has_start &&
               room_find_start(room, params.body_radius_m + 0.05, &sx, &sy, &sth) != 0) {
        fprintf(stderr, "host_sim: %s: no free start pose; give one with --start\n", o->room);
        return EXIT_USAGE;
    }
    if (check_enclosed(o, room, sx, sy) != 0) {
        return EXIT_USAGE;
    }
    sim_errors_t errors;
    if (o->ideal) {
        sim_errors_ideal(&errors);
    } else {
        sim_errors_default(&errors);
    }
    for (size_t i = 0; i < o->nerrors; i++) {
        if (apply_error(&errors, o->errors[i]) != 0) {
            return EXIT_USAGE;
        }
    }
    /* The shipped calibration belongs to the default robot: not to an ideal one, nor to
     * one with other wheels. */
    sim_errors_t defaults;
    sim_errors_default(&defaults);
    if (o->calibration == NULL) {
        bool default_robot = !o->ideal && errors.wheel_ratio_ed == defaults.wheel_ratio_ed &&
                             errors.wheel_base_eb == defaults.wheel_base_eb;
        o->calibration = default_robot ? SLAM_SOURCE_DIR HOST_SIM_CALIBRATION : NULL;
    } else if (strcmp(o->calibration, "none") == 0) {
        o->calibration = NULL;
    }
    slam_config_t cfg;
    if (build_config(o, room, sx, sy, sth, &cfg) != 0) {
        return EXIT_USAGE;
    }
    /* One source of truth: what the report says is what the firmware runs with. */
    o->cell_mm = cfg.cell_um / 1000.0;
    o->explore = cfg.explore_mode;
    if (o->commands != NULL) {
        int rc = commands_load(o->commands, &h->commands);
        if (rc != 0) {
            return rc;
        }
    }
    build_params(&cfg, &params);
    /* The world starts the robot at the room's start pose: the one chosen above. */
    room->start_x = sx;
    room->start_y = sy;
    room->start_th = sth;
    const char *bad_param = NULL;
    if (sim_params_check(&params, &errors, &bad_param) != 0) {
        fprintf(stderr, "host_sim: the simulated robot refuses %s\n", bad_param);
        return EXIT_USAGE;
    }
    h->sim = sim_create(room, &params, &errors, o->seed);
    if (h->sim == NULL) {
        fprintf(stderr, "host_sim: the robot does not fit at the start pose (%g, %g)\n", sx, sy);
        return EXIT_USAGE;
    }
    if (check_outputs(o) != 0) {
        return EXIT_USAGE;
    }

    /* From here on only a failure while running can go wrong: exit 1, and every file of
     * --out that was there before stays as it was. */
    size_t ncells = (size_t)SLAM_GRID_CELLS;
    h->r = calloc(1, sizeof *h->r);
    h->bufs = calloc(9u, ncells);
    h->scratch = calloc(2u, SLAM_GRID_A);
    h->ps = calloc(1, sizeof *h->ps);
    if (h->r == NULL || h->bufs == NULL || h->scratch == NULL || h->ps == NULL) {
        fprintf(stderr, "host_sim: out of memory\n");
        return 1;
    }
    if (make_dirs(o->out) != 0) {
        return 1;
    }
    FILE *cfgf = open_out(o->out, "config.txt");
    if (cfgf == NULL) {
        return 1;
    }
    fprintf(cfgf, "# firmware configuration of this run (host_sim --replay reads it)\n");
    cfgtext_write(cfgf, &cfg);
    if (close_out(cfgf, o->out, "config.txt") != 0) {
        return 1;
    }
    h->readings = open_out(o->out, "readings.csv");
    h->trajectory = open_out(o->out, "trajectory.csv");
    if (h->readings == NULL || h->trajectory == NULL) {
        return 1;
    }
    if (o->trace != NULL && (h->trace = open_out(NULL, o->trace)) == NULL) {
        return 1;
    }
    if (o->telemetry != NULL) {
        /* Written as it goes, in place: a viewer may be following the file. */
        h->telemetry = fopen(o->telemetry, "wb");
        if (h->telemetry == NULL) {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", o->telemetry, strerror(errno));
            return 1;
        }
    }
    FILE *readings = h->readings;
    FILE *trajectory = h->trajectory;
    run_t *r = h->r;
    fprintf(readings, "%s,%s\n", CSV_READINGS_HEADER, CSV_TRUTH_COLUMNS);
    fprintf(trajectory, "%s\n", CSV_TRAJECTORY_HEADER);
    if (o->scoring) {
        r->estimates = open_out(o->out, "scoring_estimate.csv");
        if (r->estimates == NULL) {
            return 1;
        }
        fprintf(r->estimates, "%s\n", CSV_ESTIMATE_HEADER);
    }

    sim_t *sim = h->sim;
    hal_host_attach(sim);
    if (o->storage != NULL) {
        /* Room for a record of this grid: the robot now saves its maps every
         * save_period_s, and stands still while a save begins, as a real one does. */
        hal_host_storage_resize(sizeof(mapstore_header_t) + 2u * (size_t)SLAM_GRID_CELLS);
    }
    if (hal_init() != HAL_OK || robot_init(&robot, &cfg) != SLAM_OK ||
        hal_tick_start(tick_callback, &robot) != HAL_OK) {
        fprintf(stderr, "host_sim: the firmware did not start\n");
        return 1;
    }
    grid_init(&ideal_grid, &cfg);
    mapper_init(&ideal_mapper, &cfg);
    if (h->trace != NULL) {
        trace_write_header(h->trace, &cfg);
        hal_host_trace(h->trace);
    }
    if (h->telemetry != NULL) {
        setvbuf(h->telemetry, NULL, _IONBF, 0); /* a viewer may be following the file */
        hal_host_uart_sink(h->telemetry);
    }

    uint8_t *bufs = h->bufs;
    r->geom = map_geom_of(&robot.grid);
    r->truth = bufs;
    r->observable = bufs + ncells;
    r->reachable = bufs + 2u * ncells;
    r->seen = bufs + 3u * ncells;
    uint8_t *post = bufs + 4u * ncells;
    uint8_t *ideal_post = bufs + 5u * ncells;
    uint8_t *work = bufs + 6u * ncells;
    r->wall = bufs + 7u * ncells;
    r->wall_seen = bufs + 8u * ncells;
    room_rasterize(room, r->geom.origin_x, r->geom.origin_y, r->geom.cell_m, r->geom.a,
                   r->geom.b, r->truth);
    grid_cell_t start;
    (void)grid_cell_of(&robot.grid, cfg.start_x_um, cfg.start_y_um, &start);
    reachable_cells(room, &params, r, grid_index(start));
    if (walls_init(r, room, &params, cfg.confidence_radius_um * 1e-6, grid_index(start)) != 0) {
        fprintf(stderr, "host_sim: out of memory\n");
        return 1;
    }
    r->time_to[0] = r->time_to[1] = r->time_to[2] = -1.0;
    r->last_x = sx;
    r->last_y = sy;
    r->marked_x = r->marked_y = HUGE_VAL;

    uint64_t ticks = (uint64_t)llround(o->duration_s / TICK_S);
    /* UMBmark says how far it is itself, a line a run. */
    bool progress = !o->quiet && isatty(STDERR_FILENO) && o->explore != EXPLORE_UMBMARK;
    experimenter_t *tape = &h->tape;
    experimenter_init(tape, o->out, o->seed, sx, sy, sth, o->quiet);
    int tape_rc = 0;
    double t0 = wall_now();
    for (uint64_t k = 0; k < ticks; k++) {
        sim_truth_t before = sim_truth(sim);
        hal_host_step();
        commands_feed(&h->commands, k);
        robot_idle(&robot); /* the robot's background loop runs between ticks */
        /* UMBmark: a run measured and the robot carried back; the run ends after the last. */
        tape_rc = experimenter_tick(tape, sim, &robot);
        if (tape_rc == 2 || tape_rc < 0) {
            ticks = k + 1u;
        }
        observe_tick(r, sim, &before, &params, readings, trajectory, k, k + 1u == ticks);
        if (tape_rc > 0) {
            r->last_x = sx; /* carried, not driven: no path */
            r->last_y = sy;
        }
        if (k % 1024u == 0u &&
            (write_failed(h->telemetry, o->telemetry) || write_failed(h->trace, o->trace) ||
             write_failed(readings, "readings.csv") || write_failed(trajectory, "trajectory.csv"))) {
            return 1;
        }
        if (o->realtime) {
            double ahead = (double)(k + 1u) * TICK_S / o->realtime_factor - (wall_now() - t0);
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
                    (double)(k + 1u) * TICK_S, o->duration_s, bar,
                    "##############################", done * 100.0,
                    w > 0 ? (double)(k + 1u) * TICK_S / w : 0.0);
        }
    }
    double wall_s = wall_now() - t0;
    if (progress) {
        fprintf(stderr, "\n");
    }
    int bad = 0;
    if (h->telemetry != NULL) {
        hal_host_uart_sink(NULL);
        bad |= write_failed(h->telemetry, o->telemetry) ? -1 : 0;
        if (fclose(h->telemetry) != 0 && bad == 0) {
            fprintf(stderr, "host_sim: writing %s failed: %s\n", o->telemetry, strerror(errno));
            bad = -1;
        }
        h->telemetry = NULL;
    }
    if (h->trace != NULL) {
        hal_host_trace(NULL); /* writes the end line */
        bad |= close_out(h->trace, NULL, o->trace);
        h->trace = NULL;
    }
    bad |= close_out(readings, o->out, "readings.csv");
    bad |= close_out(trajectory, o->out, "trajectory.csv");
    h->readings = h->trajectory = NULL;
    if (r->estimates != NULL) {
        bad |= close_out(r->estimates, o->out, "scoring_estimate.csv");
        r->estimates = NULL;
    }
    bad |= experimenter_close(tape) | (tape_rc < 0 ? -1 : 0);
    if (bad != 0) {
        return 1;
    }

    /* The hits still held back for matching belong in the map too (a replay does the same). */
    loc_flush(&robot.loc, &robot.mapper, &robot.grid);

    chain_scores_t odo;
    chain_scores_t ideal;
    score_chain(r, robot.grid.om, &cfg, post, h->scratch, &odo);
    score_chain(r, ideal_grid.om, &cfg, ideal_post, h->scratch, &ideal);
    post_sweep_t *ps = h->ps;
    sweep_post(r, robot.grid.om, &cfg, work, h->scratch, ps);

    /* Every map in the one trinary meaning (hal_common/mapexport.h); TM as counts. */
    const uint32_t A = r->geom.a;
    const uint32_t B = r->geom.b;
    mapx_trinary(cfg.om_mode, robot.grid.om, robot.grid.tm, NULL, A, B, work);
    bad |= write_map(o->out, "om", &r->geom, work, true);
    mapx_trinary(cfg.om_mode, robot.grid.om, robot.grid.tm, post, A, B, work);
    bad |= write_map(o->out, "om_post", &r->geom, work, true);
    mapx_trinary(cfg.om_mode, ideal_grid.om, ideal_grid.tm, NULL, A, B, work);
    bad |= write_map(o->out, "om_ideal", &r->geom, work, true);
    mapx_counts(robot.grid.tm, cfg.tm_max, A, B, work);
    bad |= write_map(o->out, "tm", &r->geom, work, false);
    if (truth_image(&r->geom, r->truth, grid_index(start), work) != 0) {
        fprintf(stderr, "host_sim: out of memory\n");
        return 1;
    }
    bad |= write_map(o->out, "truth", &r->geom, work, true);
    if (o->scoring) {
        /* What score_map() counts against, for a scorer outside this program
         * (tools/compare.py): black where a mask is set, the orientation of om.pgm. */
        mapx_counts(r->truth, 1u, A, B, work);
        bad |= write_map(o->out, "scoring_truth", &r->geom, work, false);
        mapx_counts(r->observable, 1u, A, B, work);
        bad |= write_map(o->out, "scoring_observable", &r->geom, work, false);
    }
    bad |= write_metrics(o, room, r, &cfg, &errors, sim, &robot, &odo, &ideal, ps);
    if (o->storage != NULL) {
        bad |= write_storage(o->storage);
    }
    FILE *tf = open_out(o->out, "timing.json");
    if (tf == NULL) {
        return 1;
    }
    fprintf(tf, "{\"wall_s\": %.3f, \"ticks\": %llu, \"ticks_per_s\": %.0f, "
                "\"real_time_factor\": %.0f}\n",
            wall_s, (unsigned long long)ticks, wall_s > 0 ? (double)ticks / wall_s : 0.0,
            wall_s > 0 ? (double)ticks * TICK_S / wall_s : 0.0);
    bad |= close_out(tf, o->out, "timing.json");
    if (bad != 0 || outputs_commit() != 0) {
        return 1;
    }
    if (!o->quiet) {
        print_summary(o, r, &odo, &ideal, ps, wall_s, ticks, sim, &robot);
    }
    if (o->plot) {
        plot_figure(o->out, o->quiet);
    }
    if (h->commands.dropped != 0u) {
        fprintf(stderr, "host_sim: %s: %zu command bytes found the UART full and were lost\n",
                o->commands, h->commands.dropped);
    }
    return 0;
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
    static held_t held;
    rc = run(&o, &held);
    if (rc != 0) {
        outputs_discard();
    }
    release(&held);
    return rc;
}
