/* SPDX-License-Identifier: MIT */
/*
 * The modes, above walls.h: one file a row of explore_modes.h, mode_<name>.c, defining
 * the five hooks below for its name. explore.c calls the hooks of the mode in force
 * through switches generated from the rows, and the build takes mode_<name>.c for every
 * row, so a new mode is its file and its row. What each hook is handed:
 *
 * - init(e): once, after every layer has been set up from the configuration: the first
 *   state (LOOK to explore, FORWARD to drive at once, STOP to stand), and the mode's
 *   settings of the layers below (machine.blind, memory.right, ahead.spare).
 * - job(e, pose, g, held): a tick without a reading whose job is not the last reading's
 *   point (explore.c takes that into the memory): the background work, one slice at
 *   most, typically explore_pass_slice() while the robot looks or drives.
 * - next(e, pose, why): a shared state hands over, and the mode chooses the next state
 *   (a turn, a weighing of the ways, FORWARD, LOOK...). Why, an explore_why_t: LOOK has
 *   heard a sweep standing and a pass is complete, with the way ahead clear or blocked;
 *   FORWARD has met something ahead; BACK is done.
 * - way(e, pose, g, target_mm_s): FORWARD, the way is clear, both wheels already at the
 *   speed for what is ahead: the mode may steer, or end the straight.
 * - step(e, pose, g, target_mm_s): a tick in a state of the mode's own (the walls mode's
 *   FOLLOW, DOOR, PASS, SEEK).
 *
 * The shared states do the rest: LOOK, DECIDE, TURN, FACE, BACK, HOLD (moves.h), STOP,
 * deafness and stalls. A hook a mode never reaches still exists, empty.
 */
#ifndef SLAM_EXPLORE_MODES_HOOKS_H
#define SLAM_EXPLORE_MODES_HOOKS_H

#include "walls.h"

/* Why a shared state hands over to the mode (the next hook). */
typedef enum {
    EXPLORE_WHY_CLEAR,   /* LOOK is done: nothing within avoid_um ahead */
    EXPLORE_WHY_BLOCKED, /* LOOK is done: something within avoid_um ahead */
    EXPLORE_WHY_AHEAD,   /* FORWARD: something came within avoid_um (an avoidance) */
    EXPLORE_WHY_BACKED,  /* BACK is done: the trail starts again where the robot stands */
} explore_why_t;

#define EXPLORE_MODE_HOOKS(id, value, name, summary)                                               \
    void explore_##name##_init(explore_t *e);                                                      \
    void explore_##name##_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,              \
                              const int32_t held[2]);                                              \
    void explore_##name##_next(explore_t *e, const odom_pose_t *pose, explore_why_t why);          \
    void explore_##name##_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,              \
                              int32_t target_mm_s[2]);                                             \
    void explore_##name##_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,             \
                               int32_t target_mm_s[2]);
SLAM_EXPLORE_MODES(EXPLORE_MODE_HOOKS)
#undef EXPLORE_MODE_HOOKS

/* The hooks of a mode that stands still: it stays in EXPLORE_STOP, where no hook but init
 * and job is ever called, and job has nothing to do. */
#define EXPLORE_STANDING_MODE(name)                                                                \
    void explore_##name##_init(explore_t *e)                                                       \
    {                                                                                              \
        explore_enter(e, EXPLORE_STOP);                                                            \
    }                                                                                              \
    void explore_##name##_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,              \
                              const int32_t held[2])                                               \
    {                                                                                              \
        (void)e, (void)pose, (void)g, (void)held;                                                  \
    }                                                                                              \
    void explore_##name##_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)           \
    {                                                                                              \
        (void)e, (void)pose, (void)why;                                                            \
    }                                                                                              \
    void explore_##name##_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,              \
                              int32_t target_mm_s[2])                                              \
    {                                                                                              \
        (void)e, (void)pose, (void)g, (void)target_mm_s;                                           \
    }                                                                                              \
    void explore_##name##_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,             \
                               int32_t target_mm_s[2])                                             \
    {                                                                                              \
        (void)e, (void)pose, (void)g, (void)target_mm_s;                                           \
    }

#endif /* SLAM_EXPLORE_MODES_HOOKS_H */
