/* SPDX-License-Identifier: MIT */
/* Progress, and leaving a place where there is none: a robot that has not come
 * EXPLORE_PROGRESS_UM from where it last did for a while, or stalled there again and
 * again, marks the place blocked and backs out the way it came. */
#include "moves.h"

#define EXPLORE_PROGRESS_UM 200000   /* progress: this far from where the last was made */
#define EXPLORE_STUCK_TICKS 1500u    /* without it this long, not standing on purpose: stuck */
#define EXPLORE_STALLS_STUCK 3u      /* or this many stalls without it */
#define EXPLORE_ESCAPE_BACK_UM 400000 /* backing out of it goes this far at most */
#define EXPLORE_ESCAPE_TRAIL 4u      /* a trail this long at least (0.15 m) to back out along */
#define EXPLORE_ESCAPE_DRIVE_UM 400000 /* without one, out this far along the way chosen */
#define EXPLORE_ESCAPE_MM_S 100      /* at half the cruise speed */
#define EXPLORE_ESCAPE_TICKS 800u    /* and for 8 s at most */

void explore_escape_init(explore_t *e, const slam_config_t *cfg)
{
    e->escape.x_um = e->escape.was_x_um = cfg->start_x_um;
    e->escape.y_um = e->escape.was_y_um = cfg->start_y_um;
}

/*
 * Progress is coming EXPLORE_PROGRESS_UM from where the last was made, and from where the
 * one before it was: a robot that goes to and fro between two places (along a short wall,
 * turning back at each end) makes none.
 */
bool explore_stuck(explore_t *e, const odom_pose_t *pose)
{
    explore_escape_t *s = &e->escape;
    uint64_t p2 = (uint64_t)EXPLORE_PROGRESS_UM * EXPLORE_PROGRESS_UM;
    if (e->machine.state == EXPLORE_STOP || e->machine.state == EXPLORE_ESCAPE ||
        e->moves.escaping ||
        (explore_dist2(pose, s->x_um, s->y_um) >= p2 &&
         explore_dist2(pose, s->was_x_um, s->was_y_um) >= p2)) {
        /* Progress, a stand on purpose, or an escape under way: the clock starts again
         * from here. */
        s->was_x_um = s->x_um;
        s->was_y_um = s->y_um;
        s->x_um = pose->x_um;
        s->y_um = pose->y_um;
        s->at = e->machine.now;
        s->stalls = 0u;
        return false;
    }
    return e->machine.now - s->at > EXPLORE_STUCK_TICKS || s->stalls >= EXPLORE_STALLS_STUCK;
}

void explore_escape(explore_t *e, const odom_pose_t *pose)
{
    explore_escape_t *s = &e->escape;
    explore_moves_t *mv = &e->moves;
    e->count.escapes++;
    explore_memory_block(e, pose->x_um, pose->y_um);
    s->at = e->machine.now;
    s->stalls = 0u;
    e->memory.narrow = false;
    e->wall.door = false;
    mv->leg_x_um = pose->x_um;
    mv->leg_y_um = pose->y_um;
    if (mv->trail_len >= EXPLORE_ESCAPE_TRAIL) {
        /* Back out along the trail: the body swept it coming in. */
        mv->back_left = mv->trail_len;
        mv->back_um = EXPLORE_ESCAPE_BACK_UM;
        mv->holds = 0u;
        mv->escaping = true;
        explore_enter(e, EXPLORE_BACK);
        return;
    }
    /* No trail: out along the way the robot's body has been through before, looking
     * in the body's own corridor (the wider one is what holds it). */
    e->memory.narrow = true;
    explore_decide_visited(e, EXPLORE_ESCAPE);
}

bool explore_escape_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int64_t out = EXPLORE_ESCAPE_DRIVE_UM;
    e->memory.narrow = true;
    if (explore_dist2(pose, e->moves.leg_x_um, e->moves.leg_y_um) >= (uint64_t)(out * out) ||
        explore_ahead_um(e, pose) < e->cfg.avoid_um || e->machine.ticks > EXPLORE_ESCAPE_TICKS) {
        e->memory.narrow = false;
        return true;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = EXPLORE_ESCAPE_MM_S;
    return false;
}
