/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The exploration's state (explore.h's explore_t), one sub-struct a source file of
 * firmware/src/explore/: each file keeps its own, which only the files above it read or
 * set (a file never reaches up). Only explore.h includes this. Outside the exploration only the
 * tests read these fields, and: the counters (host_sim's report; robot_idle.c keeps them across a
 * reconfiguration, as it does the random stream, machine.rng), and moves.one_wheel,
 * which robot.c sets.
 *
 * Units are in the names: world positions in µm (x_um), headings in binary angles,
 * positions on the grid in Q16 cells (16 fraction bits of a cell, fx), times in ticks
 * since explore_init() (`now`).
 */
#ifndef SLAM_EXPLORE_TYPES_H
#define SLAM_EXPLORE_TYPES_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/fixed.h"
#include "slam/grid.h"

#define EXPLORE_POINTS 16u       /**< obstacle points remembered */
#define EXPLORE_TRAIL 8u         /**< trail positions kept */
#define EXPLORE_PROGRESS_KEPT 8u /**< places of progress kept (a ring: a power of two) */
#define EXPLORE_BLOCK_SHIFT 4u   /**< frontier blocks are 16 x 16 cells */
/* The blocks of the capacity, for the bit maps; a run's grid uses the first of them. */
#define EXPLORE_BLOCKS_A ((SLAM_GRID_A + 15u) >> EXPLORE_BLOCK_SHIFT)
#define EXPLORE_BLOCKS_B ((SLAM_GRID_B + 15u) >> EXPLORE_BLOCK_SHIFT)
#define EXPLORE_BLOCKS (EXPLORE_BLOCKS_A * EXPLORE_BLOCKS_B)
_Static_assert(EXPLORE_BLOCKS <= 0xFFFFu, "a block's number fits a uint16_t");
#define EXPLORE_SEEK_CANDIDATES 4u /**< the nearest frontier blocks looked at */
/* The way cells of the capacity (way.c): 5 x 5 grid cells at the least, so that the bit
 * planes of the default 240 x 240 grid take 864 bytes. */
#define EXPLORE_WAY_A ((SLAM_GRID_A + 4u) / 5u)
#define EXPLORE_WAY_B ((SLAM_GRID_B + 4u) / 5u)
#define EXPLORE_WAY_ROW ((EXPLORE_WAY_A + 7u) / 8u) /**< bytes of a row of a bit plane */
#define EXPLORE_WAY_SLOTS 8u                        /**< frontiers put off, kept at once */

/** A frame of the robot: fixed.h's, an origin and a heading by its cosine and sine. */
typedef fix_frame_t explore_frame_t;

/** A walk along a straight line on the grid, a cell a step. */
typedef struct {
    int32_t fx, fy; /**< where the walk is, Q16 cells */
    int32_t dx, dy; /**< one step, Q16 cells */
    uint32_t left;  /**< steps still to walk */
} explore_ray_t;

/** What a pass over the obstacle memory found, in the robot's frame (µm from the axle). */
typedef struct {
    int32_t ahead_um;   /**< the nearest point in the corridor ahead; INT32_MAX if none */
    int32_t lateral_um; /**< that point's offset, left positive */
    int32_t right_q10;  /**< the squared offset of the nearest point on the right, beside
                             or ahead of the robot (walls mode), in units of (1.024 mm)^2;
                             INT32_MAX if none */
    int32_t behind_q10; /**< the squared distance of the nearest point on the right behind
                             the axle, likewise */
} explore_scan_t;

/** From the configuration, at explore_init(). */
typedef struct {
    int32_t cruise_mm_s;
    int32_t turn_mm_s;
    int32_t avoid_um;
    int32_t clearance_um;
    int32_t follow_um;
    int32_t mount_x_um;
    int32_t square_side_um;
    uint32_t cell_um;
    uint8_t mode;  /**< an explore_mode_t */
    uint8_t stops; /**< sweep stops */
    uint8_t laps;  /**< square: laps to drive; 0 = forever */
    uint8_t tm_max;
    uint16_t grid_a; /**< the grid's cells along x (grid_cells_a()) */
    uint16_t grid_b; /**< and along y */
} explore_cfg_t;

/** What the exploration did, counted since the robot started (a reconfiguration keeps it). */
typedef struct {
    uint32_t turns;      /**< turns begun */
    uint32_t avoidances; /**< of which because something was ahead */
    uint32_t stalls;     /**< times the wheels stalled against something */
    uint32_t leaves;     /**< walls mode: walls left for the least visited way */
    uint32_t doors;      /**< walls mode: openings passed */
    uint32_t seeks;      /**< walls mode: frontier blocks crossed to */
    uint32_t escapes;    /**< places backed out of for want of progress */
    uint32_t ways;       /**< walls mode: ways taken to a frontier out of sight */
} explore_count_t;

/** machine.c: the state, its clock and the random stream. */
typedef struct {
    uint32_t now;      /**< ticks since init */
    uint32_t ticks;    /**< ticks in the current state */
    uint32_t rng;      /**< xorshift32 state */
    uint16_t readings; /**< readings since the current state began (LOOK reads it, a
                            sweep's worth in) */
    uint8_t state;     /**< an explore_state_t */
    bool blind;        /**< the mode drives by odometry alone (the square): it does not look
                            after a turn, and neither deafness nor a stall stops it */
    bool explored;     /**< every way it could reach has been explored: it stands (STOP) */
} explore_machine_t;

/** memory.c: what the sonar heard, the obstacle points, and the pass over them. */
typedef struct {
    int32_t pt_x_um[EXPLORE_POINTS]; /**< obstacle points, world */
    int32_t pt_y_um[EXPLORE_POINTS];
    uint32_t pt_seen[EXPLORE_POINTS];   /**< `now` when seen; 0 = empty */
    int32_t pending_x_um, pending_y_um; /**< the point of the reading that waits */
    explore_frame_t frame;              /**< the pass: from where, facing which way */
    explore_scan_t work;                /**< what it has found so far */
    uint32_t heard;                     /**< `now` at the last echo of any stop */
    uint32_t deaf_stood;                /**< ticks stood since then for want of an echo */
    uint16_t echo_bits;                 /**< the last readings, the newest in bit 0: 1 an echo */
    uint8_t echoes;                     /**< echoes among them */
    uint8_t next_point;                 /**< the slot the next point goes to */
    uint8_t next;                       /**< the next slot the pass checks */
    uint8_t pending;                    /**< a reading's point waits to enter the memory */
    bool narrow;                        /**< the corridor checked is the body's alone (set while
                                             passing an opening) */
    bool right;                         /**< the pass measures what is on the right (walls mode) */
} explore_memory_t;

/** corridor.c: the corridor ahead on the map, read a few cells a tick. */
typedef struct {
    int32_t fx, fy;   /**< the left end of the first row, Q16 cells */
    int32_t dx, dy;   /**< one cell along the heading, Q16 cells */
    int32_t x, y;     /**< the next sample, Q16 cells */
    int32_t work_um;  /**< the nearest occupied row so far, from the axle; INT32_MAX none */
    uint8_t along;    /**< rows of cell-spaced samples */
    uint8_t across;   /**< and columns */
    uint8_t next;     /**< the next sample read */
    uint8_t hits;     /**< occupied samples read */
    uint8_t row, col; /**< the next sample's row and column */
} explore_corridor_t;

/** ahead.c: the pass over the memory and the corridor, and its last complete result. */
typedef struct {
    explore_scan_t scan;  /**< the memory, as of the last complete pass */
    int32_t map_um;       /**< the map's nearest occupied row ahead (or the held-back
                               obstacle), from the axle; INT32_MAX if none */
    int32_t ox_um, oy_um; /**< where the robot was when that pass began */
    uint32_t at;          /**< `now` when it began */
    uint32_t begun;       /**< `now` when the pass under way began */
    uint8_t phase;        /**< the slice of the pass the next tick makes */
    bool spare;           /**< each pass ends with a slice for the mode (walls mode) */
} explore_ahead_t;

/** wall.c: the wall on the right while following it. */
typedef struct {
    int32_t front_x_um, front_y_um; /**< its furthest point */
    int32_t edge_x_um, edge_y_um;   /**< an opening: the wall's last point before it */
    int32_t far_x_um, far_y_um;     /**< and its first point after it */
    uint32_t lost_um;               /**< driven since the wall was last beside */
    uint16_t arc_ticks;             /**< ticks spent arcing right without it (up to a circle's) */
    bool front;                     /**< front_x/y hold a point */
    bool door;                      /**< edge and far hold an opening */
} explore_wall_t;

/** moves.c: turning, facing, looking, the trail and backing off along it. */
typedef struct {
    int32_t trail_x_um[EXPLORE_TRAIL]; /**< where the robot was, newest at trail_head */
    int32_t trail_y_um[EXPLORE_TRAIL];
    int32_t target_mm_s[2];       /**< what the last tick asked of the wheels */
    bam32_t target_heading;       /**< TURN: where to */
    int32_t face_x_um, face_y_um; /**< FACE: the point turned to */
    int32_t leg_x_um, leg_y_um;   /**< where the last turn ended, or the stall that backing
                                       off began from */
    uint32_t look_mark;           /**< LOOK: `now` when its sweep was complete; 0 before */
    int32_t prog_x_um[EXPLORE_PROGRESS_KEPT]; /**< where the robot made progress, a ring
                                                   (moves.c's explore_progress()) */
    int32_t prog_y_um[EXPLORE_PROGRESS_KEPT];
    int32_t stuck_x_um; /**< where the last escape began: no progress near it */
    int32_t stuck_y_um;
    uint32_t prog_at;    /**< `now` when it came to the newest of them */
    uint32_t trust_from; /**< `now` from which escapes trust the places (a wheel's count
                              that stopped puts them wrong) */
    uint8_t prog_head;   /**< the newest place's slot */
    uint8_t prog_n;      /**< places held (1 .. EXPLORE_PROGRESS_KEPT) */
    uint8_t after_turn;  /**< the state LOOK hands over to */
    uint8_t trail_head;  /**< the newest trail position */
    uint8_t trail_len;   /**< trail positions held */
    uint8_t back_left;   /**< BACK: trail positions still to reach */
    uint8_t holds;       /**< HOLD: stalls since the backing off began */
    bool hold_back;      /**< HOLD: back off after it (else look) */
    bool escaping;       /**< BACK: out of a place without progress, along the
                              places of progress (prog_x/y) */
    bool squeezing;      /**< no way in known: the body's corridor ahead until progress */
    bool trail_fresh;    /**< a trail position was added: the walls mode looks at it */
    bool one_wheel;      /**< set by the caller with `stalled`: only one wheel stalled,
                              the other turning (motion_one_wheel()) */
} explore_moves_t;

/** decide.c: the weighing of candidate headings under way (DECIDE). */
typedef struct {
    explore_ray_t ray;  /**< the candidate's ray */
    uint32_t ray_cost;  /**< visits counted along it so far */
    uint32_t best_cost; /**< the best candidate's cost */
    uint8_t candidate;  /**< the candidate being weighed */
    uint8_t weighed;    /**< candidates weighed */
    uint8_t best;       /**< the best candidate so far */
    uint8_t phase;      /**< 0 start the candidate's ray, 1 walk and judge it */
    uint8_t first;      /**< where the weighing began */
    uint8_t span;       /**< candidates to weigh from the first one */
    uint8_t then;       /**< the state the weighing ends in */
} explore_decide_t;

/** seek.c: the search for a frontier block under way (SEEK). */
typedef struct {
    explore_ray_t sight;                     /**< the line of sight being walked */
    uint32_t d2[EXPLORE_SEEK_CANDIDATES];    /**< the candidates' squared distances, cells² */
    uint16_t block[EXPLORE_SEEK_CANDIDATES]; /**< the nearest frontier blocks */
    uint16_t next;                           /**< the next block weighed */
    uint16_t a, b;                           /**< the robot's cell */
    uint8_t n;                               /**< candidates found */
    uint8_t i;                               /**< the one whose line of sight is walked */
    uint8_t rounds;                          /**< sets of candidates tried */
    bool asked;                              /**< a way was asked for (way.c) */
    uint32_t asked_at;                       /**< `now` then */
} explore_search_t;

/** What the background loop answered to a request for a way (way.c). */
typedef enum {
    EXPLORE_WAY_NONE = 0, /**< no frontier can be reached: the exploration may be done */
    EXPLORE_WAY_TO,       /**< the robot sees the way's point to go to (x_um, y_um) */
    EXPLORE_WAY_PUT_OFF,  /**< none now, but frontiers not reached lately are put off */
} explore_way_result_t;

/**
 * way.c: the way to the nearest frontier the robot can reach, worked out by robot_idle()
 * over way cells (k x k grid cells, about EXPLORE_WAY_CELL_UM a side): a breadth-first
 * search whose distances are kept modulo 3 in two bit planes (the way back needs no more),
 * grown a wave at a time with whole rows of bits. The tick asks (asked, ask_*) and reads
 * the answer once `answered` equals `asked`; the background loop writes `answered` last.
 */
typedef struct {
    volatile uint16_t asked;             /**< requests the tick posted */
    volatile uint16_t answered;          /**< the last request answered */
    volatile int32_t ask_x_um, ask_y_um; /**< where the robot stood, set before `asked` */
    volatile uint32_t ask_now;           /**< and when (`now`) */
    volatile int32_t x_um, y_um;         /**< the answer: the point to go to */
    volatile uint8_t result;             /**< an explore_way_result_t */
    /* The background loop's side. */
    uint8_t phase;                      /**< way.c's phases */
    uint8_t k;                          /**< grid cells a way cell's side */
    bool put_off;                       /**< the search skipped a frontier put off */
    uint16_t na, nb;                    /**< way cells of the run's grid, a side */
    uint16_t serving;                   /**< the request being worked on */
    uint16_t wave;                      /**< the distance of the cells the search grows from */
    uint16_t row;                       /**< the row of the wave under way */
    uint16_t lo, hi;                    /**< the rows the last wave reached */
    uint16_t next_lo, next_hi;          /**< and those this one reaches (lo > hi: none yet) */
    uint32_t at;                        /**< the frontier found, then the way back to the robot */
    uint16_t at_d;                      /**< its distance from the robot, in way cells */
    uint32_t last;                      /**< the frontier last answered */
    uint32_t off[EXPLORE_WAY_SLOTS];    /**< frontiers put off (way cell + 1; 0 none) */
    uint32_t off_at[EXPLORE_WAY_SLOTS]; /**< `now` of the request that put it off */
    uint8_t off_n[EXPLORE_WAY_SLOTS];   /**< times put off */
    uint8_t off_next;                   /**< the ring's next slot */
    uint8_t label[2][EXPLORE_WAY_B][EXPLORE_WAY_ROW]; /**< distance mod 3 + 1; 0 not reached */
    uint8_t dead[EXPLORE_WAY_B][EXPLORE_WAY_ROW];     /**< frontiers given up */
} explore_way_t;

/** seek.c: the frontier at the scale of blocks (a bit a block), and the block crossed to. */
typedef struct {
    int32_t target_x_um, target_y_um;             /**< its centre */
    uint32_t target_since;                        /**< `now` when it was chosen */
    uint32_t free_scan;                           /**< the cell the rolling scan reads next */
    uint32_t target;                              /**< the block crossed to; 0xFFFF none */
    uint16_t blocks_a, blocks_b;                  /**< the run's grid in blocks, per side */
    uint8_t explored[(EXPLORE_BLOCKS + 7u) / 8u]; /**< a known free cell lies in it */
    uint8_t dead[(EXPLORE_BLOCKS + 7u) / 8u];     /**< sought and not reached: given up */
    bool reached;                                 /**< the target was reached: seek the next */
    uint8_t nones;                                /**< ways answered none in a row */
    uint32_t none_at;                             /**< `now` at the first of them */
} explore_seek_t;

/** door.c: an opening in the wall on the right, measured on the map and passed. */
typedef struct {
    int32_t walk_fx, walk_fy; /**< where the walk along the wall began, Q16 cells */
    int32_t ux, uy;           /**< the wall's direction, a Q16 unit vector */
    int32_t near_fx, near_fy; /**< the last occupied cell before the middle, its centre in
                                   Q16 cells */
    int32_t far_fx, far_fy;   /**< the first one after it */
    int32_t x_um, y_um;       /**< the opening's middle; then where the pass began */
    uint8_t walk_n;           /**< samples walked */
    uint8_t walk_len;         /**< samples to walk */
    uint8_t walk_mid;         /**< the sample nearest the opening's middle */
    uint8_t walk_last;        /**< the last occupied sample before the middle */
    uint8_t walk_first;       /**< the first occupied sample after it */
    uint8_t phase;            /**< where DOOR is (door.c) */
    bool nudged;              /**< the middle has been corrected once */
} explore_door_t;

/** mode_walls.c. */
typedef struct {
    uint32_t retrace; /**< trail steps along the wall into cells driven before, halved
                           at each step into cells that were not */
    uint8_t lefts;    /**< left turns in a row without getting clear */
} explore_walls_t;

/** mode_tm.c. */
typedef struct {
    bool fresh; /**< the next LOOK weighs every way (at the start, after backing off) */
} explore_tm_t;

/** mode_square.c. */
typedef struct {
    uint16_t legs; /**< legs done (up to 4 x 255 counted: a square of laps 0 never ends) */
} explore_square_t;

#endif /* SLAM_EXPLORE_TYPES_H */
