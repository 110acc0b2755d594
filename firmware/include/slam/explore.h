/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Exploration (paper §II.E): where to drive next, from the sonar and the maps.
 *
 * The sweep sees from 25° left to 65° right of straight ahead (with the beam's 7.5° half
 * cone, 32.5° and 72.5°), so the left flank is blind: a wall that converges from the left
 * at less than about 12° is never met at an incidence that echoes. Every mode shares what
 * keeps the robot clear of what it cannot see:
 *
 * - An obstacle memory: the last EXPLORE_POINTS obstacle points the sonar placed inside
 *   the confidence sector, in world coordinates (so they stay right while the robot
 *   turns), forgotten after EXPLORE_MEMORY_TICKS. Something is *ahead* when a point lies
 *   in the corridor the robot's body would sweep: less than clearance to either side of
 *   the centre line. The memory is checked EXPLORE_SCAN_POINTS points a tick, a whole pass
 *   every few ticks.
 * - Speed: the robot slows down as the nearest point ahead comes closer, from cruise at
 *   EXPLORE_SLOW_UM down to a crawl at avoid_um ahead of the sonar, where it stops.
 * - Turns toward the seen side: when something is ahead the robot turns left, so that
 *   the obstacle is on its right, where the sweep keeps seeing it. Turning in place never
 *   touches anything (the body is round about the axle); after every turn the robot
 *   stands still for a full sweep and looks before it drives into what was blind.
 * - Heading choices read the maps through grid_state(): an occupied cell blocks a way.
 * - Deafness: with no echo from any stop for a second the robot stands, up to three
 *   seconds (a stuck echo line or lost pings pass; open space stays silent).
 * - A trail of the last EXPLORE_TRAIL positions, EXPLORE_TRAIL_STEP_UM apart: wheels that
 *   stall (something unseen touched) make the robot stand a while (HOLD), then back off
 *   along the path that brought it in, whose cells its body has just swept; one wheel
 *   stalled while the other turns (a wheel or an encoder failed, nothing touched) makes
 *   it stand and look instead.
 *
 * The modes:
 * - EXPLORE_RANDOM, the paper's: drive straight; when something is ahead, stop and turn
 *   away from the side it is on by a random 90°..180°; now and then (and after driving
 *   straight too long) turn by a random angle anyway.
 * - EXPLORE_TM: the same avoidance, but each new heading (at the start, when something is
 *   ahead, and every EXPLORE_TM_REDECIDE_TICKS of driving) is the one of
 *   EXPLORE_CANDIDATES directions whose ray through TM (1 m, stopped by occupied cells)
 *   crosses the fewest visits, the smallest turn among equals: the trajectory map used
 *   for online path planning, as the paper says it can be. A candidate is weighed over a
 *   few ticks (about half a second for all, standing still), so every tick stays small.
 * - EXPLORE_WALLS: TM-guided wall following, which seeks the walls the sonar has not yet
 *   covered. The robot follows whatever it meets with it on its right, at follow_um from
 *   the axle, where the sweep sees it at good incidence and every wall cell passes
 *   through the confidence sector: into concave corners it turns left, around convex ones
 *   and through openings it arcs right. When the way along the wall has been driven
 *   before (TM), it leaves: it weighs the headings to its left as EXPLORE_TM does, drives
 *   straight to whatever it meets next, and follows that.
 * - EXPLORE_SQUARE: square_laps counter-clockwise squares of square_side by odometry
 *   (UMBmark's path), turning in place at the corners, then stop.
 * - EXPLORE_OFF: stand still.
 *
 * Work per tick: a tick that completes a sonar reading belongs to the map update, so the
 * exploration only notes it then and takes the reading's point into its memory in the
 * next tick; every check runs in ticks without a reading, in bounded chunks.
 *
 * The output is a target speed for each wheel; motion.h follows it.
 */
#ifndef SLAM_EXPLORE_H
#define SLAM_EXPLORE_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/odometry.h"
#include "slam/sweep.h"

#define EXPLORE_CANDIDATES 12u          /**< headings weighed in TM mode, 30° apart */
#define EXPLORE_POINTS 16u              /**< obstacle points remembered */
#define EXPLORE_MEMORY_TICKS 500u       /**< obstacle points are forgotten after 5 s */
#define EXPLORE_ECHO_WINDOW 12u         /**< readings whose echoes are counted: a sweep */
#define EXPLORE_ECHOES_SURE 8u          /**< of them, echoes below which it slows down */
#define EXPLORE_ECHO_MASK ((1u << EXPLORE_ECHO_WINDOW) - 1u)
#define EXPLORE_SCAN_POINTS 4u          /**< memory points checked a tick */
#define EXPLORE_TRAIL 8u                /**< trail positions kept */
#define EXPLORE_TRAIL_STEP_UM 50000     /**< one trail position each 50 mm driven */
#define EXPLORE_SLOW_UM 700000          /**< slow down from this far ahead of the sonar */
#define EXPLORE_FORWARD_MAX_TICKS 2000u /**< random mode: turn anyway after 20 s straight */
#define EXPLORE_TM_REDECIDE_TICKS 600u  /**< TM mode: weigh the ways again after 6 s */
#define EXPLORE_RAY_CELLS 8u            /**< TM cells a DECIDE tick walks at most */
#define EXPLORE_BACK_UM 150000          /**< how far to back off after a stall */
#define EXPLORE_DOOR_MIN_UM 180000      /**< walls mode: an opening seen this wide or wider */
#define EXPLORE_DOOR_MAX_UM 1000000     /**< and at most this wide is passed at its middle */
#define EXPLORE_PASS_CLEAR_UM 105000    /**< half the corridor through an opening */
#define EXPLORE_BLOCK_SHIFT 4u          /**< frontier blocks are 16 x 16 cells */
#define EXPLORE_BLOCKS_A ((SLAM_GRID_A + 15u) >> EXPLORE_BLOCK_SHIFT)
#define EXPLORE_BLOCKS_B ((SLAM_GRID_B + 15u) >> EXPLORE_BLOCK_SHIFT)
#define EXPLORE_BLOCKS (EXPLORE_BLOCKS_A * EXPLORE_BLOCKS_B)
#define EXPLORE_SEEK_CANDIDATES 4u      /**< the nearest frontier blocks looked at */
#define EXPLORE_MAP_ALONG 12u           /**< rows of the corridor read on the map, at most */
#define EXPLORE_MAP_ACROSS 8u           /**< and columns */
#define EXPLORE_MAP_CELLS 8u            /**< corridor cells read a tick */

/** States of the exploration. */
typedef enum {
    EXPLORE_STOP = 0, /**< stand still (EXPLORE_OFF, or the square is done) */
    EXPLORE_LOOK,     /**< stand still for a sweep, then decide */
    EXPLORE_DECIDE,   /**< TM and walls modes: weigh candidate headings, one a few ticks */
    EXPLORE_TURN,     /**< turn in place to target_heading */
    EXPLORE_FORWARD,  /**< drive straight */
    EXPLORE_BACK,     /**< back off along the trail */
    EXPLORE_FOLLOW,   /**< walls mode: drive along what is on the right */
    EXPLORE_DOOR,     /**< walls mode: measure an opening on the map, back up to it */
    EXPLORE_PASS,     /**< walls mode: drive straight through an opening on the right */
    EXPLORE_SEEK,     /**< walls mode: find the nearest frontier block in sight */
    EXPLORE_FACE,     /**< walls mode: turn in place to face a point (a block, an opening) */
    EXPLORE_HOLD,     /**< the wheels stalled: stand still a while, then back off */
} explore_state_t;

/** What a pass over the obstacle memory found, in the robot's frame (µm from the axle). */
typedef struct {
    int32_t ahead_um;  /**< the nearest point in the corridor ahead; INT32_MAX if none */
    int32_t lateral_um;/**< that point's offset, left positive */
    int32_t right_q10; /**< the squared offset of the nearest point on the right, beside
                            or ahead of the robot (walls mode), in units of (1.024 mm)^2;
                            INT32_MAX if none */
    int32_t behind_q10;/**< the squared distance of the nearest point on the right behind
                            the axle, likewise */
} explore_scan_t;

/** Exploration state. */
typedef struct {
    uint8_t mode;        /**< an explore_mode_t */
    uint8_t state;       /**< an explore_state_t */
    uint8_t stops;       /**< sweep stops */
    uint8_t candidate;   /**< DECIDE: the candidate being weighed */
    uint8_t weighed;     /**< DECIDE: candidates weighed */
    uint8_t best;        /**< DECIDE: the best candidate so far */
    uint8_t ray_phase;   /**< DECIDE: 0 start the candidate's ray, 1 walk and judge it */
    uint8_t laps;        /**< SQUARE: laps to drive; 0 = forever */
    uint8_t first_candidate; /**< DECIDE: where the weighing began */
    uint8_t span;        /**< DECIDE: candidates to weigh from the first one */
    uint8_t pending;     /**< a reading's point waits to enter the memory */
    uint8_t next_point;  /**< memory slot the next point goes to */
    uint8_t scan_next;   /**< the next memory slot the pass checks */
    uint8_t scan_phase;  /**< the slice of the pass the next tick makes */
    uint8_t trail_head;  /**< the newest trail position */
    uint8_t trail_len;   /**< trail positions held */
    uint8_t back_left;   /**< BACK: trail positions still to reach */
    uint8_t lefts;       /**< left turns in a row without getting clear */
    uint8_t after_turn;  /**< the state LOOK hands over to */
    uint8_t echoes;      /**< echoes among the last EXPLORE_ECHO_WINDOW readings */
    uint16_t echo_bits;  /**< those readings, the newest in bit 0: 1 an echo */
    uint32_t leg;        /**< SQUARE: legs done */
    uint32_t best_cost;  /**< DECIDE: its cost */
    uint32_t ray_left;   /**< DECIDE: cells of the ray still to walk */
    uint32_t ray_cost;   /**< DECIDE: visits counted along it so far */
    int32_t ray_fx, ray_fy; /**< DECIDE: where the walk is, Q16 cells */
    int32_t ray_dx, ray_dy; /**< DECIDE: one cell along the candidate, Q16 cells */
    uint32_t rng;        /**< xorshift32 state */
    uint32_t ticks;      /**< ticks in the current state */
    uint32_t now;        /**< ticks since init */
    bam32_t target_heading;    /**< TURN: where to */
    int32_t leg_x_um, leg_y_um; /**< SQUARE: where the current leg began */
    int32_t pending_x_um, pending_y_um; /**< the point of the reading that waits */
    int32_t pt_x_um[EXPLORE_POINTS]; /**< obstacle memory, world µm */
    int32_t pt_y_um[EXPLORE_POINTS];
    uint32_t pt_seen[EXPLORE_POINTS]; /**< `now` when seen; 0 = empty */
    int32_t trail_x_um[EXPLORE_TRAIL]; /**< where the robot was, newest at trail_head */
    int32_t trail_y_um[EXPLORE_TRAIL];
    /* The memory pass under way and the last complete one. */
    q1_30_t scan_cos, scan_sin;  /**< the heading the pass measures against */
    int32_t scan_x_um, scan_y_um;/**< the position it measures from */
    explore_scan_t scan_work;    /**< the pass being made */
    explore_scan_t scan;         /**< the last complete pass */
    uint32_t scan_at;            /**< `now` when that pass began */
    int32_t scan_ox_um, scan_oy_um; /**< and where the robot was then */
    /* The corridor ahead on the map, read with each memory pass. */
    uint8_t map_along, map_across; /**< rows and columns of cell-spaced samples */
    uint8_t map_next;            /**< the next sample the pass reads */
    uint8_t map_hits;            /**< occupied samples the pass has read */
    int32_t map_fx, map_fy;      /**< the left end of the first row, Q16 cells */
    int32_t map_dx, map_dy;      /**< one cell along the heading, Q16 cells */
    int32_t map_x, map_y;        /**< the next sample, Q16 cells */
    uint8_t map_row, map_col;    /**< and its row and column */
    int32_t map_work_um;         /**< the nearest occupied row of the pass under way, from
                                      the axle; INT32_MAX if none */
    int32_t map_um;              /**< that of the last complete pass */
    uint32_t scan_begun;         /**< `now` when the pass under way began */
    uint32_t look_mark;          /**< LOOK: `now` when its sweep was complete; 0 before */
    int32_t target_mm_s[2];      /**< what the last tick asked of the wheels */
    uint32_t look_readings;      /**< LOOK: readings since it began */
    uint32_t heard;              /**< `now` at the last echo of any stop */
    uint32_t deaf_stood;         /**< ticks stood since then for want of an echo */
    uint8_t holds;               /**< HOLD: stalls since the backing off began */
    bool hold_back;              /**< HOLD: back off after it (else look) */
    bool one_wheel;              /**< set by the caller with `stalled`: only one wheel
                                      stalled, the other turning (motion_one_wheel()) */
    bool decide;                 /**< TM: the next LOOK decides a new heading */
    bool trail_due;              /**< walls mode: a trail step waits to be looked at */
    /* Walls mode. */
    uint32_t retrace;            /**< cells entered along the wall that were driven before */
    uint32_t fresh;              /**< cells entered that were not */
    uint32_t lost_um;            /**< driven since the wall on the right was last beside */
    uint32_t arc_ticks;          /**< ticks spent arcing right without anything on the right */
    int32_t front_x_um, front_y_um; /**< the furthest point of the wall on the right */
    int32_t edge_x_um, edge_y_um;   /**< an opening: the wall's last point before it */
    int32_t door_x_um, door_y_um;   /**< and its first point after it; then the middle
                                         of the opening; then where the pass began */
    int32_t walk_fx, walk_fy;    /**< DOOR: where the walk along the wall is, Q16 cells */
    uint8_t walk_n;              /**< DOOR: samples walked */
    uint8_t walk_len;            /**< DOOR: samples to walk */
    uint8_t walk_mid;            /**< DOOR: the sample nearest the opening's middle */
    uint8_t walk_last;           /**< DOOR: the last occupied sample before the middle */
    uint8_t walk_first;          /**< DOOR: the first occupied sample after it */
    uint8_t walk_phase;          /**< DOOR: 0 reading the map, 1 backing up to the middle */
    bool front;                  /**< front_x/y hold a point */
    bool door;                   /**< door_x/y hold an opening */
    bool nudged;                 /**< its middle has been corrected once */
    bool narrow;                 /**< passing an opening: the corridor is the body's */
    /* The frontier at the scale of blocks (explore_seek.c): a bit a block. */
    uint8_t explored[(EXPLORE_BLOCKS + 7u) / 8u]; /**< a known free cell lies in it */
    uint8_t dead[(EXPLORE_BLOCKS + 7u) / 8u];     /**< sought and not reached: given up */
    uint32_t free_scan;          /**< the cell the rolling scan reads next */
    uint16_t cand[EXPLORE_SEEK_CANDIDATES];    /**< SEEK: the nearest frontier blocks */
    uint32_t cand_d2[EXPLORE_SEEK_CANDIDATES]; /**< and their squared distances, cells² */
    uint8_t ncand;               /**< SEEK: candidates found */
    uint8_t cand_i;              /**< SEEK: the one whose line of sight is walked */
    uint8_t seek_rounds;         /**< SEEK: sets of candidates tried */
    uint16_t seek_next;          /**< SEEK: the next block weighed */
    uint16_t seek_a, seek_b;     /**< SEEK: the robot's cell */
    uint16_t target;             /**< the block crossed to; 0xFFFF none */
    bool reached;                /**< the target was reached: seek the next */
    uint32_t target_since;       /**< `now` when it was chosen */
    int32_t target_x_um, target_y_um; /**< its centre */
    int32_t face_x_um, face_y_um; /**< FACE: the point turned to */
    int32_t wall_ux, wall_uy;    /**< DOOR: the wall's direction, a Q16 unit vector */
    /* From the configuration. */
    int32_t cruise_mm_s;
    int32_t turn_mm_s;
    int32_t avoid_um;
    int32_t clearance_um;
    int32_t follow_um;
    int32_t mount_x_um;
    int32_t mount_y_um;
    int32_t square_side_um;
    uint32_t cell_um;
    uint8_t tm_max;
    /* Counters. */
    uint32_t turns;            /**< turns begun */
    uint32_t avoidances;       /**< of which because something was ahead */
    uint32_t stalls;           /**< times the wheels stalled against something */
    uint32_t leaves;           /**< walls mode: walls left for the least visited way */
    uint32_t doors;            /**< walls mode: openings passed */
    uint32_t seeks;            /**< walls mode: frontier blocks crossed to */
} explore_t;

/** Start exploring with a checked configuration; the first act is to look. */
void explore_init(explore_t *e, const slam_config_t *cfg);

/**
 * One tick of exploration. ISR-safe, O(1).
 * @param pose    the pose after this tick's odometry step
 * @param sw      what the sweep did this tick (a completed reading feeds the memory)
 * @param m       the mapper, for the point of the last reading
 * @param g       the maps (read through grid_state() and TM, a few cells a tick)
 * @param held    the nearest obstacle ahead among the sonar's hits that g does not hold yet
 *                (held back by localization: loc_t's tick_ahead), or x = LOC_AHEAD_NONE;
 *                it counts as an occupied cell of g
 * @param stalled the wheels have stalled (motion_stalled())
 * @param target_mm_s  out: target speed of each wheel (ODOM_LEFT, ODOM_RIGHT), mm/s
 */
void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw,
                  const mapper_t *m, const grid_t *g, const int32_t held[2], bool stalled,
                  int32_t target_mm_s[2]);

/**
 * Whether a remembered obstacle lies in the corridor ahead of a pose, closer than
 * avoid_um ahead of the sonar. Checks the whole memory at once: for tests and tools, not
 * for the tick.
 */
bool explore_blocked(const explore_t *e, const odom_pose_t *pose);

#endif /* SLAM_EXPLORE_H */
