/* SPDX-License-Identifier: MIT */
/* Exploration's top: explore_init() and explore_step(), which run the shared states and
 * hand over to the mode in force through its hooks (modes.h). */
#include "modes.h"

#include <string.h>

/* A hook of the mode in force: a switch over the rows of explore_modes.h, each case a
 * direct call. (A table of pointers, measured on the MCU, costs the self-test's ticks up
 * to an instruction more and 160 bytes less flash, and hides the tick's stack depth from
 * the build's analysis, stack_depth.py.) EXPLORE_HOOK(name) is the call, defined around
 * each use. */
#define EXPLORE_HOOK_CASE(id, value, name, summary)                                                \
    case id:                                                                                       \
        EXPLORE_HOOK(name);                                                                        \
        break;
#define EXPLORE_DISPATCH(e)                                                                        \
    switch ((e)->cfg.mode) {                                                                       \
        SLAM_EXPLORE_MODES(EXPLORE_HOOK_CASE)                                                      \
    default:                                                                                       \
        break;                                                                                     \
    }

static void mode_init(explore_t *e)
{
#define EXPLORE_HOOK(name) explore_##name##_init(e)
    EXPLORE_DISPATCH(e)
#undef EXPLORE_HOOK
}

static void mode_job(explore_t *e, const odom_pose_t *pose, const grid_t *g, const int32_t held[2])
{
#define EXPLORE_HOOK(name) explore_##name##_job(e, pose, g, held)
    EXPLORE_DISPATCH(e)
#undef EXPLORE_HOOK
}

static void mode_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)
{
#define EXPLORE_HOOK(name) explore_##name##_next(e, pose, why)
    EXPLORE_DISPATCH(e)
#undef EXPLORE_HOOK
}

static void mode_way(explore_t *e, const odom_pose_t *pose, const grid_t *g, int32_t target_mm_s[2])
{
#define EXPLORE_HOOK(name) explore_##name##_way(e, pose, g, target_mm_s)
    EXPLORE_DISPATCH(e)
#undef EXPLORE_HOOK
}

static void mode_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                      int32_t target_mm_s[2])
{
#define EXPLORE_HOOK(name) explore_##name##_step(e, pose, g, target_mm_s)
    EXPLORE_DISPATCH(e)
#undef EXPLORE_HOOK
}

void explore_init(explore_t *e, const slam_config_t *cfg)
{
    memset(e, 0, sizeof *e);
    e->cfg = (explore_cfg_t){
        .cruise_mm_s = cfg->cruise_mm_s,
        .turn_mm_s = cfg->turn_mm_s,
        .avoid_um = (int32_t)cfg->avoid_um,
        .clearance_um = (int32_t)cfg->clearance_um,
        .follow_um = (int32_t)cfg->follow_um,
        .mount_x_um = cfg->mount_x_um,
        .square_side_um = (int32_t)cfg->square_side_um,
        .cell_um = cfg->cell_um,
        .mode = cfg->explore_mode,
        .stops = cfg->sweep_stops,
        .laps = cfg->square_laps,
        .tm_max = cfg->tm_max,
        .grid_a = grid_cells_a(cfg),
        .grid_b = grid_cells_b(cfg),
    };
    e->machine.rng = cfg->explore_seed;
    explore_ahead_init(e);
    explore_corridor_init(e, cfg);
    explore_moves_init(e, cfg);
    mode_init(e);
}

/* The background job of a tick without a reading, one at a time so that no tick carries
 * two: a reading's point into the memory (and, while following a wall, to the wall on
 * the right), else the mode's (a slice of the pass). */
static void job(explore_t *e, const odom_pose_t *pose, const grid_t *g, const int32_t held[2])
{
    if (e->memory.pending != 0u) {
        explore_memory_take(e);
        if (e->machine.state == EXPLORE_FOLLOW) {
            explore_wall_point(e, pose, e->memory.pending_x_um, e->memory.pending_y_um);
        }
        return;
    }
    mode_job(e, pose, g, held);
}

/* FORWARD: the mode's when something is ahead, else on at the speed for it. */
static void forward(explore_t *e, const odom_pose_t *pose, const grid_t *g, int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    if (ahead < e->cfg.avoid_um) {
        e->count.avoidances++;
        mode_next(e, pose, EXPLORE_WHY_AHEAD);
        return;
    }
    int32_t v = explore_speed_mm_s(e, ahead);
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = v;
    mode_way(e, pose, g, target_mm_s);
}

void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw, const mapper_t *m,
                  const grid_t *g, const int32_t held[2], bool stalled, int32_t target_mm_s[2])
{
    e->machine.now++;
    e->machine.ticks++;
    if (sw->reading_ready) {
        /* This tick maps the reading: only note it, and keep the wheels as they were. */
        e->machine.readings++;
        explore_memory_note(e, sw, m);
        target_mm_s[ODOM_LEFT] = e->moves.target_mm_s[ODOM_LEFT];
        target_mm_s[ODOM_RIGHT] = e->moves.target_mm_s[ODOM_RIGHT];
        return;
    }
    job(e, pose, g, held);
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    if (explore_memory_deaf(e)) {
        /* Deaf: stand (the wheels at 0) until an echo comes back, or for long enough. */
    } else if (!stalled || !explore_stall(e, pose)) {
        switch (e->machine.state) {
        case EXPLORE_STOP:
            break;
        case EXPLORE_LOOK:
            if (explore_look_done(e)) {
                bool blocked = explore_ahead_um(e, pose) < e->cfg.avoid_um;
                mode_next(e, pose, blocked ? EXPLORE_WHY_BLOCKED : EXPLORE_WHY_CLEAR);
            }
            break;
        case EXPLORE_DECIDE:
            explore_decide_step(e, pose, g);
            break;
        case EXPLORE_TURN:
            explore_turn_step(e, pose, target_mm_s);
            break;
        case EXPLORE_FORWARD:
            forward(e, pose, g, target_mm_s);
            break;
        case EXPLORE_FACE:
            explore_face_step(e, pose, target_mm_s);
            break;
        case EXPLORE_BACK:
            if (explore_back_step(e, pose, target_mm_s)) {
                mode_next(e, pose, EXPLORE_WHY_BACKED);
            }
            break;
        case EXPLORE_HOLD:
            explore_hold_step(e);
            break;
        default:
            mode_step(e, pose, g, target_mm_s);
            break;
        }
        if (e->machine.state == EXPLORE_FORWARD || e->machine.state == EXPLORE_FOLLOW) {
            explore_trail_step(e, pose);
        }
    }
    e->moves.target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_LEFT];
    e->moves.target_mm_s[ODOM_RIGHT] = target_mm_s[ODOM_RIGHT];
}
