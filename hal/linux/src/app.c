/* SPDX-License-Identifier: MIT */
/* The sonarslam-linux program: configuration, --check, the run loop, signals, maps on exit. */
#define _GNU_SOURCE /* getopt_long */
#include "lhal/app.h"

#include <getopt.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "hal/hal.h"
#include "hal_common/mapexport.h"
#include "hal_common/number.h"
#include "lhal/lconf.h"
#include "lhal/lhal.h"
#include "lhal/mapfile.h"
#include "slam/error.h"
#include "slam/postprocess.h"
#include "slam/robot.h"

#define APP_NAME "sonarslam-linux"
#define APP_IDLE_NS 5000000L /* the background loop's pause */

static robot_t app_robot;
static volatile sig_atomic_t app_stop_signal;

/* The first stop signal stops the motors at once (without I/O in the handler: the
 * watchdog thread drops the lines and the PWM) and lets the program save the maps; a
 * second one ends it at once, whatever it waits for. */
static void app_on_stop(int sig)
{
    if (app_stop_signal != 0) {
        _exit(128 + sig);
    }
    app_stop_signal = sig;
    lhal_signal_stop();
}

/* A crash stops the motors first, then takes its default course (core dump). */
static void app_on_crash(int sig)
{
    lhal_emergency_stop();
    raise(sig); /* SA_RESETHAND restored the default action */
}

static void app_usage(FILE *f)
{
    fprintf(
        f, "usage: " APP_NAME " --config FILE [--check] [--ticks N]\n"
           "       " APP_NAME " --help\n"
           "\n"
           "Runs the sonarslam firmware on a Linux robot: 10 ms control ticks, wheel encoders,\n"
           "the swept sonar, the motors and telemetry, as robot.conf describes them.\n"
           "\n"
           "  -c, --config FILE  the robot's configuration (key = value; see robot-rpi.conf)\n"
           "      --check        open every line and PWM channel, report what works, move nothing\n"
           "      --ticks N      stop after N control ticks (N/100 s); default: run until\n"
           "                     SIGINT (Ctrl-C) or SIGTERM\n"
           "  -h, --help         this text\n"
           "\n"
           "On exit the motors stop and the maps are written to storage_dir: om.pgm and\n"
           "om_post.pgm, each with a ROS map_server .yaml, and tm.pgm (where the robot drove,\n"
           "a picture with no .yaml: no map loader should read it as obstacles). The motors\n"
           "also stop, and the program exits with status 3, when a thread stalls for more\n"
           "than 100 ms or a hardware write fails. A second Ctrl-C (or SIGTERM) ends the program "
           "at once.\n"
           "Exit status: 0 ok, 1 hardware problem, 2 bad command line or configuration,\n"
           "3 stopped for safety, 128 + N ended at once by a second signal N.\n");
}

/* The tick callback: the firmware's 10 ms interrupt body. */
static void app_tick(void *ctx)
{
    robot_tick(ctx);
}

static int app_write_maps(const lconf_t *lc, FILE *out, FILE *err)
{
    const grid_t *g = &app_robot.grid;
    const mapfile_geometry_t geo = {g->cell_um, g->origin_x_um, g->origin_y_um};
    const slam_config_t *c = &app_robot.cfg;
    const post_params_t pp = {grid_threshold_byte(c->om_mode, c->post_threshold), g->om_max,
                              c->post_template_k, c->post_insert};
    static uint8_t post[SLAM_GRID_CELLS];
    static uint8_t img[SLAM_GRID_CELLS];
    static uint8_t scratch[2u * SLAM_GRID_A];
    /* The run's grid (grid_a x grid_b), within the capacity the buffers hold. */
    const uint32_t A = g->a_cells;
    const uint32_t B = g->b_cells;
    mapx_trinary(c->om_mode, g->om, g->tm, NULL, A, B, img);
    int rc = mapfile_write(lc->storage_dir, "om", img, A, B, true, &geo);
    if (rc == 0) {
        mapx_counts(g->tm, g->tm_max, A, B, img);
        rc = mapfile_write(lc->storage_dir, "tm", img, A, B, false, &geo);
    }
    if (rc == 0 && post_run(g->om, post, A, B, &pp, scratch) == SLAM_OK) {
        mapx_trinary(c->om_mode, g->om, g->tm, post, A, B, img);
        rc = mapfile_write(lc->storage_dir, "om_post", img, A, B, true, &geo);
    }
    if (rc != 0) {
        fprintf(err, APP_NAME ": cannot write the maps to %s: %s\n", lc->storage_dir,
                strerror(-rc));
        return -1;
    }
    fprintf(out, "maps written to %s: om.pgm, om_post.pgm (+ .yaml), tm.pgm\n", lc->storage_dir);
    return 0;
}

/* A home that does not fit is said at the end, never only clipped: the points the grid
 * rejected (hits, and cells the robot stood on) are missing from the maps written. */
static void app_warn_outside(const grid_t *g, uint32_t hits, FILE *err)
{
    if (g->rejected == 0u) {
        return;
    }
    uint32_t cell_mm = g->cell_um / 1000u;
    fprintf(err,
            APP_NAME ": warning: the home does not fit the grid: %u point%s fell outside its "
                     "%u x %u cells of %u mm (%u mm x %u mm), %u of them sonar hits, and are "
                     "missing from the maps\n",
            (unsigned)g->rejected, g->rejected == 1u ? "" : "s", (unsigned)g->a_cells,
            (unsigned)g->b_cells, (unsigned)cell_mm, (unsigned)(g->a_cells * cell_mm),
            (unsigned)(g->b_cells * cell_mm), (unsigned)hits);
}

static void app_signals(bool install, struct sigaction old[], const int *sigs, size_t n)
{
    for (size_t i = 0u; i < n; i++) {
        if (!install) {
            sigaction(sigs[i], &old[i], NULL);
            continue;
        }
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sigemptyset(&sa.sa_mask);
        if (sigs[i] == SIGINT || sigs[i] == SIGTERM) {
            sa.sa_handler = app_on_stop;
        } else if (sigs[i] == SIGPIPE) {
            sa.sa_handler = SIG_IGN;
        } else {
            sa.sa_handler = app_on_crash;
            sa.sa_flags = (int)(SA_RESETHAND | SA_NODEFER);
        }
        sigaction(sigs[i], &sa, &old[i]);
    }
}

/* Runs the robot until a signal, the tick limit, or a fault. Returns the exit status. */
static int app_run(const slam_config_t *core, const lconf_t *lc, uint32_t tick_limit, FILE *out,
                   FILE *err)
{
    lhal_configure(lc);
    if (hal_init() != HAL_OK) {
        fprintf(err, APP_NAME ": %s\n", lhal_error());
        return APP_EXIT_HARDWARE;
    }
    if (robot_init(&app_robot, core) != SLAM_OK) {
        fprintf(err, APP_NAME ": the firmware refused the configuration\n");
        lhal_shutdown();
        return APP_EXIT_USAGE;
    }
    if (core->sonar1_map != 0u && !app_robot.sonar1.on) {
        fprintf(err, APP_NAME ": warning: sonar1_map = 1, but %s: the second sonar is not used\n",
                hal_sonar_count() < 2u ? "robot.conf gives no sonar1_trigger and sonar1_echo"
                                       : "it needs localize = 1 or om_mode = 1");
    }
    if (strcmp(lc->telemetry, "none") != 0) {
        fprintf(out, "telemetry on %s\n", lhal_telemetry_name());
    }
    if (hal_tick_start(app_tick, &app_robot) != HAL_OK) {
        fprintf(err, APP_NAME ": %s\n", lhal_error());
        lhal_shutdown();
        return APP_EXIT_HARDWARE;
    }
    fprintf(out, "running%s\n", tick_limit ? "" : "; Ctrl-C stops");
    fflush(out);

    int status = APP_EXIT_OK;
    char msg[256];
    lhal_fault_t fault = LHAL_FAULT_NONE;
    bool warned_stuck = false;
    bool explored = false;
    bool said_explored = false;
    uint32_t ticks = 0u;
    while (!app_stop_signal) {
        /* Everything that reads the robot's state runs inside the background loop's turn,
         * which a tick that does not end keeps for at most 20 ms: then the loop goes on to
         * see the watchdog's fault. */
        lhal_stats_t st = {0};
        if (lhal_idle_lock() == HAL_OK) {
            robot_idle(&app_robot);
            ticks = app_robot.ticks;
            explored = explore_explored(&app_robot.explore);
            lhal_stats(&st);
            lhal_idle_unlock();
        }
        if (explored && !said_explored) {
            fprintf(out,
                    "explored everything it could reach after %u s: it stands (Ctrl-C "
                    "writes the maps)\n",
                    (unsigned)(ticks / (1000000u / SLAM_TICK_US)));
            fflush(out);
            said_explored = true;
        }
        fault = lhal_fault(msg, sizeof msg);
        if (fault != LHAL_FAULT_NONE || (tick_limit != 0u && ticks >= tick_limit)) {
            break;
        }
        for (unsigned i = 0u; i < st.sonars && !warned_stuck; i++) {
            if (st.sonar[i].stuck_high > 0u) {
                fprintf(err,
                        APP_NAME ": warning: %s echo line is high before the ping (stuck, "
                                 "or the sensor has no power); pings time out\n",
                        i == 0u ? "the sonar's" : "sonar 1's");
                warned_stuck = true;
            }
        }
        const struct timespec pause = {0, APP_IDLE_NS};
        nanosleep(&pause, NULL);
    }
    bool clean = lhal_shutdown();
    fault = lhal_fault(msg, sizeof msg);
    if (fault != LHAL_FAULT_NONE) {
        fprintf(err, APP_NAME ": %s\n", msg);
        status = APP_EXIT_SAFETY;
    } else if (app_stop_signal) {
        fprintf(out, "stopped by signal %d\n", (int)app_stop_signal);
    }
    if (!clean) {
        fprintf(err, APP_NAME ": a thread did not stop; the maps are written as the tick "
                              "left them\n");
        status = APP_EXIT_SAFETY; /* a stalled thread, whatever ended the run (README) */
    }
    fprintf(out, "motors stopped after %u ticks\n", (unsigned)app_robot.ticks);
    if (clean) {
        /* The hits the pose correction still holds back belong in the maps written. */
        loc_flush(&app_robot.loc, &app_robot.mapper, &app_robot.grid);
    }
    lhal_report(out);
    if (app_write_maps(lc, out, err) != 0 && status == APP_EXIT_OK) {
        status = APP_EXIT_HARDWARE;
    }
    app_warn_outside(&app_robot.grid, app_robot.mapper.outside, err);
    return status;
}

int app_main(int argc, char **argv, FILE *out, FILE *err)
{
    static const struct option opts[] = {
        {"config", required_argument, NULL, 'c'},
        {"check", no_argument, NULL, 'k'},
        {"ticks", required_argument, NULL, 't'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *config = NULL;
    bool check = false;
    uint32_t tick_limit = 0u;
    optind = 0; /* glibc: start over, so the function can run more than once */
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":c:h", opts, NULL)) != -1) {
        switch (c) {
        case 'c':
            config = optarg;
            break;
        case 'k':
            check = true;
            break;
        case 't': {
            unsigned long long v = 0u;
            if (num_uint(optarg, 1u, UINT32_MAX, &v) != NUM_OK) {
                fprintf(err, APP_NAME ": --ticks '%s': expected a whole number of ticks >= 1\n",
                        optarg);
                return APP_EXIT_USAGE;
            }
            tick_limit = (uint32_t)v;
            break;
        }
        case 'h':
            app_usage(out);
            return APP_EXIT_OK;
        case ':':
            fprintf(err, APP_NAME ": %s needs a value\n", argv[optind - 1]);
            return APP_EXIT_USAGE;
        default:
            fprintf(err, APP_NAME ": unknown option '%s' (see --help)\n", argv[optind - 1]);
            return APP_EXIT_USAGE;
        }
    }
    if (optind < argc) {
        fprintf(err, APP_NAME ": unexpected argument '%s' (see --help)\n", argv[optind]);
        return APP_EXIT_USAGE;
    }
    if (config == NULL) {
        fprintf(err, APP_NAME ": missing --config FILE (see --help)\n");
        return APP_EXIT_USAGE;
    }

    slam_config_t core;
    lconf_t lc;
    slam_config_default(&core);
    lconf_default(&lc);
    char msg[512];
    if (lconf_load(config, &core, &lc, msg, sizeof msg) != 0) {
        fprintf(err, APP_NAME ": %s\n", msg);
        return APP_EXIT_USAGE;
    }
    if (check) {
        fprintf(out, "checking %s (nothing moves)\n", config);
        return lhal_check(&lc, out) == 0u ? APP_EXIT_OK : APP_EXIT_HARDWARE;
    }

    static const int sigs[] = {SIGINT, SIGTERM, SIGPIPE, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
    struct sigaction old[sizeof sigs / sizeof sigs[0]];
    app_stop_signal = 0;
    app_signals(true, old, sigs, sizeof sigs / sizeof sigs[0]);
    int status = app_run(&core, &lc, tick_limit, out, err);
    app_signals(false, old, sigs, sizeof sigs / sizeof sigs[0]);
    return status;
}
