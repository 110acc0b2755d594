/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Pose correction: the recent sonar hits, held relative to odometry, matched against OM.
 *
 * The robot's pose is its odometry pose turned and shifted by a correction T:
 *
 *     map = R(T.th) · odom + (T.tx, T.ty),   heading_map = heading_odom + T.th
 *
 * so odometry itself stays the paper's (Eq. 8-12) and only T changes.
 *
 * Work is split between the tick and the background loop. The tick posts every completed
 * reading into the robot's queue (readings.h), O(1); robot_idle() hands them to
 * loc_reading(), reading by reading:
 *
 * - the reading's free-space evidence enters OM at once, at the corrected pose of its ping;
 * - a hit inside the confidence sector is held back, as a point of the odometry frame,
 *   while the next LOC_HOLD hits come in (about a minute of exploring in the shipped
 *   rooms); it enters OM only then, at the correction of that time. So the hits matched
 *   are never part of the map they are matched against, a scan cannot pull the pose
 *   toward itself, and a hit is placed with what the matches of that minute learned about
 *   the pose it was seen from: a drift found when the robot meets a mapped wall again
 *   moves the hits seen on the way there, not only the ones after. Half of its log-odds
 *   step goes in earlier, when it leaves the matched window (below): exploration reads OM
 *   to keep clear of walls the sweep cannot see, and must know the ones just seen. These
 *   early halves lie where the correction of the last match puts their hits (placed);
 *   each match takes them out of OM and puts them back at its result, so that OM holds
 *   them for exploration and never for a match. A save asked for by command, and the end
 *   of a run, move every held-back hit into OM first (loc_flush()); a periodic save
 *   stores OM as it stands, without them;
 * - every LOC_EVERY new hits the window, the newest LOC_WINDOW held-back hits, is
 *   matched against OM without the early halves: against the hits older than the hold,
 *   never those of the last minute, which would hold the pose where they were drawn.
 *   Each hit looks for the nearest occupied cell within LOC_ASSOC_CELLS cells and takes the
 *   wall's direction from the occupied cells around it (the principal axis of a 5×5 block,
 *   used only when they lie along a line). A hit whose wall cell lies more than a cell
 *   beyond it, seen from the robot, with the cell between not known free, is left out (the
 *   far face of a thin wall, first heard through a door). Its distance from that wall line
 *   is one scalar measurement. A sequential Kalman update over the hits, iterated
 *   LOC_PASSES times (associations and residuals taken again at the result), weighs them
 *   against the uncertainty of the correction, a covariance about the robot that grows with
 *   the distance driven and the angle turned since the last match (and carries the
 *   heading's uncertainty into the position across the path). A wall constrains only the
 *   direction across itself, so one wall never slides the pose along it; two walls at an
 *   angle, or a turn, fix the rest. The filter also learns odometry's systematic drift, the
 *   heading it gains per metre driven and per radian turned (what calibration left of E_d
 *   and E_b), and between matches turns the correction by it, so the pose follows the drift
 *   it has learned. A hit stays in the window for LOC_WINDOW / LOC_EVERY matches, so each
 *   counts with LOC_EVERY / LOC_WINDOW of its weight. A match that would move more than
 *   LOC_MAX_STEP_MDEG or LOC_MAX_STEP_UM, or finds fewer than LOC_MIN_POINTS walls, is
 *   refused and changes nothing;
 * - after each reading it publishes T for the tick, and with it the obstacle ahead that
 *   exploration cannot see in OM yet: of the newest LOC_WINDOW held-back hits (none of
 *   them in OM), those within LOC_AHEAD_REACH_UM ahead of the robot at the ping and
 *   clearance_um to either side, in cells OM does not hold free, the nearest in the second
 *   cell (a lone cell is a ghost, as for exploration's corridor on the map).
 *
 * The tick adopts, when it completes a reading, the correction published after the reading
 * before (loc_adopt(), when readq_post() finds that reading finished): every backend then
 * uses the same correction for the same reading, whenever its background loop happens to
 * run, as long as that loop finishes a reading within a reading's time (a match is about
 * 10⁵ instructions; readings are at least 60 ms apart). A tick that finds the loop behind
 * keeps its correction (the queue counts it late). With localization off none of this
 * runs: robot_idle() maps the readings itself, and the pose is odometry's.
 *
 * The files (src/localize/) form layers, each calling only those before it: loc_filter.c
 * (the filter, the correction and the drift it learns), loc_walls.c (wall lines and
 * association in OM), loc_hold.c (the held-back hits, their early halves, entering OM, the
 * obstacle ahead), loc_match.c (a match of the window, its gates and refusals), loc_tick.c
 * (the state set up, and what is published for the tick; the tick's side, loc_adopt() and
 * loc_tick_pose(), is inline below), localize.c (the background loop's entry). loc_t holds
 * one sub-struct per file. The tunables named here but LOC_HOLD are in their headers.
 *
 * Units: positions µm, angles binary (2^32 a turn) in poses and µrad in the covariance.
 */
#ifndef SLAM_LOCALIZE_H
#define SLAM_LOCALIZE_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"
#include "slam/grid.h"
#include "slam/mapper.h"
#include "slam/odometry.h"
#include "slam/readings.h"

#ifndef LOC_HOLD
#define LOC_HOLD 256u /**< hits held back from OM */
#endif
#define LOC_AHEAD_NONE INT32_MIN /**< no held-back hit ahead (loc_tick_t's ahead points) */

/** The correction from the odometry frame to the map's. */
typedef struct {
    int32_t tx_um; /**< translation */
    int32_t ty_um;
    bam32_t th; /**< rotation */
    q1_30_t c;  /**< cos th */
    q1_30_t s;  /**< sin th */
} loc_corr_t;

/** The filter's states: x, y, θ of a correction, and odometry's two drifts. */
#define LOC_STATES 5u

/** The filter's covariance (src/localize/loc_filter.h says its units). */
typedef struct {
    int64_t p[LOC_STATES][LOC_STATES];
} lkf_cov_t;

/** A held-back hit: the obstacle point in the odometry frame, from the grid's origin in
 *  units of 2^point_shift µm (loc_hold_t), so that ±2^15 units reach 512 cells either way, or
 *  twice a longer grid's side: a grid's length beyond any side (1.024 mm for 50 mm cells).
 *  Four bytes, so that LOC_HOLD of them fit the RAM budget. */
typedef struct {
    int16_t x;
    int16_t y;
} loc_point_t;

/** The filter (loc_filter.c): the correction, its covariance about the robot and of the
 *  systematic drift of odometry, κd (prad/mm) and κt (ppb), and their estimates. */
typedef struct {
    lkf_cov_t cov;
    int64_t drift_nrad; /**< learned drift not yet turned into the correction */
    loc_corr_t corr;    /**< the background loop's correction */
    int32_t kappa_prad_per_mm;
    int32_t kappa_ppb;
    odom_pose_t last_odom; /**< odometry pose of the last reading */
    bool have_last;
} loc_filter_t;

/** The held-back hits (loc_hold.c), a ring. */
typedef struct {
    loc_point_t win[LOC_HOLD];
    uint32_t shadowed[LOC_HOLD / 32u]; /**< bit i: win[i] lay just behind a wall: not mapped */
    loc_corr_t placed;                 /**< where the held-back hits' early halves lie */
    int32_t clear_um;                  /**< half the corridor ahead (clearance_um) */
    uint16_t first;
    uint16_t count;
    uint8_t point_shift; /**< a loc_point_t's unit, log2 µm */
} loc_hold_t;

/** Matches (loc_match.c). */
typedef struct {
    lkf_cov_t work;       /**< a match's covariance while it runs (static: the
                               idle loop's stack stays small) */
    uint32_t tried;       /**< matches attempted */
    uint32_t applied;     /**< matches that moved the pose */
    uint32_t refused;     /**< matches refused (too few walls, too large) */
    uint32_t last_points; /**< wall measurements of the last match */
    int16_t last_step[3]; /**< the increment the last match wanted, applied or refused:
                               x, y in 0.1 mm, θ in 10 µrad, saturated (±3.2 m, ±18°, far
                               past the refusal gates). Against the covariance, it says
                               whether the pose is in doubt; int16 fits the padding */
    uint8_t since;        /**< hits added since the last match */
} loc_match_t;

/** What the background loop publishes after each reading and the tick adopts (loc_tick.c):
 *  the correction, and the nearest held-back hit ahead of the robot that OM does not hold
 *  yet, in the map frame ({LOC_AHEAD_NONE, ...} when none). */
typedef struct {
    volatile loc_corr_t pub;
    volatile int32_t pub_ahead[2];
    loc_corr_t corr; /**< the tick's */
    int32_t ahead[2];
} loc_tick_t;

/** Localization state and counters. */
typedef struct {
    bool on; /**< matching enabled (the configuration) */
    loc_tick_t tick;
    loc_filter_t filter;
    loc_hold_t hold;
    loc_match_t match;
} loc_t;

/** Set up for a checked configuration: zero correction, empty window. */
void loc_init(loc_t *l, const slam_config_t *cfg);

/** The map pose of an odometry pose under a correction. ISR-safe, O(1). */
odom_pose_t loc_apply(const loc_corr_t *c, const odom_pose_t *odom);

/** The map pose of an odometry pose under the correction the tick adopted; odometry's own
 *  with localization off. ISR-safe, O(1). */
static inline odom_pose_t loc_tick_pose(const loc_t *l, const odom_pose_t *odom)
{
    return l->on ? loc_apply(&l->tick.corr, odom) : *odom;
}

/** Tick: adopt what the background loop published after the reading before the one just
 *  posted, once readq_post() has found that reading finished (READQ_CURRENT). ISR-safe, O(1);
 *  inline, since the tick has no instructions to spare for a call. */
static inline void loc_adopt(loc_t *l)
{
    l->tick.corr = l->tick.pub;
    l->tick.ahead[0] = l->tick.pub_ahead[0];
    l->tick.ahead[1] = l->tick.pub_ahead[1];
}

/**
 * Background loop, with localization on (off, robot_idle() maps the readings itself, as
 * readq_map() does): one reading, as the file overview says: its
 * free-space evidence, its hit held back, held-back hits entering OM, a match every
 * LOC_EVERY hits, then the correction published. Never from the tick. The mapper counts the
 * reading as mapper_reading() does.
 */
void loc_reading(loc_t *l, mapper_t *m, grid_t *g, const readq_reading_t *rd);

/** Put the window's held-back hits into OM (before a map is exported). Not ISR-safe. */
void loc_flush(loc_t *l, mapper_t *m, grid_t *g);

#endif /* SLAM_LOCALIZE_H */
