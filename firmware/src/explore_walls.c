/* SPDX-License-Identifier: MIT */
/* Walls mode: follow what is on the right, leave it for the least visited way once the
 * way along it has been driven before. */
#include "explore_internal.h"

#include <stddef.h>

#define EXPLORE_STEER_UM 2500        /* steer 1 mm/s per 2.5 mm off the follow distance */
#define EXPLORE_STEER_MAX_MM_S 60    /* at most: a 0.2 m radius at cruise */
#define EXPLORE_ARC_MM_S 30          /* with nothing on the right, arc right gently */
#define EXPLORE_LOST_UM 100000u      /* with nothing beside, straight on this far first */
#define EXPLORE_ARC_MAX_TICKS 1500u  /* then about a circle at most */
#define EXPLORE_RETRACE_LEAVE 12u    /* leave after this many trail steps driven before */
#define EXPLORE_LEFTS_MAX 8u         /* left turns in a row before backing off: a circle */

/* Seek the nearest frontier block in sight and cross to it; without one, weigh the ways
 * to the left, 30° to 150° (not straight back: that would put the wall just left on the
 * blind side), and cross to the best one. */
static void leave(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    e->retrace = 0u;
    explore_seek(e, pose, g);
}

void explore_walls_look(explore_t *e, const odom_pose_t *pose, bool blocked)
{
    if (e->after_turn == EXPLORE_PASS) {
        if (!blocked) {
            e->door_x_um = pose->x_um; /* where the pass begins */
            e->door_y_um = pose->y_um;
            explore_enter(e, EXPLORE_PASS);
            return;
        }
        if (explore_door_nudge(e, pose)) {
            return;
        }
        /* Not an opening after all: back to the wall. */
        e->narrow = false;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    if (e->after_turn == EXPLORE_DOOR) {
        explore_enter(e, EXPLORE_DOOR); /* back along the wall, abreast of the middle */
        return;
    }
    if (!blocked) {
        e->lefts = 0u;
        e->lost_um = 0u;
        e->arc_ticks = 0u;
        explore_enter(e, (explore_state_t)e->after_turn);
        return;
    }
    if (++e->lefts > EXPLORE_LEFTS_MAX) {
        e->lefts = 0u;
        e->leaves++;
        explore_decide(e, 1u, 5u, EXPLORE_FORWARD);
        return;
    }
    /* Something is still ahead: turn on to the left and look again. */
    explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(45), (explore_state_t)e->after_turn);
}

void explore_follow_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    if (ahead < e->avoid_um) {
        /* A concave corner, or something in the way: turn left, so that it is on the
         * right, and look. */
        e->avoidances++;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(45), EXPLORE_FOLLOW);
        return;
    }
    if (e->retrace >= EXPLORE_RETRACE_LEAVE && !e->door) {
        leave(e, pose, g); /* (an opening seen on the right is measured first) */
        return;
    }
    if (e->door && explore_robot_frame(e, pose, e->door_x_um, e->door_y_um, NULL) <
                       -EXPLORE_DOOR_PAST_UM) {
        /* Well past an opening on the right: measure it on the map. */
        e->walk_phase = 2u;
        explore_enter(e, EXPLORE_DOOR);
        return;
    }
    int32_t v = explore_speed_mm_s(e, ahead);
    int32_t steer;
    int32_t near = e->scan.right_q10;
    if (near == INT32_MAX) {
        /* Nothing beside: straight on a little first, then round the corner behind at
         * the follow distance. */
        e->lost_um += (uint32_t)v * 10u;
        near = e->lost_um < EXPLORE_LOST_UM ? INT32_MAX - 1 : e->scan.behind_q10;
    } else {
        e->lost_um = 0u;
    }
    if (near == INT32_MAX - 1) {
        steer = 0;
    } else if (near != INT32_MAX) {
        /* (d² - f²) / 2f is d - f near the follow distance, without a square root. */
        e->arc_ticks = 0u;
        int32_t f = e->follow_um / 1024;
        int32_t err_q10 = (near - f * f) / (2 * f);
        int32_t err_um = err_q10 * 1024;
        steer = err_um / EXPLORE_STEER_UM;
        steer = steer > EXPLORE_STEER_MAX_MM_S ? EXPLORE_STEER_MAX_MM_S : steer;
        steer = steer < -EXPLORE_STEER_MAX_MM_S ? -EXPLORE_STEER_MAX_MM_S : steer;
    } else if (++e->arc_ticks < EXPLORE_ARC_MAX_TICKS) {
        steer = EXPLORE_ARC_MM_S; /* round toward the seen side, looking for the wall */
    } else {
        leave(e, pose, g);
        return;
    }
    /* A positive steer turns right: the left wheel faster. */
    target_mm_s[ODOM_LEFT] = v + steer;
    target_mm_s[ODOM_RIGHT] = v - steer;
}

/*
 * Every trail step along a wall: has the way just ahead (two cells on, and the cells
 * around it) been driven before? Many such steps in a row mean the wall is done.
 */
void explore_walls_trail(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    grid_cell_t here;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &here) == 0) {
        explore_seek_here(e, here);
    }
    if (e->state != EXPLORE_FOLLOW) {
        e->retrace = 0u;
        return;
    }
    int32_t on = 2 * (int32_t)e->cell_um;
    grid_cell_t c;
    if (grid_cell_of(g, pose->x_um + fix_mul_q30(on, e->scan_cos),
                     pose->y_um + fix_mul_q30(on, e->scan_sin), &c) != 0 ||
        c.a == 0u || c.b == 0u || c.a + 1u >= SLAM_GRID_A || c.b + 1u >= SLAM_GRID_B) {
        return;
    }
    uint32_t k = grid_index(c);
    const uint8_t *tm = g->tm;
    bool driven = (tm[k - SLAM_GRID_A - 1u] | tm[k - SLAM_GRID_A] | tm[k - SLAM_GRID_A + 1u] |
                   tm[k - 1u] | tm[k] | tm[k + 1u] | tm[k + SLAM_GRID_A - 1u] |
                   tm[k + SLAM_GRID_A] | tm[k + SLAM_GRID_A + 1u]) != 0u;
    e->retrace = driven ? e->retrace + 1u : e->retrace / 2u;
}

/* Crossing: toward the target block, if any; once something comes within the follow
 * distance on the right, follow it. */
void explore_walls_cross(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2])
{
    int32_t f = e->follow_um / 1024;
    if (e->scan.right_q10 < f * f) {
        e->lost_um = 0u;
        e->arc_ticks = 0u;
        explore_enter(e, EXPLORE_FOLLOW);
        return;
    }
    int32_t steer = explore_seek_steer(e, pose, g);
    target_mm_s[ODOM_LEFT] += steer;
    target_mm_s[ODOM_RIGHT] -= steer;
}
