/* SPDX-License-Identifier: MIT */
/*
 * host_sim: the robot's unchanged firmware exploring a simulated room. Runs a scenario
 * through robot_init/robot_tick on the host backend, then writes the maps, the
 * trajectories, the sonar log, a score against ground truth and a picture.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
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
#include "viewers.h"

static firmware_t fw; /* the firmware's state, as a robot program owns it, and its twin */

/* A stop asked for by SIGINT, SIGTERM or SIGHUP: the run ends at the next period, writes
 * nothing and removes its temporary files, so an interrupted run leaves --out as it was.
 * A second signal ends the program at once (the next run sweeps what that leaves). */
static volatile sig_atomic_t stop_signal;

static void on_stop(int sig)
{
    stop_signal = sig;
}

static void watch_signals(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_stop;
        sa.sa_flags = (int)SA_RESETHAND;
        sigemptyset(&sa.sa_mask);
        sigaction(sigs[i], &sa, NULL);
    }
    /* A pipe whose reader went away (--telemetry /dev/stdout | head) is a failed write,
     * reported with exit 1, not a silent death by SIGPIPE. */
    signal(SIGPIPE, SIG_IGN);
}

/* The stop signal, said once; true when the run must end. */
static bool stopped(void)
{
    if (stop_signal != 0) {
        fprintf(stderr,
                "\nhost_sim: stopped by signal %d: nothing written, the earlier outputs "
                "stay as they were\n",
                (int)stop_signal);
        return true;
    }
    return false;
}

static void tick_callback(void *ctx)
{
    robot_tick(ctx);
}

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* ---- what a run holds ------------------------------------------------------------------- */

/* The buffers of the run's end. */
typedef struct {
    uint8_t *post;       /* OM post-processed, from the robot's poses */
    uint8_t *ideal_post; /* the same from the true poses */
    uint8_t *work;       /* a map being swept or exported */
    uint8_t *scratch;    /* two grid rows for the post-processing */
    post_sweep_t *ps;    /* the post-processing sweep's scores */
} end_bufs_t;

/* What a run holds; freed in one place whatever happened. */
typedef struct {
    scenario_t sc;
    run_logs_t logs;
    run_t *r; /* with its maps, each allocated */
    end_bufs_t end;
    experimenter_t tape;
    uint32_t start_cell; /* the grid index of the start cell */
    link_t link;         /* --link */
} held_t;

/* What the loop did. */
typedef struct {
    uint64_t ticks; /* ticks run */
    double wall_s;  /* wall-clock time they took */
    int tape_rc;    /* the experimenter's last answer */
} outcome_t;

/* Every buffer of the run, each its own zeroed allocation: 0, or 1 with a message. */
static int alloc_buffers(held_t *h)
{
    const size_t ncells = (size_t)SLAM_GRID_CELLS;
    end_bufs_t *e = &h->end;
    run_t *r = h->r = calloc(1, sizeof *h->r);
    if (r != NULL) {
        r->truth = calloc(ncells, 1u);
        r->observable = calloc(ncells, 1u);
        r->reachable = calloc(ncells, 1u);
        r->seen = calloc(ncells, 1u);
        r->wall_left = calloc((ncells + 63u) / 64u, sizeof *r->wall_left);
    }
    e->post = calloc(ncells, 1u);
    e->ideal_post = calloc(ncells, 1u);
    e->work = calloc(ncells, 1u);
    e->scratch = calloc(2u, SLAM_GRID_A);
    e->ps = calloc(1, sizeof *e->ps);
    if (r == NULL || r->truth == NULL || r->observable == NULL || r->reachable == NULL ||
        r->seen == NULL || r->wall_left == NULL || e->post == NULL || e->ideal_post == NULL ||
        e->work == NULL || e->scratch == NULL || e->ps == NULL) {
        fprintf(stderr, "host_sim: out of memory\n");
        return 1;
    }
    return 0;
}

static void free_buffers(held_t *h)
{
    if (h->r != NULL) {
        free(h->r->truth);
        free(h->r->observable);
        free(h->r->reachable);
        free(h->r->seen);
        free(h->r->wall_left);
        free(h->r);
        h->r = NULL;
    }
    free(h->end.post);
    free(h->end.ideal_post);
    free(h->end.work);
    free(h->end.scratch);
    free(h->end.ps);
}

static void release(held_t *h)
{
    run_logs_t *l = &h->logs;
    link_close(&h->link);
    hal_host_uart_sink(NULL);
    if (l->trace != NULL) {
        hal_host_trace(NULL);
        fclose(l->trace);
    }
    if (l->telemetry != NULL) {
        fclose(l->telemetry);
    }
    if (l->readings != NULL) {
        fclose(l->readings);
    }
    if (l->trajectory != NULL) {
        fclose(l->trajectory);
    }
    if (h->tape.csv != NULL) {
        fclose(h->tape.csv);
    }
    hal_host_attach(NULL);
    if (h->r != NULL && h->r->estimates != NULL) {
        fclose(h->r->estimates);
    }
    free_buffers(h);
    scenario_free(&h->sc);
}

/* ---- the run ------------------------------------------------------------------------------ */

/* A write error in a file being written as the robot runs: say which, once. */
static bool write_failed(FILE *f, const char *name)
{
    if (f != NULL && ferror(f)) {
        fprintf(stderr, "host_sim: writing %s failed: %s\n", name, strerror(errno));
        return true;
    }
    return false;
}

/* The outputs written as the robot runs, headers first: config.txt (whole at once),
 * readings.csv, trajectory.csv, --trace, --telemetry, scoring_estimate.csv. 0, or 1. */
static int open_logs(const options_t *o, held_t *h)
{
    run_logs_t *l = &h->logs;
    if (make_dirs(o->out) != 0) {
        return 1;
    }
    outputs_sweep(o);
    FILE *cfgf = open_out(o->out, "config.txt");
    if (cfgf == NULL) {
        return 1;
    }
    fprintf(cfgf, "# firmware configuration of this run (host_sim --replay reads it)\n");
    cfgtext_write(cfgf, &h->sc.cfg);
    if (close_out(cfgf, o->out, "config.txt") != 0) {
        return 1;
    }
    l->readings = open_out(o->out, "readings.csv");
    l->trajectory = open_out(o->out, "trajectory.csv");
    if (l->readings == NULL || l->trajectory == NULL) {
        return 1;
    }
    if (o->trace != NULL && (l->trace = open_out(NULL, o->trace)) == NULL) {
        return 1;
    }
    if (o->telemetry != NULL) {
        /* Written as it goes, in place: a viewer may be following the file. */
        l->telemetry = open_stream(o->telemetry);
        if (l->telemetry == NULL) {
            return 1;
        }
    }
    if (o->link != NULL && link_open(&h->link, o->link, o->quiet) != 0) {
        return 1;
    }
    fprintf(l->readings, "%s,%s\n", CSV_READINGS_HEADER, CSV_TRUTH_COLUMNS);
    fprintf(l->trajectory, "%s\n", CSV_TRAJECTORY_HEADER);
    if (o->scoring) {
        h->r->estimates = open_out(o->out, "scoring_estimate.csv");
        if (h->r->estimates == NULL) {
            return 1;
        }
        fprintf(h->r->estimates, "%s\n", CSV_ESTIMATE_HEADER);
    }
    return 0;
}

/* Power the robot up in the world: the HAL on it, the firmware and its twin started, the
 * trace and the telemetry recording from the first tick. 0, or 1 with a message. */
static int start_firmware(const options_t *o, held_t *h)
{
    const slam_config_t *cfg = &h->sc.cfg;
    hal_host_attach(h->sc.sim);
    if (o->storage != NULL) {
        /* Room for a record of this grid: the robot now saves its maps every
         * save_period_s, and stands still while a save begins, as a real one does. */
        hal_host_storage_resize(sizeof(mapstore_header_t) +
                                2u * (size_t)grid_cells_a(cfg) * grid_cells_b(cfg));
    }
    if (hal_init() != HAL_OK || robot_init(&fw.robot, cfg) != SLAM_OK ||
        hal_tick_start(tick_callback, &fw.robot) != HAL_OK) {
        fprintf(stderr, "host_sim: the firmware did not start\n");
        return 1;
    }
    grid_init(&fw.ideal_grid, cfg);
    mapper_init(&fw.ideal_mapper, cfg);
    if (h->logs.trace != NULL) {
        trace_write_header(h->logs.trace, cfg);
        hal_host_trace(h->logs.trace);
    }
    if (h->logs.telemetry != NULL) {
        setvbuf(h->logs.telemetry, NULL, _IONBF, 0); /* a viewer may be following the file */
        hal_host_uart_sink(h->logs.telemetry);
    }
    if (o->link != NULL && link_start(&h->link, h->logs.telemetry) != 0) {
        return 1;
    }
    return 0;
}

/* --realtime: sleep until the wall clock catches up with tick k. */
static void keep_pace(const options_t *o, uint64_t k, double t0)
{
    double ahead = (double)(k + 1u) * TICK_S / o->realtime_factor - (wall_now() - t0);
    if (ahead > 0.0) {
        struct timespec ts = {(time_t)ahead, (long)((ahead - floor(ahead)) * 1e9)};
        nanosleep(&ts, NULL);
    }
}

static void show_progress(const options_t *o, uint64_t k, uint64_t ticks, double t0)
{
    double done = (double)(k + 1u) / (double)ticks;
    int bar = (int)(done * 30.0);
    double w = wall_now() - t0;
    fprintf(stderr, "\r  simulating %7.1f s / %.0f s [%-30.*s] %3.0f%%  %6.0fx real time ",
            (double)(k + 1u) * TICK_S, o->duration_s, bar, "##############################",
            done * 100.0, w > 0 ? (double)(k + 1u) * TICK_S / w : 0.0);
}

/* The run itself: each period the world and the firmware's tick, the commands due, the
 * background loop, the experimenter, the measurements. 0, or 1 when a log fails. */
static int drive(const options_t *o, held_t *h, outcome_t *out)
{
    const scenario_t *sc = &h->sc;
    sim_t *sim = sc->sim;
    run_t *r = h->r;
    const run_logs_t *l = &h->logs;
    uint64_t ticks = (uint64_t)llround(o->duration_s / TICK_S);
    /* UMBmark says how far it is itself, a line a run. */
    bool progress = !o->quiet && isatty(STDERR_FILENO) && o->explore != EXPLORE_UMBMARK;
    experimenter_t *tape = &h->tape;
    experimenter_init(tape, o->out, o->seed, sc->sx, sc->sy, sc->sth, o->quiet);
    int tape_rc = 0;
    double t0 = wall_now();
    for (uint64_t k = 0; k < ticks; k++) {
        sim_truth_t before = sim_truth(sim);
        hal_host_step();
        commands_feed(&h->sc.commands, k);
        if (!link_poll(&h->link)) {
            ticks = k + 1u; /* ended by Ctrl-C: the outputs of the run so far */
        }
        robot_idle(&fw.robot); /* the robot's background loop runs between ticks */
        /* UMBmark: a run measured and the robot carried back; the run ends after the last. */
        tape_rc = experimenter_tick(tape, sim, &fw.robot);
        if (tape_rc == 2 || tape_rc < 0) {
            ticks = k + 1u;
        }
        observe_tick(r, &fw, sim, &before, &sc->params, l, k, k + 1u == ticks);
        if (tape_rc > 0) {
            r->last_x = sc->sx; /* carried, not driven: no path */
            r->last_y = sc->sy;
        }
        if (k % 1024u == 0u &&
            (write_failed(l->telemetry, o->telemetry) || write_failed(l->trace, o->trace) ||
             write_failed(l->readings, "readings.csv") ||
             write_failed(l->trajectory, "trajectory.csv"))) {
            return 1;
        }
        if (stop_signal != 0) {
            return 1;
        }
        if (o->realtime) {
            keep_pace(o, k, t0);
        }
        if (progress && (k % 4096u == 0u || k + 1u == ticks)) {
            show_progress(o, k, ticks, t0);
        }
    }
    out->wall_s = wall_now() - t0;
    if (progress) {
        fprintf(stderr, "\n");
    }
    out->ticks = ticks;
    out->tape_rc = tape_rc;
    return 0;
}

/* Close what was written as the robot ran (the trace gets its end line). 0, or 1 when a
 * file failed or the experimenter did. */
static int close_logs(const options_t *o, held_t *h, int tape_rc)
{
    run_logs_t *l = &h->logs;
    int bad = 0;
    link_close(&h->link);
    if (l->telemetry != NULL) {
        hal_host_uart_sink(NULL);
        bad |= write_failed(l->telemetry, o->telemetry) ? -1 : 0;
        if (fclose(l->telemetry) != 0 && bad == 0) {
            fprintf(stderr, "host_sim: writing %s failed: %s\n", o->telemetry, strerror(errno));
            bad = -1;
        }
        l->telemetry = NULL;
    }
    if (l->trace != NULL) {
        hal_host_trace(NULL); /* writes the end line */
        bad |= close_out(l->trace, NULL, o->trace);
        l->trace = NULL;
    }
    bad |= close_out(l->readings, o->out, "readings.csv");
    bad |= close_out(l->trajectory, o->out, "trajectory.csv");
    l->readings = l->trajectory = NULL;
    if (h->r->estimates != NULL) {
        bad |= close_out(h->r->estimates, o->out, "scoring_estimate.csv");
        h->r->estimates = NULL;
    }
    bad |= experimenter_close(&h->tape) | (tape_rc < 0 ? -1 : 0);
    return bad != 0 ? 1 : 0;
}

/* ---- the end ------------------------------------------------------------------------------ */

/* Every map in the one trinary meaning (hal_common/mapexport.h); TM as counts; the truth,
 * and with --scoring the scorer's masks. A failed write ORs -1 into *bad; false when out
 * of memory (with a message). */
static bool export_maps(const options_t *o, held_t *h, int *bad)
{
    const run_t *r = h->r;
    const robot_t *robot = &fw.robot;
    const slam_config_t *cfg = &h->sc.cfg;
    uint8_t *work = h->end.work;
    const uint32_t A = r->geom.a;
    const uint32_t B = r->geom.b;
    mapx_trinary(cfg->om_mode, robot->grid.om, robot->grid.tm, NULL, A, B, work);
    *bad |= write_map(o->out, "om", &r->geom, work, true);
    mapx_trinary(cfg->om_mode, robot->grid.om, robot->grid.tm, h->end.post, A, B, work);
    *bad |= write_map(o->out, "om_post", &r->geom, work, true);
    mapx_trinary(cfg->om_mode, fw.ideal_grid.om, fw.ideal_grid.tm, NULL, A, B, work);
    *bad |= write_map(o->out, "om_ideal", &r->geom, work, true);
    mapx_counts(robot->grid.tm, cfg->tm_max, A, B, work);
    *bad |= write_map(o->out, "tm", &r->geom, work, false);
    if (truth_image(&r->geom, r->truth, h->start_cell, work) != 0) {
        fprintf(stderr, "host_sim: out of memory\n");
        return false;
    }
    *bad |= write_map(o->out, "truth", &r->geom, work, true);
    if (o->scoring) {
        /* What score_map() counts against, for a scorer outside this program
         * (tools/compare.py): black where a mask is set, the orientation of om.pgm. */
        mapx_counts(r->truth, 1u, A, B, work);
        *bad |= write_map(o->out, "scoring_truth", &r->geom, work, false);
        mapx_counts(r->observable, 1u, A, B, work);
        *bad |= write_map(o->out, "scoring_observable", &r->geom, work, false);
    }
    return true;
}

/* timing.json, kept apart so every other output is byte-identical for a seed. 0, -1 when
 * its write failed, 1 when it cannot be opened. */
static int write_timing(const options_t *o, const outcome_t *out)
{
    FILE *tf = open_out(o->out, "timing.json");
    if (tf == NULL) {
        return 1;
    }
    double wall_s = out->wall_s;
    fprintf(tf,
            "{\"wall_s\": %.3f, \"ticks\": %llu, \"ticks_per_s\": %.0f, "
            "\"real_time_factor\": %.0f}\n",
            wall_s, (unsigned long long)out->ticks, wall_s > 0 ? (double)out->ticks / wall_s : 0.0,
            wall_s > 0 ? (double)out->ticks * TICK_S / wall_s : 0.0);
    return close_out(tf, o->out, "timing.json");
}

/* A home that does not fit is said at the end, never only clipped: the points the grid
 * rejected (hits, and cells the robot stood on) are missing from every map written. */
static void warn_outside(const grid_t *g, uint32_t hits)
{
    if (g->rejected == 0u) {
        return;
    }
    double cell = g->cell_um * 1e-6;
    fprintf(stderr,
            "host_sim: warning: the home does not fit the grid: %u point%s fell outside its "
            "%u x %u cells of %.0f mm (%.2f m x %.2f m), %u of them sonar hits, and are missing "
            "from the map (metrics.json: robot.outside_grid)\n",
            (unsigned)g->rejected, g->rejected == 1u ? "" : "s", (unsigned)g->a_cells,
            (unsigned)g->b_cells, cell * 1e3, g->a_cells * cell, g->b_cells * cell, (unsigned)hits);
}

/* The end of a run: the held-back hits mapped, the maps scored and exported, the metrics,
 * the storage slots and the timing written, then all committed at once; the summary, the
 * figure. 0, or 1. Never inlined: tools/bench.py measures the end of a run from its entry. */
__attribute__((noinline)) static int finish(const options_t *o, held_t *h, const outcome_t *out)
{
    const scenario_t *sc = &h->sc;
    run_t *r = h->r;
    end_bufs_t *e = &h->end;
    /* The hits still held back for matching belong in the map too (a replay does the same). */
    loc_flush(&fw.robot.loc, &fw.robot.mapper, &fw.robot.grid);

    chain_scores_t odo;
    chain_scores_t ideal;
    score_chain(r, fw.robot.grid.om, &sc->cfg, e->post, e->scratch, &odo);
    score_chain(r, fw.ideal_grid.om, &sc->cfg, e->ideal_post, e->scratch, &ideal);
    /* The chain at every TH and K only when asked: it costs more than the rest of the end. */
    const post_sweep_t *ps = NULL;
    if (o->sweep) {
        sweep_post(r, fw.robot.grid.om, &sc->cfg, e->work, e->scratch, e->ps);
        ps = e->ps;
    }

    int bad = 0;
    if (!export_maps(o, h, &bad)) {
        return 1;
    }
    bad |=
        write_metrics(o, &sc->room, r, &sc->cfg, &sc->errors, sc->sim, &fw.robot, &odo, &ideal, ps);
    if (o->storage != NULL) {
        bad |= write_storage(o->storage);
    }
    int timing = write_timing(o, out);
    if (timing > 0) {
        return 1;
    }
    bad |= timing;
    if (bad != 0 || stop_signal != 0 || outputs_commit() != 0) {
        return 1;
    }
    if (!o->quiet) {
        print_summary(o, r, &odo, &ideal, ps, out->wall_s, out->ticks, sc->sim, &fw.robot);
    }
    if (o->plot) {
        plot_figure(o->out, o->quiet);
    }
    if (o->bag != NULL && bag_write(o->out, o->bag, sc->params.sonar_cone_deg,
                                    sc->params.sonar_max_m, o->quiet) != 0) {
        return 1;
    }
    if (sc->commands.dropped != 0u) {
        fprintf(stderr, "host_sim: %s: %zu command bytes found the UART full and were lost\n",
                o->commands, sc->commands.dropped);
    }
    warn_outside(&fw.robot.grid, fw.robot.mapper.outside);
    return 0;
}

/* ---- main ----------------------------------------------------------------------------- */

/* What a run writes grows with its simulated time; a long one is said before it starts,
 * so a typo in --duration does not fill a disk unannounced. Bytes a simulated second,
 * measured in the default room (a sweep's 15 pings and 10 poses a second). */
#define ANNOUNCE_BYTES 100e6
static void announce_size(const options_t *o)
{
    const struct {
        bool on;
        const char *name;
        double bytes_s;
    } logs[] = {
        {true, "readings.csv", 1400.0},
        {true, "trajectory.csv", 720.0},
        {o->scoring, "scoring_estimate.csv", 600.0},
        {o->telemetry != NULL, "--telemetry", 5600.0},
        {o->trace != NULL, "--trace", 3700.0},
        {o->bag != NULL, "--bag", 23000.0},
    };
    double total = 0.0;
    for (size_t i = 0; i < sizeof logs / sizeof logs[0]; i++) {
        total += logs[i].on ? logs[i].bytes_s * o->duration_s : 0.0;
    }
    if (total < ANNOUNCE_BYTES) {
        return;
    }
    char parts[512] = "";
    size_t used = 0;
    for (size_t i = 0; i < sizeof logs / sizeof logs[0] && used < sizeof parts; i++) {
        if (logs[i].on) {
            int n = snprintf(parts + used, sizeof parts - used, "%s%s %.0f MB", used ? ", " : "",
                             logs[i].name, logs[i].bytes_s * o->duration_s / 1e6);
            used += n > 0 ? (size_t)n : 0u;
        }
    }
    fprintf(stderr, "host_sim: %.0f simulated seconds will write about %.0f MB (%s)\n",
            o->duration_s, total / 1e6, parts);
}

/* Checks the input, then the outputs, then runs: 0, EXIT_USAGE or 1. */
static int run(options_t *o, held_t *h)
{
    /* Everything that can be wrong with the input is checked before anything is written. */
    int rc = scenario_load(o, &h->sc);
    if (rc != 0) {
        return rc;
    }
    if (check_outputs(o) != 0 || (o->link != NULL && link_check(o->link) != 0) ||
        (o->bag != NULL && bag_check(o->bag) != 0)) {
        return EXIT_USAGE;
    }
    bool umbmark = h->sc.cfg.explore_mode == EXPLORE_UMBMARK;
    if (umbmark && !o->has_duration) {
        o->duration_s = EXPERIMENTER_MAX_S; /* until the last run is measured */
    }
    announce_size(o);
    /* From here on only a failure while running can go wrong: exit 1, and every file of
     * --out that was there before stays as it was. */
    if (alloc_buffers(h) != 0 || open_logs(o, h) != 0 || start_firmware(o, h) != 0 ||
        observe_init(h->r, &h->sc, &fw.robot, &h->start_cell) != 0) {
        return 1;
    }
    outcome_t out;
    if (drive(o, h, &out) != 0 || close_logs(o, h, out.tape_rc) != 0) {
        return 1;
    }
    if (umbmark && !o->has_duration) {
        o->duration_s = (double)out.ticks * TICK_S; /* what the test took */
    }
    unsigned runs = 2u * fw.robot.umbmark.runs;
    if (umbmark && out.tape_rc >= 0 && h->tape.measured < runs) {
        /* A csv with the first runs only would leave umbmark.py without a direction. */
        double each = h->tape.measured > 0u ? o->duration_s / h->tape.measured : 0.0;
        fprintf(stderr,
                "host_sim: UMBmark stopped after %u of its %u runs: --duration %.0f s ended "
                "the run first (",
                h->tape.measured, runs, o->duration_s);
        if (each > 0.0) {
            fprintf(stderr,
                    "a run takes about %.0f s; give --duration %.0f or more, or leave it "
                    "out to run until the last run)\n",
                    each, each * runs * 1.1);
        } else {
            fprintf(stderr, "leave --duration out to run until the last run)\n");
        }
    }
    return finish(o, h, &out);
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
    watch_signals();
    static held_t held;
    rc = run(&o, &held);
    if (rc != 0) {
        outputs_discard();
    }
    release(&held);
    if (rc != 0 && stopped()) { /* a signal after the outputs were committed changes nothing */
        return 128 + (int)stop_signal;
    }
    return rc;
}
