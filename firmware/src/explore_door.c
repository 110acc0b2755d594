/* SPDX-License-Identifier: MIT */
/* Walls mode: openings in the wall on the right, found by the sonar, measured on the map
 * and passed straight through their middle. */
#include "explore_internal.h"

#include <stddef.h>



#define EXPLORE_WALL_NEAR_UM 100000   /* a point of the wall on the right is 0.1 m or more */
#define EXPLORE_WALL_FAR_UM 150000    /* and up to 0.15 m beyond the follow distance aside */
#define EXPLORE_WALL_OFF_UM 100000    /* and within 0.1 m of the wall's line */
#define EXPLORE_WALK_BEFORE_UM 300000 /* the wall is read on the map from 0.3 m before */
#define EXPLORE_WALK_AFTER_UM 150000  /* to 0.15 m after the opening's far point */
#define EXPLORE_WALK_SAMPLES 4u       /* wall samples read a tick, three cells each */
#define EXPLORE_DOOR_WIDE_UM 100000   /* free on the map this wide (the cone narrows it) */
#define EXPLORE_PASS_BEYOND_UM 150000 /* an opening is passed until the body is beyond */
#define EXPLORE_PASS_MM_S 100         /* at half the cruise speed */
#define EXPLORE_DOOR_BACK_MM_S 60     /* and backed up to slowly */
#define EXPLORE_DOOR_BACK_MAX_UM 700000 /* but no further than this */
#define EXPLORE_DOOR_ABREAST_UM 5000  /* abreast of the middle within 5 mm */
#define EXPLORE_NUDGE_MIN_UM 30000    /* an edge nearer the middle than this is a wall */
#define EXPLORE_NUDGE_MARGIN_UM 15000 /* a nudge leaves the edge this far out of the way */
#define EXPLORE_DOOR_SKEW_Q16 11380   /* sin 10°: the robot drives along the wall */
#define EXPLORE_DOOR_TRAIL_MM 200     /* over a trail at least this long */
#define EXPLORE_DOOR_ALIGN_Q16 5712   /* sin 5°: backing up turns in place first beyond */
#define EXPLORE_DOOR_STEER_Q16 200    /* and steers 1 mm/s per this much sine within */
#define EXPLORE_WALK_NONE 0xFFu
#define EXPLORE_WALK_BEGIN 2u         /* walk_phase before the walk has begun */

int32_t explore_robot_frame(const explore_t *e, const odom_pose_t *pose, int32_t x_um,
                            int32_t y_um, int32_t *side)
{
    int32_t ox = pose != NULL ? pose->x_um : e->scan_ox_um;
    int32_t oy = pose != NULL ? pose->y_um : e->scan_oy_um;
    int32_t dx = (int32_t)((uint32_t)x_um - (uint32_t)ox);
    int32_t dy = (int32_t)((uint32_t)y_um - (uint32_t)oy);
    if (side != NULL) {
        *side = (int32_t)(((int64_t)dy * e->scan_cos - (int64_t)dx * e->scan_sin) >> 30);
    }
    return (int32_t)(((int64_t)dx * e->scan_cos + (int64_t)dy * e->scan_sin) >> 30);
}

/*
 * A new point while following: is it on the wall to the right, and does it lie further
 * along than the furthest so far by an opening's width? The sweep's right stops find the
 * wall every few centimetres of travel, so a stretch without points is an opening. Its
 * exact edges are read from the map once the robot is past it.
 */
void explore_walls_point(explore_t *e, const odom_pose_t *pose, int32_t x_um, int32_t y_um)
{
    int32_t side;
    int32_t ahead = explore_robot_frame(e, pose, x_um, y_um, &side);
    if (side > -EXPLORE_WALL_NEAR_UM || side < -(e->follow_um + EXPLORE_WALL_FAR_UM) ||
        ahead < 0 || ahead > EXPLORE_DOOR_MAX_UM) {
        return;
    }
    if (e->front) {
        int32_t front_side;
        int32_t front = explore_robot_frame(e, pose, e->front_x_um, e->front_y_um, &front_side);
        int32_t off = side - front_side;
        off = off < 0 ? -off : off;
        if (ahead <= front || off >= EXPLORE_WALL_OFF_UM) {
            return; /* behind the front, or not on the wall's line (a jamb's far corner) */
        }
        if (!e->door && ahead - front >= EXPLORE_DOOR_MIN_UM && ahead - front <= EXPLORE_DOOR_MAX_UM) {
            e->door = true;
            e->edge_x_um = e->front_x_um;
            e->edge_y_um = e->front_y_um;
            e->door_x_um = x_um;
            e->door_y_um = y_um;
            e->nudged = false;
        }
    }
    e->front = true;
    e->front_x_um = x_um;
    e->front_y_um = y_um;
}

/* Along the wall from a point, µm: the projection on its direction. */
static int32_t along_wall(const explore_t *e, int32_t from_x_um, int32_t from_y_um, int32_t x_um,
                          int32_t y_um)
{
    int32_t dx = (int32_t)((uint32_t)x_um - (uint32_t)from_x_um);
    int32_t dy = (int32_t)((uint32_t)y_um - (uint32_t)from_y_um);
    return (int32_t)(((int64_t)dx * e->wall_ux + (int64_t)dy * e->wall_uy) >> 16);
}

/*
 * The walk along the wall, in the direction the robot drives: it must have driven
 * straight along the wall, its last half metre of trail within 10° of its heading, since
 * it backs up along that heading. The walk runs from before the opening's near point to
 * beyond its far one, a cell a sample.
 */
static bool walk_begin(explore_t *e, const grid_t *g)
{
    e->wall_ux = e->scan_cos >> 14; /* Q16 */
    e->wall_uy = e->scan_sin >> 14;
    uint8_t old = (uint8_t)((e->trail_head + EXPLORE_TRAIL - (e->trail_len - 1u)) % EXPLORE_TRAIL);
    int32_t dx = (e->trail_x_um[e->trail_head] - e->trail_x_um[old]) / 1000; /* mm */
    int32_t dy = (e->trail_y_um[e->trail_head] - e->trail_y_um[old]) / 1000;
    uint32_t len = explore_isqrt((uint32_t)(dx * dx + dy * dy));
    int32_t cross = dx * e->wall_uy - dy * e->wall_ux; /* |d| sin(skew), Q16 mm */
    cross = cross < 0 ? -cross : cross;
    if (len < EXPLORE_DOOR_TRAIL_MM || (int64_t)cross > (int64_t)len * EXPLORE_DOOR_SKEW_Q16) {
        return false;
    }
    int32_t near = explore_robot_frame(e, NULL, e->edge_x_um, e->edge_y_um, NULL);
    int32_t far = explore_robot_frame(e, NULL, e->door_x_um, e->door_y_um, NULL);
    if (far - near > EXPLORE_DOOR_MAX_UM) {
        return false;
    }
    int32_t bx = e->edge_x_um - (int32_t)(((int64_t)EXPLORE_WALK_BEFORE_UM * e->wall_ux) >> 16);
    int32_t by = e->edge_y_um - (int32_t)(((int64_t)EXPLORE_WALK_BEFORE_UM * e->wall_uy) >> 16);
    uint32_t n = (uint32_t)(far - near + EXPLORE_WALK_BEFORE_UM + EXPLORE_WALK_AFTER_UM) / e->cell_um;
    uint32_t mid = (uint32_t)((far - near) / 2 + EXPLORE_WALK_BEFORE_UM) / e->cell_um;
    e->walk_fx = explore_q16_cells(bx, g->origin_x_um, g->cell_um, SLAM_GRID_A);
    e->walk_fy = explore_q16_cells(by, g->origin_y_um, g->cell_um, SLAM_GRID_B);
    e->walk_len = (uint8_t)(n < EXPLORE_WALK_NONE ? n : EXPLORE_WALK_NONE - 1u);
    e->walk_mid = (uint8_t)(mid < e->walk_len ? mid : e->walk_len);
    e->walk_n = 0u;
    e->walk_last = EXPLORE_WALK_NONE;
    e->walk_first = EXPLORE_WALK_NONE;
    e->walk_phase = 0u;
    return e->walk_fx >= 0 && e->walk_fy >= 0;
}

static bool occupied_at(const grid_t *g, int32_t fx, int32_t fy)
{
    uint32_t a = (uint32_t)(fx >> 16);
    uint32_t b = (uint32_t)(fy >> 16);
    return fx >= 0 && fy >= 0 && a < SLAM_GRID_A && b < SLAM_GRID_B &&
           grid_state(g, b * SLAM_GRID_A + a) == GRID_OCCUPIED;
}

/*
 * A few samples of the walk: each reads the cell on the wall's line and the cells a cell
 * to either side of it, since the sonar's hits scatter about the line. The occupied cell
 * found is kept by its centre (edge_x/y before the middle, door_x/y after it, in Q16
 * cells): the samples fall anywhere in their cells, the cells' centres do not.
 */
static void walk_samples(explore_t *e, const grid_t *g)
{
    int32_t ux = e->wall_ux; /* a cell along the wall, Q16 cells */
    int32_t uy = e->wall_uy;
    for (uint32_t n = 0; n < EXPLORE_WALK_SAMPLES && e->walk_n < e->walk_len; n++) {
        int32_t fx = e->walk_fx + e->walk_n * ux;
        int32_t fy = e->walk_fy + e->walk_n * uy;
        if (!occupied_at(g, fx, fy)) {
            if (occupied_at(g, fx - uy, fy + ux)) {
                fx -= uy;
                fy += ux;
            } else if (occupied_at(g, fx + uy, fy - ux)) {
                fx += uy;
                fy -= ux;
            } else {
                e->walk_n++;
                continue;
            }
        }
        int32_t cx = (int32_t)(((uint32_t)fx & 0xFFFF0000u) | 0x8000u);
        int32_t cy = (int32_t)(((uint32_t)fy & 0xFFFF0000u) | 0x8000u);
        if (e->walk_n < e->walk_mid) {
            e->walk_last = e->walk_n;
            e->edge_x_um = cx;
            e->edge_y_um = cy;
        } else {
            e->walk_first = e->walk_n;
            e->door_x_um = cx;
            e->door_y_um = cy;
            e->walk_n = e->walk_len; /* the far edge: done */
            return;
        }
        e->walk_n++;
    }
}

static void give_up(explore_t *e)
{
    e->door = false;
    e->lost_um = 0u;
    e->arc_ticks = 0u;
    explore_enter(e, EXPLORE_FOLLOW);
}

/*
 * DOOR: standing, read the wall on the map through the opening; its middle is the middle
 * of the free cells between the last occupied one before and the first after. The cone
 * narrows an opening on the map by the same amount on both sides, so the middle holds.
 * Then back up along the way just driven until abreast of the middle, turn right to face
 * it, look, and pass.
 */
void explore_door_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                       int32_t target_mm_s[2])
{
    if (e->walk_phase == EXPLORE_WALK_BEGIN) {
        if (!walk_begin(e, g)) {
            give_up(e);
        }
        return;
    }
    if (e->walk_phase == 0u) {
        if (e->walk_n < e->walk_len) {
            walk_samples(e, g);
            return;
        }
        uint32_t free_cells = (uint32_t)(e->walk_first - e->walk_last) - 1u;
        if (e->walk_last == EXPLORE_WALK_NONE || e->walk_first == EXPLORE_WALK_NONE ||
            free_cells * e->cell_um < EXPLORE_DOOR_WIDE_UM) {
            give_up(e);
            return;
        }
        /* The middle of the two edge cells' centres, back to the world. */
        int64_t fx = ((int64_t)e->edge_x_um + e->door_x_um) / 2;
        int64_t fy = ((int64_t)e->edge_y_um + e->door_y_um) / 2;
        e->door_x_um = g->origin_x_um + (int32_t)((fx * g->cell_um) >> 16);
        e->door_y_um = g->origin_y_um + (int32_t)((fy * g->cell_um) >> 16);
        e->walk_phase = 1u;
        /* The middle must lie behind on the right, within the stretch just driven
         * straight: backing up goes no further than that. */
        int32_t side;
        int32_t ahead = explore_robot_frame(e, pose, e->door_x_um, e->door_y_um, &side);
        if (ahead < -EXPLORE_DOOR_BACK_MAX_UM || side > -EXPLORE_WALL_NEAR_UM ||
            side < -(e->follow_um + EXPLORE_WALL_FAR_UM)) {
            give_up(e);
            return;
        }
    }
    int32_t ahead = along_wall(e, pose->x_um, pose->y_um, e->door_x_um, e->door_y_um);
    if (ahead < -EXPLORE_DOOR_ABREAST_UM) {
        /* Straight back along the way the robot came, which its body swept: the heading
         * is held to the wall's direction (the turn the robot was in when it stopped may
         * have carried it off), turning in place first when it is far off. */
        int32_t skew = (int32_t)(((int64_t)e->wall_uy * (fix_cos(pose->heading) >> 14) -
                                  (int64_t)e->wall_ux * (fix_sin(pose->heading) >> 14)) >> 16);
        int32_t steer = skew / EXPLORE_DOOR_STEER_Q16;
        int32_t v = -EXPLORE_DOOR_BACK_MM_S;
        if (skew > EXPLORE_DOOR_ALIGN_Q16 || skew < -EXPLORE_DOOR_ALIGN_Q16) {
            v = 0;
            steer = skew > 0 ? EXPLORE_DOOR_BACK_MM_S / 2 : -EXPLORE_DOOR_BACK_MM_S / 2;
        }
        /* A positive skew: the wall's direction is to the left, a counter-clockwise turn. */
        target_mm_s[ODOM_LEFT] = v - steer;
        target_mm_s[ODOM_RIGHT] = v + steer;
        return;
    }
    if (ahead > EXPLORE_DOOR_ABREAST_UM) {
        /* A few centimetres on (after a nudge), looking ahead as ever. */
        if (explore_ahead_um(e, pose) < e->avoid_um) {
            give_up(e);
            return;
        }
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = EXPLORE_DOOR_BACK_MM_S;
        return;
    }
    /* Abreast: face the middle, at right angles to the wall. */
    e->doors++;
    e->narrow = true;
    explore_face(e, e->door_x_um, e->door_y_um, EXPLORE_PASS);
}

/*
 * Facing an opening, its corridor is not clear: one of its edges is nearer the middle
 * than the robot's half corridor, so the middle was misjudged (the map's cells are
 * coarse). Once per opening, the edge's offset tells which way and how far: the middle
 * moves along the wall away from that edge, and the robot turns back along the wall to
 * get abreast of it again. Something right in the middle is a wall: no opening.
 */
bool explore_door_nudge(explore_t *e, const odom_pose_t *pose)
{
    int32_t lat = e->scan.lateral_um;
    int32_t mag = lat < 0 ? -lat : lat;
    if (e->nudged || e->scan.ahead_um == INT32_MAX || mag < EXPLORE_NUDGE_MIN_UM) {
        return false;
    }
    e->nudged = true;
    /* Facing the opening, the robot's left is the way along the wall it came by. */
    int32_t shift = EXPLORE_PASS_CLEAR_UM + EXPLORE_NUDGE_MARGIN_UM - mag;
    shift = lat < 0 ? shift : -shift;
    e->door_x_um += (int32_t)(((int64_t)shift * e->wall_ux) >> 16);
    e->door_y_um += (int32_t)(((int64_t)shift * e->wall_uy) >> 16);
    e->narrow = false;
    explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_DOOR);
    e->walk_phase = 1u;
    return true;
}

/* Through an opening: straight on, in a corridor as narrow as the body allows, until the
 * body is past the wall's line; then a turn to the right, so that the wall just passed
 * is followed on its other side and nothing unseen lies along the way on the left. */
void explore_pass_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    int64_t through = (int64_t)e->follow_um + EXPLORE_PASS_BEYOND_UM;
    if (ahead < e->avoid_um) {
        e->narrow = false;
        e->avoidances++;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    if (explore_dist2(pose, e->door_x_um, e->door_y_um) >= (uint64_t)(through * through)) {
        e->narrow = false;
        explore_turn_by(e, pose, -(int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = EXPLORE_PASS_MM_S;
}
