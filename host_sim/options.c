/* SPDX-License-Identifier: MIT */
/* host_sim's command line: the options, their checks, and --help. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "host_sim.h"

#ifndef SLAM_SOURCE_DIR
#define SLAM_SOURCE_DIR "."
#endif

const char *const explore_names[EXPLORE_MODES] = {"off", "random", "tm", "square", "walls", "umbmark"};

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
        "  --crop X Y W H       take this part of a ROS map (metres, map frame); its edges\n"
        "                       become walls\n"
        "  --start X Y DEG      start pose (default: the room's, or a free spot)\n"
        "  --duration S         simulated seconds (default 600)\n"
        "  --seed N             seed of every random error and of the exploration (default 1)\n"
        "  --cell MM            grid cell size in mm (default 50)\n"
        "  --explore MODE       walls | random | tm | square | umbmark | off (default\n"
        "                       walls); umbmark: the calibration test, with a simulated\n"
        "                       person who measures each run's return error (a tape,\n"
        "                       +-5 mm) into umbmark.csv and puts the robot back; it ends\n"
        "                       after the last run\n"
        "  --ideal              turn every error source off\n"
        "  --paper              the paper's method: OM counts hits (Eq. 6), post-processing\n"
        "                       TH 3, K 1, insert (the default map holds free-space evidence)\n"
        "  --error NAME=VALUE   one error level (repeatable): ed, eb (wheel diameter ratio,\n"
        "                       wheel base ratio), slip (per m/s² beyond slip_free m/s²),\n"
        "                       noise, sonar_noise (m), dropout, ghost, grazing (deg)\n"
        "  --calibration FILE   the firmware's odometry calibration (cal_left, cal_right,\n"
        "                       cal_base: key = value lines, as tools/umbmark.py writes them),\n"
        "                       or none. Default: host_sim/calibration/default_robot.conf,\n"
        "                       what make calibrate measured on the default robot; none\n"
        "                       with --ideal or another ed or eb (another robot)\n"
        "  --config FILE        firmware configuration, key = value lines (after the\n"
        "                       calibration)\n"
        "  --set KEY=VALUE      one firmware configuration value (repeatable)\n"
        "outputs:\n"
        "  --out DIR            output folder (default out/sim)\n"
        "  --trace FILE         also record the HAL trace of the run\n"
        "  --telemetry FILE     write the firmware's telemetry bytes (the UART) to FILE\n"
        "                       (watch: tools/telemetry.py view FILE --follow)\n"
        "  --commands FILE      send the robot commands at set times: 'TIME_S COMMAND' lines,\n"
        "                       COMMAND start, stop, mode MODE, get KEY, set KEY VALUE, save,\n"
        "                       map, calibrate, or hex BYTES (host_sim/README.md); the\n"
        "                       answers go to --telemetry\n"
        "  --storage DIR        give the robot map storage (it saves every save_period_s,\n"
        "                       standing still as a save begins) and write its two slots as\n"
        "                       DIR/slot0.bin and slot1.bin, as the Linux robot keeps them\n"
        "                       (tools/plot_run.py DIR draws them)\n"
        "  --realtime [FACTOR]  run at the speed of the real robot (FACTOR times it, 0.1 to\n"
        "                       1000; default 1), not as fast as possible\n"
        "  --scoring            also write what the score is computed against: the truth's\n"
        "                       boundary cells (scoring_truth.pgm) and the cells within rc\n"
        "                       of a sonar position (scoring_observable.pgm), black where set,\n"
        "                       and the estimated pose of every reading (scoring_estimate.csv)\n"
        "  --no-plot            do not draw figure.png\n"
        "  --quiet              no progress line and no summary\n"
        "  --help               this text\n"
        "\n"
        "Files written: om.pgm om_post.pgm om_ideal.pgm truth.pgm (+ ROS .yaml each), tm.pgm,\n"
        "trajectory.csv readings.csv metrics.json timing.json config.txt figure.png, and\n"
        "umbmark.csv when the robot ran UMBmark\n"
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

int parse_options(int argc, char **argv, options_t *o)
{
    *o = (options_t){
        .room = SLAM_SOURCE_DIR "/host_sim/rooms/default.room",
        .duration_s = 600.0,
        .seed = 1u,
        .cell_mm = 50.0,
        .explore = EXPLORE_WALLS,
        .out = "out/sim",
        .plot = true,
        .realtime_factor = 1.0,
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
                return fail_usage("--explore: unknown mode '%s' (random, tm, walls, square, umbmark, "
                                  "off)", argv[i]);
            }
        } else if (strcmp(a, "--out") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--out needs a folder");
            }
            o->out = argv[i];
        } else if (strcmp(a, "--ideal") == 0) {
            o->ideal = true;
        } else if (strcmp(a, "--paper") == 0) {
            o->paper = true;
        } else if (strcmp(a, "--error") == 0 || strcmp(a, "--set") == 0) {
            bool err = a[2] == 'e';
            if (!take(argc, argv, &i, 1) || strchr(argv[i], '=') == NULL) {
                return fail_usage("%s needs NAME=VALUE", a);
            }
            size_t *n = err ? &o->nerrors : &o->nsets;
            if (*n == HOST_SIM_MAX_SETS) {
                return fail_usage("too many %s options", a);
            }
            (err ? o->errors : o->sets)[(*n)++] = argv[i];
        } else if (strcmp(a, "--config") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--config needs a file");
            }
            o->config = argv[i];
        } else if (strcmp(a, "--calibration") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--calibration needs a file, or none");
            }
            o->calibration = argv[i];
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
        } else if (strcmp(a, "--commands") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--commands needs a file");
            }
            o->commands = argv[i];
        } else if (strcmp(a, "--storage") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--storage needs a folder");
            }
            o->storage = argv[i];
        } else if (strcmp(a, "--realtime") == 0) {
            o->realtime = true;
            /* An optional factor: the next word, when it is not an option. */
            if (i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0) {
                if (!parse_double(argv[++i], 0.1, 1000.0, &o->realtime_factor)) {
                    return fail_usage("--realtime: FACTOR must be a number from 0.1 to 1000");
                }
            }
        } else if (strcmp(a, "--replay") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--replay needs a readings.csv");
            }
            o->replay = argv[i];
        } else if (strcmp(a, "--scoring") == 0) {
            o->scoring = true;
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

/* --error NAME=VALUE onto the error levels. */
int apply_error(sim_errors_t *e, const char *nv)
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
