/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Exploration (paper §II.E): where to drive next, from the sonar and the maps.
 *
 * The default sweep sees from 50° left to 90° right of straight ahead (the paper's from
 * 25° left to 65° right), so the left flank is blind beyond it: a wall that converges
 * from the left at a small angle is never met at an incidence that echoes. Every mode shares what
 * keeps the robot clear of what it cannot see:
 *
 * - An obstacle memory: the last EXPLORE_POINTS obstacle points the sonar placed inside
 *   the confidence sector, in world coordinates (so they stay right while the robot
 *   turns), forgotten after EXPLORE_MEMORY_TICKS. Something is *ahead* when a point lies
 *   in the corridor the robot's body would sweep: less than clearance to either side of
 *   the centre line. The memory is checked a few points a tick, a whole pass every few
 *   ticks, together with the same corridor on the map.
 * - Speed: the robot slows down as the nearest point ahead comes closer, from cruise at
 *   0.7 m down to a crawl at avoid_um ahead of the sonar, where it stops.
 * - Turns toward the seen side: when something is ahead the robot turns left, so that
 *   the obstacle is on its right, where the sweep keeps seeing it. Turning in place never
 *   touches anything (the body is round about the axle); after every turn the robot
 *   stands still for a full sweep and looks before it drives into what was blind.
 * - Heading choices read the maps through grid_state(): an occupied cell blocks a way.
 * - Deafness: with no echo from any stop for a second the robot stands, up to three
 *   seconds (a stuck echo line or lost pings pass; open space stays silent).
 * - A trail of the last EXPLORE_TRAIL positions, 50 mm apart: wheels that stall
 *   (something unseen touched) make the robot stand a while (HOLD), then back off along
 *   the path that brought it in, whose cells its body has just swept; one wheel stalled
 *   while the other turns (a wheel or an encoder failed, nothing touched) makes it stand
 *   and look instead.
 * - Escapes: the places where the robot made progress (each 0.25 m from the last two, and
 *   from where the last escape began). A robot about to turn 20 s after its last progress,
 *   or in the walls mode boxed in (a full circle of looks, every way blocked), backs out
 *   along the newest of them instead, the way it came (its rear brought round at
 *   the full turning speed), and drops them from the list; with no way in known it
 *   squeezes (the body's corridor ahead until it gets on). Not for a minute after a
 *   wheel stalled alone (its count may have stopped: the places are then wrong).
 *
 * The modes:
 * - EXPLORE_RANDOM, the paper's: drive straight; when something is ahead, stop and turn
 *   away from the side it is on by a random 90°..180°; now and then (and after driving
 *   straight too long) turn by a random angle anyway.
 * - EXPLORE_TM: the same avoidance, but each new heading (at the start, when something is
 *   ahead, and every 6 s of driving) is the one of 12 directions, 30° apart, whose ray
 *   through TM (1 m, stopped by occupied cells) crosses the fewest visits, the smallest
 *   turn among equals: the trajectory map used for online path planning, as the paper
 *   says it can be. A candidate is weighed over a few ticks (about half a second for
 *   all, standing still), so every tick stays small.
 * - EXPLORE_WALLS: TM-guided wall following, which seeks the walls the sonar has not yet
 *   covered. The robot follows whatever it meets with it on its right, at follow_um from
 *   the axle, where the sweep sees it at good incidence and every wall cell passes
 *   through the confidence sector: into concave corners it turns left, around convex ones
 *   and through openings it arcs right. When the way along the wall has been driven
 *   before (TM), it leaves: it weighs the headings to its left as EXPLORE_TM does, drives
 *   straight to whatever it meets next, and follows that.
 * - EXPLORE_SQUARE: square_laps counter-clockwise squares of square_side by odometry
 *   (UMBmark's path), turning in place at the corners, then stop.
 * - EXPLORE_OFF, and EXPLORE_UMBMARK once umbmark.c has done with it: stand still.
 *
 * Work per tick: a tick that completes a sonar reading belongs to the map update, so the
 * exploration only notes it then and takes the reading's point into its memory in the
 * next tick; every check runs in ticks without a reading, in bounded chunks.
 *
 * The output is a target speed for each wheel; motion.h follows it.
 *
 * The sources (firmware/src/explore/) are layers, each calling only the ones below it
 * (tools/check_layers.py checks it): geometry and the state machine (base.h); the
 * sonar's memory, the map's corridor, what is ahead and the wall on the right (sight.h);
 * the moves every mode shares and the weighing of ways (moves.h); the walls mode's
 * frontier and openings (walls.h); one file a mode, mode_<name>.c for each row of
 * explore_modes.h, with five hooks (modes.h); and explore.c, which runs the shared
 * states and hands over to the mode's hooks. explore_t holds one sub-struct a file
 * (explore_types.h).
 */
#ifndef SLAM_EXPLORE_H
#define SLAM_EXPLORE_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/explore_types.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/odometry.h"
#include "slam/sweep.h"

#define EXPLORE_MEMORY_TICKS 500u /**< obstacle points are forgotten after 5 s */
#define EXPLORE_BACK_UM 150000    /**< how far to back off after a stall */

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

/** Exploration state: one sub-struct a source file (explore_types.h). */
typedef struct {
    explore_cfg_t cfg;           /**< from the configuration */
    explore_count_t count;       /**< what it did */
    explore_machine_t machine;   /**< the state and its clock */
    explore_memory_t memory;     /**< the obstacle points, what the sonar heard */
    explore_corridor_t corridor; /**< the corridor ahead on the map */
    explore_ahead_t ahead;       /**< what is ahead and on the right */
    explore_wall_t wall;         /**< the wall on the right */
    explore_moves_t moves;       /**< turning, looking, backing off along the trail
                                      (moves.one_wheel: set by the caller) */
    /* Weighing the ways and seeking a frontier block never run at once (both stand in a
     * state of their own, DECIDE and SEEK, which hands over to the other only after it
     * has ended): they share their work space. */
    union {
        explore_decide_t decide;
        explore_search_t search;
    };
    explore_seek_t seek; /**< the frontier of blocks */
    explore_way_t way;   /**< the way to a frontier out of sight (robot_idle() works it out) */
    explore_door_t door; /**< an opening being measured and passed */
    explore_walls_t walls;
    explore_square_t square;
    explore_tm_t tm;
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
 *                (held back by localization: loc_t's tick.ahead), or x = LOC_AHEAD_NONE;
 *                it counts as an occupied cell of g
 * @param stalled the wheels have stalled (motion_stalled()); e->moves.one_wheel says
 *                whether only one of them did
 * @param target_mm_s  out: target speed of each wheel (ODOM_LEFT, ODOM_RIGHT), mm/s
 */
void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw, const mapper_t *m,
                  const grid_t *g, const int32_t held[2], bool stalled, int32_t target_mm_s[2]);

/** Whether the exploration stands on purpose (EXPLORE_STOP): its mode stands still, the
 *  square is done, or everything reachable has been explored. ISR-safe. */
static inline bool explore_standing(const explore_t *e)
{
    return e->machine.state == EXPLORE_STOP;
}

/** Whether the exploration is done: it has explored every way it could reach, and
 *  stands. ISR-safe. */
static inline bool explore_explored(const explore_t *e)
{
    return e->machine.explored;
}

/**
 * Background loop: a slice of the way the walls mode asked for (to the nearest frontier the
 * robot can reach, when none is in sight), at most a few thousand grid cells read a call.
 * Never from the tick; nothing to do unless a request waits.
 */
void explore_way_work(explore_way_t *w, const grid_t *g);

/**
 * Whether a remembered obstacle lies in the corridor ahead of a pose, closer than
 * avoid_um ahead of the sonar. Checks the whole memory at once: for tests and tools, not
 * for the tick.
 */
bool explore_blocked(const explore_t *e, const odom_pose_t *pose);

#endif /* SLAM_EXPLORE_H */
