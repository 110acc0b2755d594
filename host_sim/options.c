/* SPDX-License-Identifier: MIT */
/* host_sim's command line: the options, their checks, and --help. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/number.h"
#include "host_sim.h"

#ifndef SLAM_SOURCE_DIR
#define SLAM_SOURCE_DIR "."
#endif

/* The modes' names, " off random ...", for --help and messages. */
#define EXPLORE_NAME_WORD(id, value, name, ...) " " #name
#define EXPLORE_NAME_LIST SLAM_EXPLORE_MODES(EXPLORE_NAME_WORD)

#define EXPLORE_NAME(id, value, name, ...) [id] = #name,
const char *const explore_names[EXPLORE_MODES] = {SLAM_EXPLORE_MODES(EXPLORE_NAME)};
#undef EXPLORE_NAME

/* murmur3's 32-bit finaliser: a bijection that scatters nearby values. */
static uint32_t mix32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x85EBCA6Bu;
    x ^= x >> 13;
    x *= 0xC2B2AE35u;
    x ^= x >> 16;
    return x;
}

static void usage(FILE *f)
{
    fprintf(
        f,
        "usage: host_sim [options]\n"
        "       host_sim --replay DIR/readings.csv [--config FILE] [--out OUT]\n"
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
        "  --duration S         simulated seconds (default 600; a robot running UMBmark,\n"
        "                       --explore umbmark: until its last run is measured)\n"
        "  --seed N             seed of every random error and of the exploration (default 1;\n"
        "                       sets explore_seed)\n"
        "  --cell MM            grid cell size in mm (default 50; sets cell_um)\n"
        "  --explore MODE       one of" EXPLORE_NAME_LIST " (default walls;\n"
        "                       sets explore_mode); umbmark: the calibration test,\n"
        "                       with a simulated person who measures each run's return\n"
        "                       error (a tape, +-5 mm) into umbmark.csv and puts the robot\n"
        "                       back; it ends after the last run\n"
        "  --sonar LEVEL        how much of what real HC-SR04s do at oblique incidence the\n"
        "                       sonar shows: optimistic (a surface answers up to 45 deg at\n"
        "                       every range; the model of older figures), typical (the\n"
        "                       limit narrows with range, and sound a surface does not\n"
        "                       answer reflects on and may come back as a long, wrong\n"
        "                       range) or pessimistic (the lowest measured limits); default\n"
        "                       %s; hal/host/README.md gives the sources. --error refines it\n"
        "  --sonar1 X Y DEG     fit a second sonar (HAL instance 1, off by default), fixed\n"
        "                       X m ahead of and Y m left of the axle, its beam DEG from\n"
        "                       the heading (-90..90; 90: looking left), and map it\n"
        "                       (sonar1_map = 1) as if it sat on the servo's axis\n"
        "  --bumpers            fit two bump switches (HAL bump 0 front left, 1 front right)\n"
        "  --ideal              turn every error source off\n"
        "  --paper              the paper's method: OM counts hits (Eq. 6), post-processing\n"
        "                       TH 3, K 1, insert (the default map holds free-space evidence)\n"
        "  --error NAME=VALUE   one error level (repeatable), within its range:\n"
        "                       ed, eb 0.8..1.2 (wheel diameter ratio, wheel base ratio);\n"
        "                       slip 0..1 per m/s² beyond slip_free 0..100 m/s²;\n"
        "                       noise 0..0.5 (wheel travel, 1 sigma); sonar_noise 0..1 m;\n"
        "                       dropout, ghost 0..1 (per ping); grazing 0..90 deg (a\n"
        "                       flat limit at every range, instead of the level's);\n"
        "                       multipath 0..8 (reflections a sound may make; 0 none);\n"
        "                       echo_stuck 0..10 per s (the echo line sticks high);\n"
        "                       servo_lag 0..0.95 (share of the servo's speed lost);\n"
        "                       servo_stall 0..10 per s (the horn stops); tick_miss\n"
        "                       0..0.9 (per tick); encoder_stop 0..10 per s (a counter stops)\n"
        "  --calibration FILE   the firmware's odometry calibration (cal_left, cal_right,\n"
        "                       cal_base: key = value lines, as tools/umbmark.py writes them;\n"
        "                       no other key, at least one of them), or none.\n"
        "                       Default: host_sim/calibration/default_robot.conf,\n"
        "                       what make calibrate measured on the default robot; none\n"
        "                       with --ideal or another ed or eb (another robot)\n"
        "  --config FILE        firmware configuration, key = value lines: a robot's\n"
        "                       robot.conf as it is (its [linux] section is skipped)\n"
        "  --set KEY=VALUE      one firmware configuration value (repeatable); one that\n"
        "                       disagrees with --cell or --explore is refused\n"
        "                       The configuration is built in this order, a later one\n"
        "                       overriding an earlier one: the calibration file, the\n"
        "                       --config file, the options given (--paper, --seed, --cell,\n"
        "                       --explore), each --set\n"
        "outputs:\n"
        "  --out DIR            output folder (default out/sim; for --replay, DIR/replay\n"
        "                       beside the log; never a folder holding a run's metrics.json)\n"
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
        "                       (tools/plot_run.py DIR draws them); a DIR that holds slots\n"
        "                       already is refused: the run would replace them\n"
        "  --link PATH          the robot's UART live, both ways: a pseudo-terminal that PATH\n"
        "                       links to while the run lasts, as the Linux robot offers one;\n"
        "                       runs in real time (--realtime FACTOR changes the pace). Watch\n"
        "                       and command it: tools/telemetry.py serve PATH, then open the\n"
        "                       page it prints (tools/web/README.md)\n"
        "  --bag FILE           also write the run as a ROS bag: /map, /odom, /tf, /sonar and\n"
        "                       the truth (tools/rosbag_out.py; needs python3-rosbag)\n"
        "  --realtime [FACTOR]  run at the speed of the real robot (FACTOR times it, 0.1 to\n"
        "                       1000; default 1), not as fast as possible\n"
        "  --scoring            also write what the score is computed against: the truth's\n"
        "                       boundary cells (scoring_truth.pgm) and the cells within rc\n"
        "                       of a sonar position (scoring_observable.pgm), black where set,\n"
        "                       and the estimated pose of every reading (scoring_estimate.csv)\n"
        "  --sweep              also score the post-processing chain at every threshold TH\n"
        "                       and template K: post_sweep in metrics.json and the best\n"
        "                       TH, K in the summary (tools/sim_report.py asks for it)\n"
        "  --no-plot            do not draw figure.png\n"
        "  --quiet              no progress line and no summary\n"
        "  --help               this text\n"
        "\n"
        "Files written: om.pgm om_post.pgm om_ideal.pgm truth.pgm (+ ROS .yaml each), tm.pgm,\n"
        "trajectory.csv readings.csv metrics.json timing.json config.txt figure.png, and\n"
        "umbmark.csv when the robot ran UMBmark\n"
        "Inputs are regular files: a FIFO, a device or a socket is refused. A FIFO given to\n"
        "--telemetry or --trace needs its reader running already; without one, exit 1.\n"
        "Exit status: 0 done, 1 failed while running (a pipe's reader gone, a disk full),\n"
        "2 bad options or input, 128 + N stopped by signal N (SIGINT, SIGTERM, SIGHUP:\n"
        "nothing written, the earlier outputs stay).\n",
        sim_sonar_level_name(SIM_SONAR_DEFAULT));
}

__attribute__((format(printf, 1, 2))) static int fail_usage(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "host_sim: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(host_sim --help lists the options)\n");
    va_end(ap);
    return EXIT_USAGE;
}

typedef num_status_t num_t;

/* A real number by the rule of hal_common/number.h: decimal, the whole argument. */
static num_t parse_double(const char *s, double lo, double hi, double *out)
{
    return num_real(s, lo, hi, out);
}

static num_t parse_u64(const char *s, uint64_t *out)
{
    unsigned long long v = 0u;
    num_t r = num_uint(s, 0u, UINT64_MAX, &v);
    if (r == NUM_OK) {
        *out = v;
    }
    return r;
}

/* "OPTION: 'TEXT' is not a number" or "... is out of range LO..HI". */
static int bad_number(const char *option, const char *text, num_t why, double lo, double hi)
{
    if (why == NUM_RANGE) {
        return fail_usage("%s: '%.40s' is out of range %g..%g", option, text, lo, hi);
    }
    return fail_usage("%s: '%.40s' is not a decimal number", option, text);
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
        .sonar = SIM_SONAR_DEFAULT,
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
                num_t r = parse_double(argv[i - 3 + k], -ROOM_MAX_COORD_M, ROOM_MAX_COORD_M, v[k]);
                if (r != NUM_OK) {
                    return bad_number("--crop", argv[i - 3 + k], r, -ROOM_MAX_COORD_M,
                                      ROOM_MAX_COORD_M);
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
            double *v[3] = {&o->start_x, &o->start_y, &o->start_deg};
            const double lim[3] = {ROOM_MAX_COORD_M, ROOM_MAX_COORD_M, 360.0};
            for (int k = 0; k < 3; k++) {
                num_t r = parse_double(argv[i - 2 + k], -lim[k], lim[k], v[k]);
                if (r != NUM_OK) {
                    return bad_number("--start", argv[i - 2 + k], r, -lim[k], lim[k]);
                }
            }
            o->has_start = true;
        } else if (strcmp(a, "--duration") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--duration needs seconds between 0.01 and 1000000");
            }
            num_t r = parse_double(argv[i], 0.01, 1e6, &o->duration_s);
            if (r != NUM_OK) {
                return bad_number("--duration", argv[i], r, 0.01, 1e6);
            }
            o->has_duration = true;
        } else if (strcmp(a, "--seed") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--seed needs a whole number >= 0");
            }
            num_t r = parse_u64(argv[i], &o->seed);
            if (r == NUM_RANGE) {
                return fail_usage("--seed: '%.40s' is out of range 0..18446744073709551615",
                                  argv[i]);
            }
            if (r != NUM_OK) {
                return fail_usage("--seed: '%.40s' is not a whole number >= 0", argv[i]);
            }
            o->has_seed = true;
        } else if (strcmp(a, "--cell") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--cell needs whole millimetres between 20 and 1000");
            }
            /* cell_um's range in config_fields.h, in millimetres. */
            num_t r = parse_double(argv[i], 20.0, 1000.0, &o->cell_mm);
            if (r != NUM_OK) {
                return bad_number("--cell", argv[i], r, 20.0, 1000.0);
            }
            if (o->cell_mm != floor(o->cell_mm)) {
                return fail_usage("--cell: '%.40s' is not whole millimetres", argv[i]);
            }
            o->has_cell = true;
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
                return fail_usage("--explore: unknown mode '%.40s' (one of%s)", argv[i],
                                  EXPLORE_NAME_LIST);
            }
            o->has_explore = true;
        } else if (strcmp(a, "--out") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--out needs a folder");
            }
            o->out = argv[i];
            o->has_out = true;
        } else if (strcmp(a, "--sonar") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--sonar needs a level: optimistic, typical or pessimistic");
            }
            o->sonar = sim_sonar_level_of(argv[i]);
            if (o->sonar < 0) {
                return fail_usage("--sonar: unknown level '%.40s' (optimistic, typical, "
                                  "pessimistic)",
                                  argv[i]);
            }
            o->has_sonar = true;
        } else if (strcmp(a, "--sonar1") == 0) {
            if (!take(argc, argv, &i, 3)) {
                return fail_usage("--sonar1 needs X Y DEG");
            }
            double *v[3] = {&o->sonar1_x, &o->sonar1_y, &o->sonar1_deg};
            const double lim[3] = {1.0, 1.0, 90.0};
            for (int k = 0; k < 3; k++) {
                num_t r = parse_double(argv[i - 2 + k], -lim[k], lim[k], v[k]);
                if (r != NUM_OK) {
                    return bad_number("--sonar1", argv[i - 2 + k], r, -lim[k], lim[k]);
                }
            }
            o->has_sonar1 = true;
        } else if (strcmp(a, "--bumpers") == 0) {
            o->bumpers = true;
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
                return fail_usage("more than %u %s options", HOST_SIM_MAX_SETS, a);
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
        } else if (strcmp(a, "--link") == 0 || strcmp(a, "--bag") == 0) {
            bool live = a[2] == 'l';
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("%s needs a path", a);
            }
            *(live ? &o->link : &o->bag) = argv[i];
            o->realtime = o->realtime || live; /* a live robot keeps the real one's pace */
        } else if (strcmp(a, "--realtime") == 0) {
            o->realtime = true;
            /* An optional factor: the next word, when it is not an option. */
            if (i + 1 < argc && strncmp(argv[i + 1], "--", 2) != 0) {
                num_t r = parse_double(argv[++i], 0.1, 1000.0, &o->realtime_factor);
                if (r != NUM_OK) {
                    return fail_usage("--realtime FACTOR: '%.40s' is %s 0.1..1000", argv[i],
                                      r == NUM_RANGE ? "out of range" : "not a number in");
                }
            }
        } else if (strcmp(a, "--replay") == 0) {
            if (!take(argc, argv, &i, 1)) {
                return fail_usage("--replay needs a readings.csv");
            }
            o->replay = argv[i];
        } else if (strcmp(a, "--scoring") == 0) {
            o->scoring = true;
        } else if (strcmp(a, "--sweep") == 0) {
            o->sweep = true;
        } else if (strcmp(a, "--no-plot") == 0) {
            o->plot = false;
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = true;
        } else {
            return fail_usage("unknown option '%s'", a);
        }
    }
    if (o->ideal && o->has_sonar) {
        return fail_usage("--sonar and --ideal: an ideal sonar has no level");
    }
    return 0;
}

/* The --error names, their fields and ranges: within what sim_params_check() takes.
 * Fields are doubles but multipath's, a whole number (offset SIZE_MAX). */
static const struct {
    const char *name;
    size_t offset;
    double lo, hi;
} error_names[] = {
    {"ed", offsetof(sim_errors_t, wheel_ratio_ed), 0.8, 1.2},
    {"eb", offsetof(sim_errors_t, wheel_base_eb), 0.8, 1.2},
    {"slip", offsetof(sim_errors_t, slip_per_mps2), 0.0, 1.0},
    {"slip_free", offsetof(sim_errors_t, slip_free_mps2), 0.0, 100.0},
    {"noise", offsetof(sim_errors_t, wheel_noise), 0.0, 0.5},
    {"sonar_noise", offsetof(sim_errors_t, sonar_noise_m), 0.0, 1.0},
    {"dropout", offsetof(sim_errors_t, sonar_dropout), 0.0, 1.0},
    {"ghost", offsetof(sim_errors_t, sonar_ghost), 0.0, 1.0},
    {"grazing", offsetof(sim_errors_t, grazing_deg), 0.0, 90.0},
    {"multipath", SIZE_MAX, 0.0, 8.0},
    {"echo_stuck", offsetof(sim_errors_t, echo_stuck_per_s), 0.0, 10.0},
    {"servo_lag", offsetof(sim_errors_t, servo_lag), 0.0, 0.95},
    {"servo_stall", offsetof(sim_errors_t, servo_stall_per_s), 0.0, 10.0},
    {"tick_miss", offsetof(sim_errors_t, tick_miss), 0.0, 0.9},
    {"encoder_stop", offsetof(sim_errors_t, encoder_stop_per_s), 0.0, 10.0},
};

/* --error NAME=VALUE onto the error levels. */
int apply_error(sim_errors_t *e, const char *nv)
{
    const char *eq = strchr(nv, '=');
    size_t len = (size_t)(eq - nv);
    for (size_t i = 0; i < sizeof error_names / sizeof error_names[0]; i++) {
        if (strlen(error_names[i].name) == len && strncmp(nv, error_names[i].name, len) == 0) {
            double v;
            num_t r = parse_double(eq + 1, error_names[i].lo, error_names[i].hi, &v);
            if (r != NUM_OK) {
                fprintf(stderr, "host_sim: --error %s: '%.40s' is %s %g..%g\n", error_names[i].name,
                        eq + 1, r == NUM_BAD ? "not a number in" : "out of range",
                        error_names[i].lo, error_names[i].hi);
                return -1;
            }
            if (error_names[i].offset == SIZE_MAX) {
                if (v != floor(v)) {
                    fprintf(stderr, "host_sim: --error %s: '%.40s' is not a whole number\n",
                            error_names[i].name, eq + 1);
                    return -1;
                }
                e->multipath = (uint32_t)v;
                return 0;
            }
            memcpy((char *)e + error_names[i].offset, &v, sizeof v);
            if (error_names[i].offset == offsetof(sim_errors_t, grazing_deg)) {
                e->grazing_curve.n = 0u; /* a flat limit, instead of the level's curve */
            }
            return 0;
        }
    }
    fprintf(stderr, "host_sim: --error: unknown error source '%.*s' (",
            (int)(len > 40u ? 40u : len), nv);
    for (size_t i = 0; i < sizeof error_names / sizeof error_names[0]; i++) {
        fprintf(stderr, "%s%s", i ? ", " : "", error_names[i].name);
    }
    fprintf(stderr, ")\n");
    return -1;
}

uint32_t explore_seed_of(uint64_t seed)
{
    /* A bijection of 32-bit words (murmur3's finaliser) applied to the low word mixed
     * with a hash of the high one: seeds 0 .. 2^32 - 3 each get their own stream, and
     * nearby seeds get unrelated ones. Zero is no xorshift state, so the seed that would
     * map there (2^32 - 1) shares the stream of 2^32 - 2: the one collision below 2^32. */
    uint32_t hi = (uint32_t)(seed >> 32);
    uint32_t h = hi == 0u ? 0u : mix32(hi ^ 0x9E3779B9u);
    uint32_t v = mix32(((uint32_t)seed ^ h) + 1u);
    return v != 0u ? v : mix32(0xFFFFFFFFu);
}
