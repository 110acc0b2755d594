/* SPDX-License-Identifier: MIT */
/* EXPLORE_WALLS: follow what is met on the right; pass the openings in it (door.c); once
 * the way along it has been driven before, leave it for the nearest frontier block in
 * sight (seek.c), or for the least visited way to the left (decide.c). */
#include "modes.h"

#define EXPLORE_STEER_UM 2500       /* steer 1 mm/s per 2.5 mm off the follow distance */
#define EXPLORE_STEER_MAX_MM_S 60   /* at most: a 0.2 m radius at cruise */
#define EXPLORE_ARC_MM_S 30         /* with nothing on the right, arc right gently */
#define EXPLORE_LOST_UM 100000u     /* with nothing beside, straight on this far first */
#define EXPLORE_ARC_MAX_TICKS 1500u /* then about a circle at most */
#define EXPLORE_RETRACE_LEAVE 12u   /* leave after this many trail steps driven before */
#define EXPLORE_DOOR_PAST_UM 150000 /* an opening is measured once this far past it */

/* Seek the nearest frontier block in sight and cross to it; without one, weigh the ways
 * to the left and cross to the best one. */
static void leave(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    e->walls.retrace = 0u;
    explore_seek(e, pose, g);
}

/* FOLLOW: along what is on the right, at follow_um from the axle. */
static void follow(explore_t *e, const odom_pose_t *pose, const grid_t *g, int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    if (ahead < e->cfg.avoid_um) {
        /* A concave corner, or something in the way: turn left, so that it is on the
         * right, and look. */
        e->count.avoidances++;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(45), EXPLORE_FOLLOW);
        return;
    }
    if (e->walls.retrace >= EXPLORE_RETRACE_LEAVE && !e->wall.door) {
        leave(e, pose, g); /* (an opening seen on the right is measured first) */
        return;
    }
    if (e->wall.door) {
        explore_frame_t f = explore_pass_frame(e, pose);
        int32_t side;
        if (fix_frame_point(&f, e->wall.far_x_um, e->wall.far_y_um, &side) <
            -EXPLORE_DOOR_PAST_UM) {
            explore_door_begin(e); /* well past an opening on the right: measure it */
            return;
        }
    }
    int32_t v = explore_speed_mm_s(e, ahead);
    int32_t steer;
    int32_t near = e->ahead.scan.right_q10;
    if (near == INT32_MAX) {
        /* Nothing beside: straight on a little first, then round the corner behind at
         * the follow distance. */
        e->wall.lost_um += (uint32_t)v * 10u;
        near = e->wall.lost_um < EXPLORE_LOST_UM ? INT32_MAX - 1 : e->ahead.scan.behind_q10;
    } else {
        e->wall.lost_um = 0u;
    }
    if (near == INT32_MAX - 1) {
        steer = 0;
    } else if (near != INT32_MAX) {
        /* (d² - f²) / 2f is d - f near the follow distance, without a square root. */
        e->wall.arc_ticks = 0u;
        int32_t f = e->cfg.follow_um / 1024;
        int32_t err_q10 = (near - f * f) / (2 * f);
        int32_t err_um = err_q10 * 1024;
        steer = err_um / EXPLORE_STEER_UM;
        steer = steer > EXPLORE_STEER_MAX_MM_S ? EXPLORE_STEER_MAX_MM_S : steer;
        steer = steer < -EXPLORE_STEER_MAX_MM_S ? -EXPLORE_STEER_MAX_MM_S : steer;
    } else if (++e->wall.arc_ticks < EXPLORE_ARC_MAX_TICKS) {
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
 * Every trail step: the robot's block is explored; and along a wall, has the way just
 * ahead (two cells on, and the cells around it) been driven before? Many such steps in a
 * row mean the wall is done.
 */
static void trail_look(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    explore_progress(e, pose);
    grid_cell_t here;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &here) == 0) {
        explore_seek_here(e, here);
    }
    if (e->machine.state != EXPLORE_FOLLOW) {
        e->walls.retrace = 0u;
        return;
    }
    int32_t on = 2 * (int32_t)e->cfg.cell_um;
    grid_cell_t c;
    if (grid_cell_of(g, pose->x_um + fix_mul_q30(on, e->memory.frame.cos),
                     pose->y_um + fix_mul_q30(on, e->memory.frame.sin), &c) != 0 ||
        c.a == 0u || c.b == 0u || c.a + 1u >= g->a_cells || c.b + 1u >= g->b_cells) {
        return;
    }
    uint32_t k = grid_index(g, c);
    const uint32_t row = g->a_cells;
    const uint8_t *tm = g->tm;
    bool driven = (tm[k - row - 1u] | tm[k - row] | tm[k - row + 1u] | tm[k - 1u] | tm[k] |
                   tm[k + 1u] | tm[k + row - 1u] | tm[k + row] | tm[k + row + 1u]) != 0u;
    e->walls.retrace = driven ? e->walls.retrace + 1u : e->walls.retrace / 2u;
}

void explore_walls_init(explore_t *e)
{
    e->memory.right = true;
    e->ahead.spare = true; /* the frontier's rolling scan */
    explore_seek_init(e);
    explore_enter(e, EXPLORE_LOOK);
}

/* A trail step to look at comes first; then the pass, and after each pass a slice of the
 * frontier's rolling scan. */
void explore_walls_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                       const int32_t held[2])
{
    if (e->moves.trail_fresh) {
        e->moves.trail_fresh = false;
        trail_look(e, pose, g);
        return;
    }
    uint8_t s = e->machine.state;
    if ((s == EXPLORE_LOOK || s == EXPLORE_FOLLOW || s == EXPLORE_PASS || s == EXPLORE_FORWARD) &&
        explore_pass_slice(e, pose, g, held)) {
        explore_seek_scan(e, g);
    }
}

/* LOOK is done: go on as the turn or the face before it meant to, unless something is
 * ahead. */
static void looked(explore_t *e, const odom_pose_t *pose, bool blocked)
{
    uint8_t then = e->moves.after_turn;
    if (then == EXPLORE_PASS) {
        if (!blocked) {
            explore_pass_begin(e, pose);
            return;
        }
        if (explore_door_nudge(e, pose)) {
            return;
        }
        /* Not an opening after all: back to the wall. */
        e->memory.narrow = false;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    if (then == EXPLORE_DOOR) {
        explore_enter(e, EXPLORE_DOOR); /* back along the wall, abreast of the middle */
        return;
    }
    if (!blocked) {
        e->walls.lefts = 0u;
        explore_wall_afresh(e);
        explore_enter(e, (explore_state_t)then);
        return;
    }
    if (++e->walls.lefts > EXPLORE_LEFTS_MAX) {
        /* Every way blocked: back out the way it came, else weigh the ways. */
        e->walls.lefts = 0u;
        if (explore_escape_boxed(e, pose)) {
            return;
        }
        e->count.leaves++;
        explore_decide(e, EXPLORE_LEFT_FIRST, EXPLORE_LEFT_SPAN, EXPLORE_FORWARD);
        return;
    }
    /* Something is still ahead: turn on to the left and look again. */
    explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(45), (explore_state_t)then);
}

void explore_walls_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)
{
    switch (why) {
    case EXPLORE_WHY_CLEAR:
    case EXPLORE_WHY_BLOCKED:
        looked(e, pose, why == EXPLORE_WHY_BLOCKED);
        break;
    case EXPLORE_WHY_AHEAD:
    case EXPLORE_WHY_BACKED:
        /* Turn so that what is ahead (or was, before backing off) is on the right, and
         * follow it. */
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        break;
    }
}

/* Crossing: toward the target block, if any; once something comes within the follow
 * distance on the right, follow it. */
void explore_walls_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                       int32_t target_mm_s[2])
{
    int32_t f = e->cfg.follow_um / 1024;
    if (e->ahead.scan.right_q10 < f * f) {
        explore_wall_afresh(e);
        explore_enter(e, EXPLORE_FOLLOW);
        return;
    }
    int32_t steer = explore_seek_steer(e, pose, g);
    target_mm_s[ODOM_LEFT] += steer;
    target_mm_s[ODOM_RIGHT] -= steer;
}

void explore_walls_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        int32_t target_mm_s[2])
{
    switch (e->machine.state) {
    case EXPLORE_FOLLOW:
        follow(e, pose, g, target_mm_s);
        break;
    case EXPLORE_DOOR:
        explore_door_step(e, pose, g, target_mm_s);
        break;
    case EXPLORE_PASS:
        explore_pass_step(e, pose, target_mm_s);
        break;
    case EXPLORE_SEEK:
        explore_seek_step(e, pose, g);
        break;
    default:
        break;
    }
}
