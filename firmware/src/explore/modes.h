/* SPDX-License-Identifier: MIT */
/*
 * The modes, above walls.h: one file a row of explore_modes.h, mode_<name>.c, defining
 * the hooks below for its name. explore.c calls the hooks of the mode in force through
 * switches generated from the rows, and the build takes mode_<name>.c for every row, so
 * a new mode is its file and its row. What each hook is handed:
 *
 * - init(e): once, after every layer has been set up from the configuration: the first
 *   state (LOOK to explore, FORWARD to drive at once, STOP to stand), and the mode's
 *   settings below (machine.blind, memory.right, ahead.spare).
 * - point(e, pose): a tick's job was to take the last reading's point into the memory
 *   (e->memory.pending_x/y_um); the mode may look at it.
 * - job(e, pose, g, held): any other tick without a reading: the background work, one
 *   slice at most, typically explore_pass_slice() while the robot looks or drives.
 * - look(e, pose, blocked): LOOK has heard a sweep standing and a pass is complete;
 *   blocked: something lies within avoid_um ahead. The mode chooses the next state.
 * - ahead(e, pose): FORWARD, something within avoid_um ahead (counted as an avoidance).
 * - way(e, pose, g, target_mm_s): FORWARD, the way is clear; both wheels already at the
 *   speed for what is ahead; the mode may steer, or end the straight.
 * - backed(e, pose): BACK is done (the trail starts again where the robot stands).
 * - step(e, pose, g, target_mm_s): a tick in a state of the mode's own (the walls mode's
 *   FOLLOW, DOOR, PASS, SEEK).
 *
 * The shared states do the rest: LOOK, DECIDE, TURN, FACE, BACK, HOLD (moves.h), STOP,
 * deafness and stalls. A hook a mode never reaches still exists, empty.
 */
#ifndef SLAM_EXPLORE_MODES_HOOKS_H
#define SLAM_EXPLORE_MODES_HOOKS_H

#include "walls.h"

#define EXPLORE_MODE_HOOKS(id, value, name, summary)                                         \
    void explore_##name##_init(explore_t *e);                                                \
    void explore_##name##_point(explore_t *e, const odom_pose_t *pose);                      \
    void explore_##name##_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,        \
                              const int32_t held[2]);                                        \
    void explore_##name##_look(explore_t *e, const odom_pose_t *pose, bool blocked);         \
    void explore_##name##_ahead(explore_t *e, const odom_pose_t *pose);                      \
    void explore_##name##_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,        \
                              int32_t target_mm_s[2]);                                       \
    void explore_##name##_backed(explore_t *e, const odom_pose_t *pose);                     \
    void explore_##name##_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,       \
                               int32_t target_mm_s[2]);
SLAM_EXPLORE_MODES(EXPLORE_MODE_HOOKS)
#undef EXPLORE_MODE_HOOKS

/* The hooks of a mode that stands still: it stays in EXPLORE_STOP, where no hook but init
 * and point is ever called, and point has nothing to do. */
#define EXPLORE_STANDING_MODE(name)                                                          \
    void explore_##name##_init(explore_t *e)                                                 \
    {                                                                                        \
        explore_enter(e, EXPLORE_STOP);                                                      \
    }                                                                                        \
    void explore_##name##_point(explore_t *e, const odom_pose_t *pose)                       \
    {                                                                                        \
        (void)e, (void)pose;                                                                 \
    }                                                                                        \
    void explore_##name##_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,        \
                              const int32_t held[2])                                         \
    {                                                                                        \
        (void)e, (void)pose, (void)g, (void)held;                                            \
    }                                                                                        \
    void explore_##name##_look(explore_t *e, const odom_pose_t *pose, bool blocked)          \
    {                                                                                        \
        (void)e, (void)pose, (void)blocked;                                                  \
    }                                                                                        \
    void explore_##name##_ahead(explore_t *e, const odom_pose_t *pose)                       \
    {                                                                                        \
        (void)e, (void)pose;                                                                 \
    }                                                                                        \
    void explore_##name##_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,        \
                              int32_t target_mm_s[2])                                        \
    {                                                                                        \
        (void)e, (void)pose, (void)g, (void)target_mm_s;                                     \
    }                                                                                        \
    void explore_##name##_backed(explore_t *e, const odom_pose_t *pose)                      \
    {                                                                                        \
        (void)e, (void)pose;                                                                 \
    }                                                                                        \
    void explore_##name##_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,       \
                               int32_t target_mm_s[2])                                       \
    {                                                                                        \
        (void)e, (void)pose, (void)g, (void)target_mm_s;                                     \
    }

#endif /* SLAM_EXPLORE_MODES_HOOKS_H */
