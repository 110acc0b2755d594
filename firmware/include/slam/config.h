/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The configuration of the core: one `slam_config_t` with the paper's defaults.
 *
 * Frames and units: the world frame is metric with x and y in micrometres (µm) and angles
 * in millidegrees (mdeg), counter-clockwise from +x. The robot frame has x forward and y to
 * the left of the wheel-axle centre. Servo angles follow the paper: 90° points straight
 * ahead, 65° is 25° to the left and 155° is 65° to the right (Eq. 3).
 *
 * Compile-time choices (grid size A×B) live in grid.h; everything here can be changed at
 * run time by filling a `slam_config_t` before robot_init(). A configuration is checked as
 * a whole by slam_config_check(); the core refuses a bad one and changes nothing.
 *
 * Each member has a row in config_fields.h (its type, default, range, telemetry key and
 * range in words): a new field is a member here, with its doc, and a row there.
 */
#ifndef SLAM_CONFIG_H
#define SLAM_CONFIG_H

#include <stdint.h>

#include "slam/explore_modes.h"
#include "slam/fixed.h"

/** Marks a function that runs at start-up or once in a long while, never in a tick: the
 *  compiler builds it for size and away from the tick's code (GCC's and Clang's cold). */
#define SLAM_START_UP __attribute__((cold))

/** The control period: Algorithm C.1 and robot_tick() run once per period. */
#define SLAM_TICK_US 10000u

/** The most servo stops a sweep may have. */
#define SLAM_SWEEP_STOPS_MAX 16u

/** The corridor ahead that exploration reads on the map (explore/corridor.c): rows of
 *  cells up to this far ahead of the axle, each as wide as twice clearance_um. */
#define SLAM_CORRIDOR_REACH_UM 300000u
/** The most cells the corridor may hold: it is read 8 cells a tick, so a pass over the
 *  largest takes 0.3 s. The configuration check refuses a cell size and clearance whose
 *  corridor would be larger (20 mm cells take a clearance below 160 mm). */
#define SLAM_CORRIDOR_CELLS_MAX 240u

/** The corridor's rows: the cells whose centres lie within the reach, one at least. */
static inline uint32_t slam_corridor_rows(uint32_t cell_um)
{
    uint32_t rows = SLAM_CORRIDOR_REACH_UM / cell_um;
    return rows < 1u ? 1u : rows;
}

/** The corridor's columns: cell-spaced samples spread over ±clearance_um. */
static inline uint32_t slam_corridor_columns(uint32_t cell_um, uint32_t clearance_um)
{
    return 2u * clearance_um / cell_um + 1u;
}

/** What an OM cell holds (grid.h). */
typedef enum {
    OM_MODE_COUNT = 0,    /**< the paper's Eq. 6: hits counted up to OMmax, nothing else */
    OM_MODE_EVIDENCE = 1, /**< a log-odds byte: hits raise it, beams that pass lower it */
    OM_MODES
} om_mode_t;

/** How the robot explores (explore.h): the rows of explore_modes.h. */
typedef enum {
#define SLAM_EXPLORE_MODE_ENUM(id, value, ...) id = value,
    SLAM_EXPLORE_MODES(SLAM_EXPLORE_MODE_ENUM)
#undef SLAM_EXPLORE_MODE_ENUM
        EXPLORE_MODES
} explore_mode_t;

/** Everything the core can be told about the robot, the sensor and the method; the
 *  defaults and ranges are those of config_fields.h. */
typedef struct {
    /* Odometry (Eq. 8-12). */
    uint32_t wheel_diameter_left_um;  /**< nominal left wheel diameter; 65 mm */
    uint32_t wheel_diameter_right_um; /**< nominal right wheel diameter; 65 mm */
    uint32_t wheel_base_um;           /**< 2h, distance between the wheel contacts; 130 mm */
    uint32_t encoder_counts_per_rev;  /**< encoder counts per wheel turn; 700 */
    q1_30_t cal_left;                 /**< UMBmark correction c_L of the left wheel distance; 1.0 */
    q1_30_t cal_right; /**< UMBmark correction c_R of the right wheel distance; 1.0 */
    q1_30_t cal_base;  /**< UMBmark E_b, actual over nominal wheel base; 1.0 */

    /* Start pose in the world frame (known at the start, paper §III.B). */
    int32_t start_x_um;         /**< SLAM_START_UM */
    int32_t start_y_um;         /**< SLAM_START_UM */
    int32_t start_heading_mdeg; /**< 0 (facing +x) */

    /* Grids (Eq. 1-2, 6-7). */
    uint32_t cell_um;      /**< L, the side of a square cell; 50 mm */
    uint16_t grid_a;       /**< A, cells along x: 3..SLAM_GRID_A, or 0 for SLAM_GRID_A; 0 */
    uint16_t grid_b;       /**< B, cells along y: 3..SLAM_GRID_B, or 0 for SLAM_GRID_B; 0 */
    uint16_t start_cell_a; /**< the cell (a, b) whose centre is the start pose; */
    uint16_t start_cell_b; /**< the centre of the grid by default */
    uint8_t om_max;        /**< OMmax, Eq. 6 (OM_MODE_COUNT); 9 */
    uint8_t tm_max;        /**< TMmax, Eq. 7; 30 */
    uint8_t om_mode;       /**< an om_mode_t; OM_MODE_EVIDENCE (the best F1, measured) */
    uint8_t om_hit;        /**< OM_MODE_EVIDENCE: log-odds added by a hit; 4 */
    uint8_t om_miss;       /**< OM_MODE_EVIDENCE: log-odds taken by a beam passing; 1 */

    /* Sonar (Eq. 3-5). */
    uint32_t confidence_radius_um; /**< rc: readings with d >= rc never touch OM; 1 m */
    uint32_t range_min_um;         /**< shorter readings are discarded; 20 mm (HC-SR04) */
    uint32_t sound_speed_mm_per_s; /**< speed of sound; 343 m/s (20 °C) */
    int32_t mount_x_um;            /**< servo axis in the robot frame, forward; 50 mm */
    int32_t mount_y_um;            /**< servo axis in the robot frame, left; 0 */
    int32_t mount_yaw_mdeg;        /**< extra yaw of the servo's 90° from straight ahead; 0 */

    /* Sweep (§II.A): stops from first to last, then back, all timing in control ticks. The
     * paper sweeps 65° to 155° in six stops (slam_config_paper()); the default reaches 90°
     * to the right, where the wall the walls mode follows stands square to the beam, and
     * 50° to the left: a real HC-SR04 answers a wall only near its normal (firmware/
     * experiments.md, "Exploration": own-pose F1 0.82 -> 0.91 at the typical sonar). */
    int32_t sweep_first_mdeg;       /**< 40° (the paper: 65°) */
    int32_t sweep_last_mdeg;        /**< 180° (the paper: 155°) */
    uint8_t sweep_stops;            /**< 8, 20° apart (the paper: 6, 18° apart) */
    uint8_t settle_ticks;           /**< servo travel + settle before the ping; 3 (30 ms) */
    uint8_t echo_timeout_ticks;     /**< give up on an echo after this; 4 (40 ms >= 38 ms) */
    uint16_t servo_pulse_0deg_us;   /**< servo pulse at 0°; 500 µs (SG90) */
    uint16_t servo_pulse_180deg_us; /**< servo pulse at 180°; 2500 µs (SG90) */

    /* Post-processing (§II.D). The defaults are those of OM_MODE_EVIDENCE, where every
     * step lowered the measured F1: TH 0, no template, no insert. The paper's are TH 3,
     * K 1 (K 4 erases thin walls) and insert on. */
    uint8_t post_threshold;  /**< TH: a cell at OM <= TH (OM_MODE_COUNT), or at log-odds
                                  <= TH (OM_MODE_EVIDENCE), holds no obstacle; 0 */
    uint8_t post_template_k; /**< K: occupied cells with fewer occupied neighbours are
                                  freed; 0 = off; 0 */
    uint8_t post_insert;     /**< 1: free cells between two occupied ones are filled; 0 */

    /* Motion (§III.B). */
    uint16_t top_speed_mm_s; /**< wheel speed at full duty (feed-forward); 300 */
    uint16_t accel_mm_s2;    /**< acceleration limit of each wheel; 500 */
    uint16_t motion_kp_q8;   /**< duty per µm/tick of speed error, Q8; 64 */
    uint16_t motion_ki_q8;   /**< duty per µm of accumulated error, Q8; 8 */

    /* Exploration (§II.E). */
    uint8_t explore_mode;    /**< an explore_mode_t; EXPLORE_WALLS (the best wall coverage
                                  and F1 measured in the simulator) */
    uint16_t cruise_mm_s;    /**< forward speed; 200 */
    uint16_t turn_mm_s;      /**< wheel speed when turning in place; 100 */
    uint32_t avoid_um;       /**< turn away from anything closer ahead than this; 300 mm */
    uint32_t clearance_um;   /**< half the width of the corridor the robot needs; 130 mm */
    uint32_t square_side_um; /**< side of the EXPLORE_SQUARE path and of UMBmark's squares;
                                  1.5 m: the errors UMBmark measures come out divided by
                                  4 sides, and most rooms hold a 1.5 m square */
    uint8_t square_laps;     /**< laps of the square, then stop; 0 = go on forever; 1 */
    uint32_t explore_seed;   /**< the random stream of the exploration (not 0); 1 */

    /* Persistence (mapstore.h). */
    uint16_t save_period_s; /**< save the maps this often from robot_idle(); 0 = never; 60 */

    /* Localization (localize.h). */
    uint8_t localize; /**< 1: correct the pose against OM; 0: odometry alone (the
                           paper's); 1 */

    /* Sonar timing and the walls mode. */
    uint8_t ping_interval_ticks; /**< least time from one trigger to the next; 6 (60 ms, the
                                      HC-SR04 datasheet's measurement cycle: sooner, the
                                      late echo of one ping is read as the next) */
    uint32_t follow_um;          /**< walls mode: distance from the axle to what it follows;
                                      300 mm */
    /* Calibration (umbmark.h): the UMBmark test on the square of square_side_um. */
    uint8_t umbmark_runs;     /**< runs in each direction, 1..50; 5 (Borenstein & Feng) */
    uint16_t umbmark_pause_s; /**< standing still before and after each run, to measure
                                   and put the robot back, 1..3600 s; 90 */
    /* A second sonar (HAL sonar 1): a fixed HC-SR04 on the servo's axis. */
    uint8_t sonar1_map;  /**< 1: ping it from robot_idle() between the sweep's pings and map
                              its readings as the sweep's (when readings are deferred:
                              localize = 1 or om_mode = 1); 0 */
    int32_t sonar1_mdeg; /**< the way its beam faces, as a servo angle: 0 looks left, 90
                              ahead, 180 right (millidegrees); 0 */
} slam_config_t;

/** Fill @p cfg with the defaults above. */
void slam_config_default(slam_config_t *cfg);

/**
 * Turn a configuration to the paper's method, leaving the robot's geometry alone: the pose
 * is odometry alone, OM counts hits (Eq. 6, OM_MODE_COUNT) and post-processing is the
 * paper's threshold TH 3, template (K 1: the paper's four neighbours erase one-cell walls)
 * and insert, and the sweep is the paper's, 65° to 155° in six stops.
 */
void slam_config_paper(slam_config_t *cfg);

/**
 * Check every field of a configuration against its valid range.
 * @param cfg    the configuration
 * @param field  out: on error, the name of the first bad field (a static string);
 *               may be NULL
 * @retval SLAM_OK      every field is in range
 * @retval SLAM_EINVAL  a field is out of range; *field names it
 */
int slam_config_check(const slam_config_t *cfg, const char **field);

#endif /* SLAM_CONFIG_H */
