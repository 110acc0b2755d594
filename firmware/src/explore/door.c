/* SPDX-License-Identifier: MIT */
/* Walls mode: an opening in the wall on the right (found by wall.c), measured on the map
 * and passed straight through its middle. */
#include "walls.h"

#define EXPLORE_WALK_BEFORE_UM 300000   /* the wall is read on the map from 0.3 m before */
#define EXPLORE_WALK_AFTER_UM 150000    /* to 0.15 m after the opening's far point */
#define EXPLORE_WALK_SAMPLES 4u         /* wall samples read a tick, three cells each */
#define EXPLORE_WALK_NONE 0xFFu         /* no occupied sample (walk_last, walk_first) */
#define EXPLORE_DOOR_WIDE_UM 100000     /* free on the map this wide (the cone narrows it) */
#define EXPLORE_PASS_BEYOND_UM 150000   /* an opening is passed until the body is beyond */
#define EXPLORE_PASS_MM_S 100           /* at half the cruise speed */
#define EXPLORE_DOOR_BACK_MM_S 60       /* and backed up to slowly */
#define EXPLORE_DOOR_BACK_MAX_UM 700000 /* but no further than this */
#define EXPLORE_DOOR_ABREAST_UM 5000    /* abreast of the middle within 5 mm */
#define EXPLORE_NUDGE_MIN_UM 30000      /* an edge nearer the middle than this is a wall */
#define EXPLORE_NUDGE_MARGIN_UM 15000   /* a nudge leaves the edge this far out of the way */
#define EXPLORE_DOOR_SKEW_Q16 11380     /* sin 10°: the robot drives along the wall */
#define EXPLORE_DOOR_TRAIL_MM 200       /* over a trail at least this long */
#define EXPLORE_DOOR_ALIGN_Q16 5712     /* sin 5°: backing up turns in place first beyond */
#define EXPLORE_DOOR_STEER_Q16 200      /* and steers 1 mm/s per this much sine within */

/* Where DOOR is (door.phase). */
enum {
    EXPLORE_DOOR_READ = 0, /* reading the wall on the map */
    EXPLORE_DOOR_BACK,     /* backing up abreast of the middle */
    EXPLORE_DOOR_BEGIN,    /* the walk along the wall is still to begin */
};

void explore_door_begin(explore_t *e)
{
    e->door.phase = EXPLORE_DOOR_BEGIN;
    e->door.nudged = false;
    explore_enter(e, EXPLORE_DOOR);
}

/* Along the wall from a point, µm: the projection on its direction. */
static int32_t along_wall(const explore_door_t *d, int32_t from_x_um, int32_t from_y_um,
                          int32_t x_um, int32_t y_um)
{
    int32_t dx = (int32_t)((uint32_t)x_um - (uint32_t)from_x_um);
    int32_t dy = (int32_t)((uint32_t)y_um - (uint32_t)from_y_um);
    return (int32_t)(((int64_t)dx * d->ux + (int64_t)dy * d->uy) >> 16);
}

/*
 * The walk along the wall, in the direction the robot drives: it must have driven
 * straight along the wall, its last half metre of trail within 10° of its heading, since
 * it backs up along that heading. The walk runs from before the opening's near point to
 * beyond its far one, a cell a sample.
 */
static bool walk_begin(explore_t *e, const grid_t *g)
{
    explore_door_t *d = &e->door;
    const explore_moves_t *mv = &e->moves;
    d->ux = e->memory.frame.cos >> 14; /* Q16 */
    d->uy = e->memory.frame.sin >> 14;
    uint8_t old =
        (uint8_t)((mv->trail_head + EXPLORE_TRAIL - (mv->trail_len - 1u)) % EXPLORE_TRAIL);
    int32_t dx = (mv->trail_x_um[mv->trail_head] - mv->trail_x_um[old]) / 1000; /* mm */
    int32_t dy = (mv->trail_y_um[mv->trail_head] - mv->trail_y_um[old]) / 1000;
    uint32_t len = explore_isqrt((uint32_t)(dx * dx + dy * dy));
    int32_t cross = dx * d->uy - dy * d->ux; /* |d| sin(skew), Q16 mm */
    cross = cross < 0 ? -cross : cross;
    if (len < EXPLORE_DOOR_TRAIL_MM || (int64_t)cross > (int64_t)len * EXPLORE_DOOR_SKEW_Q16) {
        return false;
    }
    explore_frame_t f = explore_pass_frame(e, NULL);
    int32_t side;
    int32_t near = fix_frame_point(&f, e->wall.edge_x_um, e->wall.edge_y_um, &side);
    int32_t far = fix_frame_point(&f, e->wall.far_x_um, e->wall.far_y_um, &side);
    if (far - near > EXPLORE_DOOR_MAX_UM) {
        return false;
    }
    int32_t bx = e->wall.edge_x_um - (int32_t)(((int64_t)EXPLORE_WALK_BEFORE_UM * d->ux) >> 16);
    int32_t by = e->wall.edge_y_um - (int32_t)(((int64_t)EXPLORE_WALK_BEFORE_UM * d->uy) >> 16);
    uint32_t n =
        (uint32_t)(far - near + EXPLORE_WALK_BEFORE_UM + EXPLORE_WALK_AFTER_UM) / e->cfg.cell_um;
    uint32_t mid = (uint32_t)((far - near) / 2 + EXPLORE_WALK_BEFORE_UM) / e->cfg.cell_um;
    d->walk_fx = explore_q16_cells(bx, g->origin_x_um, g->cell_um, g->a_cells);
    d->walk_fy = explore_q16_cells(by, g->origin_y_um, g->cell_um, g->b_cells);
    d->walk_len = (uint8_t)(n < EXPLORE_WALK_NONE ? n : EXPLORE_WALK_NONE - 1u);
    d->walk_mid = (uint8_t)(mid < d->walk_len ? mid : d->walk_len);
    d->walk_n = 0u;
    d->walk_last = EXPLORE_WALK_NONE;
    d->walk_first = EXPLORE_WALK_NONE;
    d->phase = EXPLORE_DOOR_READ;
    return d->walk_fx >= 0 && d->walk_fy >= 0;
}

static bool occupied_at(const grid_t *g, int32_t fx, int32_t fy)
{
    uint32_t k = explore_cell_q16(g->a_cells, g->b_cells, fx, fy);
    return k != EXPLORE_NO_CELL && grid_state(g, k) == GRID_OCCUPIED;
}

/*
 * A few samples of the walk: each reads the cell on the wall's line and the cells a cell
 * to either side of it, since the sonar's hits scatter about the line. The occupied cell
 * found is kept by its centre (near before the middle, far after it): the samples fall
 * anywhere in their cells, the cells' centres do not.
 */
static void walk_samples(explore_door_t *d, const grid_t *g)
{
    int32_t ux = d->ux; /* a cell along the wall, Q16 cells */
    int32_t uy = d->uy;
    for (uint32_t n = 0; n < EXPLORE_WALK_SAMPLES && d->walk_n < d->walk_len; n++) {
        int32_t fx = d->walk_fx + d->walk_n * ux;
        int32_t fy = d->walk_fy + d->walk_n * uy;
        if (!occupied_at(g, fx, fy)) {
            if (occupied_at(g, fx - uy, fy + ux)) {
                fx -= uy;
                fy += ux;
            } else if (occupied_at(g, fx + uy, fy - ux)) {
                fx += uy;
                fy -= ux;
            } else {
                d->walk_n++;
                continue;
            }
        }
        int32_t cx = (int32_t)(((uint32_t)fx & 0xFFFF0000u) | 0x8000u);
        int32_t cy = (int32_t)(((uint32_t)fy & 0xFFFF0000u) | 0x8000u);
        if (d->walk_n < d->walk_mid) {
            d->walk_last = d->walk_n;
            d->near_fx = cx;
            d->near_fy = cy;
        } else {
            d->walk_first = d->walk_n;
            d->far_fx = cx;
            d->far_fy = cy;
            d->walk_n = d->walk_len; /* the far edge: done */
            return;
        }
        d->walk_n++;
    }
}

static void give_up(explore_t *e)
{
    e->wall.door = false;
    explore_wall_afresh(e);
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
    explore_door_t *d = &e->door;
    if (d->phase == EXPLORE_DOOR_BEGIN) {
        if (!walk_begin(e, g)) {
            give_up(e);
        }
        return;
    }
    if (d->phase == EXPLORE_DOOR_READ) {
        if (d->walk_n < d->walk_len) {
            walk_samples(d, g);
            return;
        }
        uint32_t free_cells = (uint32_t)(d->walk_first - d->walk_last) - 1u;
        if (d->walk_last == EXPLORE_WALK_NONE || d->walk_first == EXPLORE_WALK_NONE ||
            free_cells * e->cfg.cell_um < EXPLORE_DOOR_WIDE_UM) {
            give_up(e);
            return;
        }
        /* The middle of the two edge cells' centres, back to the world. */
        int64_t fx = ((int64_t)d->near_fx + d->far_fx) / 2;
        int64_t fy = ((int64_t)d->near_fy + d->far_fy) / 2;
        d->x_um = g->origin_x_um + (int32_t)((fx * g->cell_um) >> 16);
        d->y_um = g->origin_y_um + (int32_t)((fy * g->cell_um) >> 16);
        d->phase = EXPLORE_DOOR_BACK;
        /* The middle must lie behind on the right, within the stretch just driven
         * straight: backing up goes no further than that. */
        explore_frame_t f = explore_pass_frame(e, pose);
        int32_t side;
        int32_t ahead = fix_frame_point(&f, d->x_um, d->y_um, &side);
        if (ahead < -EXPLORE_DOOR_BACK_MAX_UM || side > -EXPLORE_WALL_NEAR_UM ||
            side < -(e->cfg.follow_um + EXPLORE_WALL_FAR_UM)) {
            give_up(e);
            return;
        }
    }
    int32_t ahead = along_wall(d, pose->x_um, pose->y_um, d->x_um, d->y_um);
    if (ahead < -EXPLORE_DOOR_ABREAST_UM) {
        /* Straight back along the way the robot came, which its body swept: the heading
         * is held to the wall's direction (the turn the robot was in when it stopped may
         * have carried it off), turning in place first when it is far off. */
        int32_t skew = (int32_t)(((int64_t)d->uy * (fix_cos(pose->heading) >> 14) -
                                  (int64_t)d->ux * (fix_sin(pose->heading) >> 14)) >>
                                 16);
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
        if (explore_ahead_um(e, pose) < e->cfg.avoid_um) {
            give_up(e);
            return;
        }
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = EXPLORE_DOOR_BACK_MM_S;
        return;
    }
    /* Abreast: face the middle, at right angles to the wall. */
    e->count.doors++;
    e->memory.narrow = true;
    explore_face(e, d->x_um, d->y_um, EXPLORE_PASS);
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
    explore_door_t *d = &e->door;
    int32_t lat = e->ahead.scan.lateral_um;
    int32_t mag = lat < 0 ? -lat : lat;
    if (d->nudged || e->ahead.scan.ahead_um == INT32_MAX || mag < EXPLORE_NUDGE_MIN_UM) {
        return false;
    }
    d->nudged = true;
    /* Facing the opening, the robot's left is the way along the wall it came by. */
    int32_t shift = EXPLORE_PASS_CLEAR_UM + EXPLORE_NUDGE_MARGIN_UM - mag;
    shift = lat < 0 ? shift : -shift;
    d->x_um += (int32_t)(((int64_t)shift * d->ux) >> 16);
    d->y_um += (int32_t)(((int64_t)shift * d->uy) >> 16);
    e->memory.narrow = false;
    explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_DOOR);
    d->phase = EXPLORE_DOOR_BACK;
    return true;
}

void explore_pass_begin(explore_t *e, const odom_pose_t *pose)
{
    e->door.x_um = pose->x_um;
    e->door.y_um = pose->y_um;
    explore_enter(e, EXPLORE_PASS);
}

/* Through an opening: straight on, in a corridor as narrow as the body allows, until the
 * body is past the wall's line; then a turn to the right, so that the wall just passed
 * is followed on its other side and nothing unseen lies along the way on the left. */
void explore_pass_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    int64_t through = (int64_t)e->cfg.follow_um + EXPLORE_PASS_BEYOND_UM;
    if (ahead < e->cfg.avoid_um) {
        e->memory.narrow = false;
        e->count.avoidances++;
        explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    if (explore_dist2(pose, e->door.x_um, e->door.y_um) >= (uint64_t)(through * through)) {
        e->memory.narrow = false;
        explore_turn_by(e, pose, -(int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
        return;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = EXPLORE_PASS_MM_S;
}
