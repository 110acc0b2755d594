/* SPDX-License-Identifier: MIT */
/* The moves every mode shares, above sight.h: turning in place, facing a point, looking,
 * the speed for what is ahead, the trail and backing off along it after a stall
 * (moves.c); and weighing the ways by TM, then turning to the best (decide.c). */
#ifndef SLAM_EXPLORE_MOVES_H
#define SLAM_EXPLORE_MOVES_H

#include "sight.h"

/* ---- moves.c ------------------------------------------------------------------------ */

/* Where the robot starts: its trail, its heading, the state LOOK hands over to. */
void explore_moves_init(explore_t *e, const slam_config_t *cfg);

/* Turn in place by a signed binary angle (left positive), then look and go on in
 * `then`. */
void explore_turn_by(explore_t *e, const odom_pose_t *pose, int32_t angle, explore_state_t then);

/* TURN: toward target_heading; once there, look (a blind mode drives on at once). */
void explore_turn_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);

/* Turn in place to face a world point, then look and go on in `then`. */
void explore_face(explore_t *e, int32_t x_um, int32_t y_um, explore_state_t then);

/* FACE: turn until the point lies straight ahead, then look. */
void explore_face_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);

/* LOOK: true once a full sweep has come in standing still and a pass begun after its
 * last reading is complete: the mode's turn to choose. */
bool explore_look_done(explore_t *e);

/* The forward speed for the nearest point ahead: cruise far from it, slower close to it,
 * and slower when the sonar hears little. */
int32_t explore_speed_mm_s(const explore_t *e, int32_t ahead_um);

#define EXPLORE_TRAIL_STEP_UM 50000 /* one trail position each 50 mm driven */

#define EXPLORE_STUCK_TICKS 2000u /* turning about this long without progress: an escape */
/* A wheel that stalled alone (a count that stopped: motion_one_wheel()) puts the places
 * where the odometry says, not where the body went: no escape for this long after it. */
#define EXPLORE_DOUBT_TICKS 6000u

/* Progress: the robot has come EXPLORE_PROGRESS_UM from the last two places where it made
 * progress, and from where the last escape began; if so, here is the newest. Checked at
 * each turn begun (moves.c) and, in the walls mode, at each trail position (a job of its
 * own tick, not the trail's). */
void explore_progress(explore_t *e, const odom_pose_t *pose);

/* Boxed in (the mode has looked every way and every one is blocked): the escape, at once
 * rather than EXPLORE_STUCK_TICKS after the last progress. True when it has begun (BACK);
 * false when it may not (blind, or a wheel stalled alone lately) or no way in is known (it
 * squeezes then, as an escape does). */
bool explore_escape_boxed(explore_t *e, const odom_pose_t *pose);

/* Driving on: a new trail position each EXPLORE_TRAIL_STEP_UM (trail_fresh tells the
 * mode). Inline: the tick makes it whenever the robot drives. */
static inline void explore_trail_step(explore_t *e, const odom_pose_t *pose)
{
    explore_moves_t *mv = &e->moves;
    uint64_t step = EXPLORE_TRAIL_STEP_UM;
    if (explore_dist2(pose, mv->trail_x_um[mv->trail_head], mv->trail_y_um[mv->trail_head]) <
        step * step) {
        return;
    }
    mv->trail_head = (uint8_t)((mv->trail_head + 1u) % EXPLORE_TRAIL);
    mv->trail_x_um[mv->trail_head] = pose->x_um;
    mv->trail_y_um[mv->trail_head] = pose->y_um;
    mv->trail_len = (uint8_t)(mv->trail_len < EXPLORE_TRAIL ? mv->trail_len + 1u : EXPLORE_TRAIL);
    mv->trail_fresh = true;
}

/* The wheels stalled: what it means in this state. False when nothing is to be done (a
 * blind mode, or a state that stands anyway); else the robot now holds. */
bool explore_stall(explore_t *e, const odom_pose_t *pose);

/* HOLD: stand a while, then back off (or look). */
void explore_hold_step(explore_t *e);

/* BACK: reverse along the trail. True when done (far enough, or given up): the trail
 * starts again where the robot stands, and the mode chooses what next. */
bool explore_back_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);

/* ---- decide.c ----------------------------------------------------------------------- */

#define EXPLORE_CANDIDATES                                                                         \
    12u /* headings weighed, 30° apart; candidate 0 is straight on,                               \
           1 .. 6 to the left */

/* Stand still and weigh candidates first .. first + span - 1 (mod EXPLORE_CANDIDATES),
 * turning then to the best one; the weighing ends in `then`. */
void explore_decide(explore_t *e, uint8_t first, uint8_t span, explore_state_t then);

/* DECIDE: one tick of weighing. */
void explore_decide_step(explore_t *e, const odom_pose_t *pose, const grid_t *g);

#endif /* SLAM_EXPLORE_MOVES_H */
