/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Internal interfaces of the host_sim program: map files, scoring against ground truth.
 *
 * Maps here are the grid's arrays: a×b cells, index b·a_cells + a, cell (0, 0) at the
 * grid origin (its lower-left corner, in metres of the world frame).
 */
#ifndef HOST_SIM_HOST_SIM_H
#define HOST_SIM_HOST_SIM_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "host/sim.h"
#include "slam/robot.h"

#define HOST_SIM_PI 3.14159265358979323846
#define TICK_S (HAL_TICK_PERIOD_US * 1e-6) /* the control period, s */
#define EXIT_USAGE 2                       /* bad options or input */
/* The calibration `make calibrate` made for the default simulated robot. */
#define HOST_SIM_CALIBRATION "/host_sim/calibration/default_robot.conf"

/** The geometry shared by every map of a run. */
typedef struct {
    uint32_t a;      /**< cells along x */
    uint32_t b;      /**< cells along y */
    double cell_m;   /**< cell side */
    double origin_x; /**< world x of the lower-left corner of cell (0, 0), m */
    double origin_y;
    uint32_t cell_um; /**< the same geometry as the firmware holds it */
    int32_t origin_x_um;
    int32_t origin_y_um;
} map_geom_t;

/** The geometry of a firmware grid. */
static inline map_geom_t map_geom_of(const grid_t *g)
{
    return (map_geom_t){
        g->a_cells, g->b_cells,     g->cell_um * 1e-6, g->origin_x_um * 1e-6, g->origin_y_um * 1e-6,
        g->cell_um, g->origin_x_um, g->origin_y_um};
}

/** How a map is scored (DESIGN.md §5). */
typedef struct {
    uint32_t mapped;     /**< occupied cells in the map */
    uint32_t true_pos;   /**< of which within one cell of a truth-occupied cell */
    uint32_t observable; /**< truth-occupied cells within rc of a sonar position */
    uint32_t matched;    /**< of which within one cell of a mapped cell */
    double precision;
    double recall;
    double f1;
} score_t;

/**
 * Score a map: a cell is occupied when non-zero. Precision = true_pos / mapped, recall =
 * matched / observable (Chebyshev distance <= 1 both ways), F1 their harmonic mean
 * (0 when either is 0).
 */
void score_map(const map_geom_t *g, const uint8_t *map, const uint8_t *truth,
               const uint8_t *observable, score_t *out);

/** Mark every cell whose centre lies within radius_m of (x, y). */
void mark_disc(const map_geom_t *g, uint8_t *marks, double x, double y, double radius_m);

/**
 * Write an image of a×b bytes (row 0 = the top = the largest y, as hal_common/mapexport.h
 * makes them) as DIR/NAME.pgm and, when @p yaml, its ROS map_server DIR/NAME.yaml.
 * @return 0, or -1 with a message on stderr
 */
int write_map(const char *dir, const char *name, const map_geom_t *g, const uint8_t *img,
              bool yaml);

/**
 * Ground truth for export: the scoring truth's boundary cells, the inside of solid
 * obstacles filled (cells no 4-connected path of free cells joins to the start or to the
 * grid's border), the outside of the room left unknown (reached from the border).
 * @param truth  boundary cells (room_rasterize()), a·b
 * @param out    the trinary image (mapexport.h), first row the grid's last
 * @return 0, or -1 when out of memory
 */
int truth_image(const map_geom_t *g, const uint8_t *truth, uint32_t start, uint8_t *out);

/**
 * Append v with exactly @p decimals digits after the point (rounded half away from zero)
 * to @p out, then @p sep if it is not 0; returns the new end. What printf's "%.Nf" writes
 * for |v| < 9e8, a tenth of its cost: the logs hold tens of thousands of numbers.
 */
char *fmt_fixed(char *out, double v, int decimals, char sep);

/*
 * The logs' columns (host_sim/README.md describes them). Units are in the names; each kind
 * of column has one precision, enough to carry the firmware's value exactly: times are
 * whole 10 ms ticks, lengths whole µm, servo angles whole millidegrees, and ten decimals
 * of a radian are finer than half a binary angle unit (7.3e-10 rad), so a replay recovers
 * the firmware's exact heading.
 */
#define CSV_TIME_DECIMALS 2
#define CSV_LENGTH_DECIMALS 6
#define CSV_HEADING_DECIMALS 10
#define CSV_SERVO_DECIMALS 3
#define CSV_READINGS_HEADER "t_s,servo_deg,range_m,status,odom_x_m,odom_y_m,odom_th_rad"
#define CSV_TRUTH_COLUMNS "true_x_m,true_y_m,true_th_rad"
#define CSV_TRAJECTORY_HEADER "t_s,odom_x_m,odom_y_m,odom_th_rad," CSV_TRUTH_COLUMNS
/* The estimate's columns, then the pose correction's own statistics after the reading was
 * processed: the filter's covariance over x, y, θ in its units, the match counters, and
 * the increment the last match wanted (applied or refused); last, OM's byte where the echo
 * ends, seen from the estimate. */
#define CSV_ESTIMATE_HEADER                                                                        \
    "t_s,est_x_m,est_y_m,est_th_rad,cov_xx_um2,cov_xy_um2,cov_yy_um2,cov_xth_um_urad,"             \
    "cov_yth_um_urad,cov_thth_urad2,match_tried,match_applied,match_refused,match_points,"         \
    "step_x_m,step_y_m,step_th_rad,om_at_echo"

/**
 * The status column of a reading: "ok" inside the confidence sector (range_min <= d < rc),
 * "far" at or beyond rc, "near" below range_min, "timeout" without an echo.
 */
const char *reading_status(const sonar_t *s, bool echo, uint32_t range_um);

/**
 * Open DIR/NAME (or the path NAME when dir is NULL) for writing. A regular file (or a new
 * one) is written under a temporary name beside it and takes its name only at
 * outputs_commit(), so a run that fails leaves the earlier file as it was; a device or a
 * pipe is written in place.
 * @return the file, or NULL with a message on stderr
 */
FILE *open_out(const char *dir, const char *name);

/**
 * Open a file in place for writing as it goes (--telemetry, a device, a FIFO): a FIFO that
 * no program reads yet is refused at once rather than waited on.
 * @return the file, or NULL with a message on stderr
 */
FILE *open_stream(const char *path);

/** Close a file opened by open_out(); -1 with a message when the write failed. */
int close_out(FILE *f, const char *dir, const char *name);

/** Give every file open_out() wrote its name; -1 with a message when one could not. */
int outputs_commit(void);

/** Remove the temporary files of open_out(), and the folders make_dirs() created if they
 *  are empty: the earlier outputs stay as they were. */
void outputs_discard(void);

/**
 * Check, changing nothing, that an output folder can be written: it is a writable
 * directory (none of @p names, a NULL-terminated list, being there as anything but a
 * regular file), or the nearest existing folder above it is one.
 * @param what  the option, for the message ("--out")
 * @return 0, or -1 with a message naming the option and the path
 */
int check_out_dir(const char *what, const char *dir, const char *const *names);

/** The same for an output file: not a directory, writable, in a writable folder. */
int check_out_file(const char *what, const char *path);

/** Create a directory and its parents; -1 with a message on stderr. */
int make_dirs(const char *path);

/** The robot's map storage slots as DIR/slot0.bin, DIR/slot1.bin; -1 with a message. */
int write_storage(const char *dir);

/* ---- options (options.c) --------------------------------------------------------------- */

#define HOST_SIM_MAX_SETS 64 /* --error and --set options at most */

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
    bool has_seed, has_cell, has_explore, has_duration; /* given on the command line */
    const char *out;
    bool has_out; /* --out given: a replay's default is beside its log, not out/sim */
    bool ideal;
    bool paper;
    int sonar;       /* --sonar: the sonar's realism level (sim_sonar_level_t) */
    bool has_sonar;  /* given on the command line */
    bool has_sonar1; /* --sonar1: a second, fixed sonar (HAL instance 1) */
    double sonar1_x, sonar1_y, sonar1_deg; /* its mount: m ahead, m left, deg from the heading */
    bool bumpers;                          /* --bumpers: the front bump switches */
    const char *errors[HOST_SIM_MAX_SETS];
    size_t nerrors;
    const char *config;
    const char *calibration; /* --calibration FILE|none; NULL: the shipped one for the
                                default robot (scenario.c resolves it: NULL when none applies) */
    const char *sets[HOST_SIM_MAX_SETS];
    size_t nsets;
    const char *trace;
    const char *telemetry;
    const char *commands;
    const char *storage;
    const char *link; /* --link PATH: the UART live on a pseudo-terminal (viewers.h) */
    const char *bag;  /* --bag FILE: the run as a ROS bag (viewers.h) */
    bool realtime;
    double realtime_factor; /* simulated seconds per wall-clock second under --realtime */
    const char *replay;
    bool scoring; /* --scoring: write the scorer's truth and observable masks */
    bool sweep;   /* --sweep: score the post-processing chain at every TH and K */
    bool plot;
    bool quiet;
} options_t;

extern const char *const explore_names[EXPLORE_MODES];

/** Parse the command line (--help prints and exits); 0, or EXIT_USAGE with a message. */
int parse_options(int argc, char **argv, options_t *o);

/**
 * Every output path of a run, checked before anything is written (check_out_dir(),
 * check_out_file()): --out, --trace, --telemetry, and that no two of them name one file.
 * @return 0, or -1 with a message
 */
int check_outputs(const options_t *o);

/** Remove the temporary files of open_out() that runs now gone left in the run's folders
 *  (--out, --storage, beside --trace): killed at once, they could not remove their own. */
void outputs_sweep(const options_t *o);

/** One --error NAME=VALUE onto the error levels; 0, or -1 with a message. */
int apply_error(sim_errors_t *e, const char *nv);

/**
 * The run's firmware configuration (config.c): defaults, then the --config file, then
 * what the options set (--paper, --cell, --explore, --seed, then each --set in turn), then the
 * scenario's start pose (sx, sy in m, sth in rad) and the grid placement (the room in the
 * middle of the grid, unless start_cell_a/b were set). Refused with a message naming the
 * option, or the file, line and key: a value two options set differently, a key given
 * twice, a start pose in the file that is not the scenario's, a room that does not fit
 * the grid, any value slam_config_check() refuses (with its valid range). A --config file
 * that sets cal_left, cal_right or cal_base becomes o->calibration: where the calibration
 * the firmware runs with came from.
 * @return 0, or -1 with a message
 */
int build_config(options_t *o, const room_t *room, double sx, double sy, double sth,
                 slam_config_t *cfg);

/** The firmware's explore_seed for a run's --seed: distinct for seeds 0 .. 2^32 - 3. */
uint32_t explore_seed_of(uint64_t seed);

/* Units: the firmware's µm and binary angles from metres and radians, and back. */
static inline int32_t to_um(double m)
{
    double v = m * 1e6;
    if (fabs(v) < 2147483647.0) { /* so that i ± 1 fits too */
        /* lround(v) without its call (it runs twice a period): the fraction beside the
         * truncated value is exact, and a half rounds away from zero. */
        int32_t i = (int32_t)v;
        double f = v - (double)i;
        return i + (f >= 0.5) - (f <= -0.5);
    }
    return (int32_t)lround(v);
}

/* remainder(a, 2π), into [-π, π]: the IEEE remainder is exact, and so is each step here
 * for |a| <= 4π (Sterbenz: x - y is exact when y/2 <= x <= 2y), at a tenth of libm's
 * cost; it runs several times a period. Beyond, libm's. */
static inline double wrap_pi(double a)
{
    /* π as a double object: where doubles are evaluated in a wider format (i386's x87,
     * C11), the constant itself would compare as the wider π. */
    static const double pi = HOST_SIM_PI;
    const double turn = 2.0 * pi;
    double m = fabs(a);
    if (m <= pi) {
        return a; /* a tie at π keeps the even quotient, 0 */
    }
    if (!(m <= 2.0 * turn)) {
        return remainder(a, turn);
    }
    double r = m - turn; /* quotient 1 */
    if (r >= pi) {
        r -= turn; /* quotient 2, which a tie at 3π also takes: it is even */
    }
    return a < 0.0 ? -r : r;
}

static inline bam32_t to_bam(double rad)
{
    double turns = rad / (2.0 * HOST_SIM_PI);
    turns -= floor(turns);
    return (bam32_t)(uint64_t)llround(turns * 4294967296.0);
}

static inline double bam_rad(bam32_t b)
{
    return (double)b * (2.0 * HOST_SIM_PI / 4294967296.0);
}

/* ---- what a run measures (observe.c, coverage.c) and reports (report.c) ------------------ */

/** Progress is coming this far (m) from where the robot last made progress. */
#define PROGRESS_M 0.2
/** A touch is recovered from once the body is out of contact and this far (m) from
 *  where it began. */
#define MOVED_ON_M 0.05
/** The touches whose recovery times metrics.json lists. */
#define TOUCHES_LISTED 16u

/* Everything measured while the robot runs. */
typedef struct {
    map_geom_t geom;
    uint8_t *truth;
    uint8_t *observable;
    uint8_t *reachable;
    uint8_t *seen;
    uint32_t reachable_cells;
    uint32_t visited_cells;
    double time_to[3];      /* to 50, 80, 90 % of the reachable cells; < 0: not reached */
    double series[4096][3]; /* (t, coverage, wall coverage) */
    size_t nseries;
    /* Wall coverage (coverage.c). */
    const room_t *room;
    uint64_t *wall_left; /* bit i: cell i is a wall cell the robot could map, not yet inside
                            the confidence sector of a ping */
    uint32_t wall_cells, walls_covered;
    double wall_time_to[3]; /* to 50, 80, 90 % of the wall cells; < 0: not reached */
    double rc_m, half_cone, body_m;
    /* The smallest gap between the body and an obstacle, and where it was last asked. */
    double min_clearance, clear_x, clear_y, clear_at;
    double max_pos_err, max_th_err, final_pos_err, final_th_err, path_m;
    /* The first touch: when (s, < 0: none), the true pose, the bearing of the obstacle
     * from the heading (rad, left positive) and the pose estimate's errors (m, rad). */
    double touch_t, touch_x, touch_y, touch_th, touch_bearing, touch_pos_err, touch_th_err;
    double last_x, last_y;
    double marked_x, marked_y; /* the sonar position last marked observable around */
    /* Progress (observe.c): where the robot last came PROGRESS_M from the place before and
     * when, not counting a deliberate stand; the longest time without, and when it began. */
    double prog_x, prog_y, prog_t, stuck_s, stuck_from_s;
    /* Touches (observe.c): one begins when the body meets an obstacle, and it is recovered
     * from once the body is out of contact and MOVED_ON_M from where it began. */
    bool touching;
    double touch_from_t, touch_from_x, touch_from_y;
    uint32_t touches;                        /* begun */
    double touch_recovery_max_s;             /* the longest recovery so far */
    double touch_recovery_s[TOUCHES_LISTED]; /* of the first ones, < 0: not recovered */
    double explored_at_s;                    /* when the firmware said it was done; < 0: never */
    /* Truth cells (walls) the readings lowered in the perfect-odometry map: by echoes that
     * came by a mirror path (SIM_PING_MULTIPATH), and by the others (observe.c). */
    uint32_t walls_lowered[2];
    FILE *estimates;      /* --scoring: the estimated pose of every reading's ping */
    uint32_t sonar1_seen; /* the second sonar's readings observed (robot.sonar1.readings) */
} run_t;

/** Clearance is looked for this far beyond the body, m. */
#define CLEARANCE_CAP_M 0.5

/**
 * Find the wall cells the robot could map (truth cells facing the open space around the
 * start, within rc of a cell its centre can reach) into r->wall_left; needs r->truth and
 * r->reachable. Also readies the clearance watch. 0, or -1 when out of memory.
 */
int walls_init(run_t *r, const room_t *room, const sim_params_t *p, double rc_m, uint32_t start);

/** Mark the wall cells inside one ping's confidence sector (true sensor position, true
 *  beam axis) as covered, at time t. */
void walls_ping(run_t *r, double sx, double sy, double bearing, double t);

/** Track the smallest gap between the body at (x, y) and any obstacle. */
void clearance_tick(run_t *r, double x, double y);

/** Note the run's first touch, when the world reports contact at (x, y, th) at time t with
 *  the pose estimate off by pos_err m and th_err rad: where the obstacle lay. */
void touch_tick(run_t *r, bool contact, double x, double y, double th, double t, double pos_err,
                double th_err);

typedef struct {
    score_t raw, threshold, templ, insert;
} chain_scores_t;

/* The post-processing parameters over their whole range: F1 for every TH and K. */
#define SWEEP_K 9u
#define SWEEP_EVIDENCE_TH 16u
typedef struct {
    uint8_t th_count;
    score_t s[256][SWEEP_K];
    uint8_t best_th, best_k;
} post_sweep_t;

/** Score a map after each post-processing step; the final map is left in @p out. */
void score_chain(const run_t *r, const uint8_t *om, const slam_config_t *cfg, uint8_t *out,
                 uint8_t *scratch, chain_scores_t *s);

/** Score the chain at every threshold and template K. */
void sweep_post(const run_t *r, const uint8_t *om, const slam_config_t *cfg, uint8_t *out,
                uint8_t *scratch, post_sweep_t *ps);

/** Write metrics.json (DESIGN.md §5, and the scenario that produced it); post_sweep only
 *  when @p ps is not NULL (--sweep). */
int write_metrics(const options_t *o, const room_t *room, const run_t *r, const slam_config_t *cfg,
                  const sim_errors_t *e, const sim_t *sim, const robot_t *robot,
                  const chain_scores_t *odo, const chain_scores_t *ideal, const post_sweep_t *ps);

/** The summary table on stdout; the best TH and K only when @p ps is not NULL. */
void print_summary(const options_t *o, const run_t *r, const chain_scores_t *odo,
                   const chain_scores_t *ideal, const post_sweep_t *ps, double wall_s,
                   uint64_t ticks, const sim_t *sim, const robot_t *robot);

/** figure.png through tools/plot_run.py; a missing Python or matplotlib is a warning. */
void plot_figure(const char *out, bool quiet);

/** --replay: rebuild OM from a readings.csv through the same mapper (replay.c). */
int replay(const options_t *o);

/* ---- commands to the robot (commands.c) -------------------------------------------------- */

typedef struct {
    uint64_t tick; /* the tick after which the bytes arrive */
    size_t offset; /* into bytes */
    size_t len;
} command_line_t;

/** The --commands file: framed command bytes and when they arrive. */
typedef struct {
    command_line_t *lines;
    size_t n, lines_cap;
    uint8_t *bytes;
    size_t nbytes, bytes_cap;
    size_t grows;   /* reallocations made while reading (tests bound them) */
    size_t next;    /* the next line to feed */
    size_t dropped; /* bytes the UART had no room for */
} commands_t;

/**
 * Read a --commands file: `TIME_S COMMAND` lines (start, stop, mode MODE, get KEY,
 * set KEY VALUE, save, map, calibrate, or hex BYTES), times not going back; `#` comments.
 * @return 0, or EXIT_USAGE with a message naming the file and line
 */
int commands_load(const char *path, commands_t *c);

/** Hand the robot's UART every command due by @p tick (hal_host_uart_receive()). */
void commands_feed(commands_t *c, uint64_t tick);

void commands_free(commands_t *c);

/** One row of a readings.csv, as the replay maps it. */
typedef struct {
    double servo_deg; /**< -360..360 */
    bool echo;        /**< an echo (status ok, far or near); else a timeout */
    double range_m;   /**< 0..1000 with an echo; 0 */
    double x_m, y_m;  /**< odometry pose of the ping, within 1 km */
    double th_rad;    /**< within ±1000 rad */
} replay_row_t;

typedef void (*replay_row_fn)(void *ctx, const replay_row_t *row);

/**
 * Read a readings.csv: its header (the columns of CSV_READINGS_HEADER, found by name, in
 * any order among others), then every row, each checked whole (the numbers within the
 * ranges above, a status of ok, far, near or timeout, a range only with an echo) and
 * handed to @p fn in order.
 * @param name  the file's name, for messages
 * @return 0, or -1 with "NAME:LINE: what is wrong" in err (an empty file, a header and
 *         no row, a NUL byte, a line of 512 characters or more, a last line without its
 *         newline (a file cut short), a wrong header, a malformed row)
 */
int replay_read(FILE *in, const char *name, replay_row_fn fn, void *ctx, char *err, size_t errlen);

/** A row as the robot's tick posted its reading: micrometres, binary angles. */
readq_reading_t replay_reading(const replay_row_t *row);

/* ---- the scenario (scenario.c) ---------------------------------------------------------- */

/** What a run is: the input, each part checked, and the world built from it. */
typedef struct {
    room_t room;         /* the room, its start pose set to the one chosen */
    double sx, sy, sth;  /* the start pose, m and rad */
    sim_errors_t errors; /* the robot's error levels */
    slam_config_t cfg;   /* the firmware's configuration */
    commands_t commands; /* --commands, if given */
    sim_params_t params; /* the robot as built (from cfg) */
    sim_t *sim;          /* the world */
} scenario_t;

/**
 * Load and check everything a run needs before anything is written: the room, the start
 * pose (--start, the room's, or one found), the error levels and the calibration that
 * goes with them (o->calibration resolved), the configuration (o->cell_mm and o->explore
 * set from it), the commands, the world. What was loaded stays in @p sc on failure too.
 * @return 0, or EXIT_USAGE with a message
 */
int scenario_load(options_t *o, scenario_t *sc);

/** Free what scenario_load() made (the world first: detach it from the HAL before). */
void scenario_free(scenario_t *sc);

/* ---- what a run measures as it goes (observe.c) ----------------------------------------- */

/** The firmware of a run, and its twin fed the same readings at the true poses. */
typedef struct {
    robot_t robot;     /* the firmware's state, as a robot program owns it */
    grid_t ideal_grid; /* the same readings mapped from the true poses */
    mapper_t ideal_mapper;
} firmware_t;

/** The logs written as the robot runs. */
typedef struct {
    FILE *readings, *trajectory, *trace, *telemetry;
} run_logs_t;

/**
 * Ready the measurements of a run: the geometry, the truth, the reachable cells and the
 * walls of run_t (its maps allocated and zero), the coverage marks, the start.
 * @param start_cell  out: the grid index of the start cell
 * @return 0, or -1 (out of memory) with a message
 */
int observe_init(run_t *r, const scenario_t *sc, const robot_t *robot, uint32_t *start_cell);

/**
 * After each tick (@p last: the run's last): odometry error against the truth of the
 * period's start (@p before), coverage, clearance and touch, the trajectory and the
 * reading of the tick if any (logged, and mapped into the twin from the true pose).
 */
void observe_tick(run_t *r, firmware_t *fw, const sim_t *sim, const sim_truth_t *before,
                  const sim_params_t *p, const run_logs_t *logs, uint64_t tick, bool last);

/* ---- the UMBmark experimenter (experimenter.c) ------------------------------------------ */

#define EXPERIMENTER_CSV "umbmark.csv" /* the measurements, in the output folder */

/* Without --duration, a robot that runs UMBmark runs until its last run is measured; no
 * test takes ten hours (50 runs each way of a 100 m square would: the longest allowed). */
#define EXPERIMENTER_MAX_S 36000.0

/** A person with a tape measure beside the UMBmark test (firmware/include/slam/umbmark.h). */
typedef struct {
    const char *dir;                   /* the output folder */
    FILE *csv;                         /* EXPERIMENTER_CSV, open from the first measurement */
    bool failed;                       /* it could not be written */
    uint64_t rng;                      /* the tape's noise */
    double start_x, start_y, start_th; /* the start pose in the world, m and rad */
    unsigned measured;                 /* runs measured */
    bool quiet;
} experimenter_t;

void experimenter_init(experimenter_t *x, const char *dir, uint64_t seed, double start_x,
                       double start_y, double start_th, bool quiet);

/**
 * After each tick: while the robot runs UMBmark and has just finished a run (it stands in
 * the pause that follows), write the run's return error to DIR/umbmark.csv, the true
 * position read with the tape's noise minus odometry's, in the start pose's frame, mm
 * (one line a run: direction,x_mm,y_mm; tools/umbmark.py reads it), and put the robot
 * back at the start pose (sim_place()). A progress line per run on stderr unless quiet.
 * @return 0 nothing done, 1 a run measured, 2 the last run measured, -1 failed (the robot
 *         ran into something: the square does not fit; or the file cannot be written)
 */
int experimenter_tick(experimenter_t *x, sim_t *sim, const robot_t *rb);

/** Close the file; -1 with a message when writing it failed. */
int experimenter_close(experimenter_t *x);

#endif /* HOST_SIM_HOST_SIM_H */
