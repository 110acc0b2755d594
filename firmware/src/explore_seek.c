/* SPDX-License-Identifier: MIT */
/* Walls mode: the frontier at the scale of blocks of cells, and crossing to it. */
#include "explore_internal.h"

#include <stddef.h>

#define EXPLORE_FREE_STEPS 8u        /* cells (or skipped blocks) the rolling scan reads a tick */
#define EXPLORE_SEEK_BLOCKS 4u       /* blocks weighed a tick */
#define EXPLORE_SIGHT_CELLS 8u       /* cells of a line of sight walked a tick */
#define EXPLORE_SEEK_REACH_UM 4000000 /* frontier blocks further than 4 m are not sought */
#define EXPLORE_TARGET_TICKS 6000u   /* a block not reached within a minute is given up */
#define EXPLORE_FACE_DONE 32         /* facing a point: within 1/32 rad (1.8°) */
#define EXPLORE_STEER_TARGET_MM_S 20 /* the steer toward a target while crossing */
#define EXPLORE_SEEK_ROUNDS 4u       /* sets of four candidates tried in one search */
#define EXPLORE_NONE 0xFFFFu

static bool bit(const uint8_t *map, uint32_t k)
{
    return (map[k >> 3] & (1u << (k & 7u))) != 0u;
}

static void set_bit(uint8_t *map, uint32_t k)
{
    map[k >> 3] = (uint8_t)(map[k >> 3] | (1u << (k & 7u)));
}

static uint32_t block_of(uint32_t a, uint32_t b)
{
    return (b >> EXPLORE_BLOCK_SHIFT) * EXPLORE_BLOCKS_A + (a >> EXPLORE_BLOCK_SHIFT);
}

void explore_seek_init(explore_t *e)
{
    e->target = EXPLORE_NONE;
}

/* The robot's own block is explored: it stands in it. */
void explore_seek_here(explore_t *e, grid_cell_t here)
{
    uint32_t k = block_of(here.a, here.b);
    set_bit(e->explored, k);
    if (e->target != EXPLORE_NONE && k == e->target) {
        e->target = EXPLORE_NONE; /* reached */
        e->reached = true;
    }
}

/*
 * The rolling scan: a block with a known free cell (grid_state(), which says free where
 * the robot has been, and where beams have passed once OM holds free-space evidence) is
 * explored. A few cells a tick, skipping the rest of a block row once its block is known.
 */
void explore_seek_scan(explore_t *e, const grid_t *g)
{
    uint32_t i = e->free_scan;
    for (uint32_t n = 0; n < EXPLORE_FREE_STEPS; n++) {
        if (i >= SLAM_GRID_CELLS) {
            i = 0u;
        }
        uint32_t a = i % SLAM_GRID_A;
        uint32_t k = block_of(a, i / SLAM_GRID_A);
        if (bit(e->explored, k)) {
            uint32_t next = (a | ((1u << EXPLORE_BLOCK_SHIFT) - 1u)) + 1u; /* next block */
            i += next - a;
            if (next >= SLAM_GRID_A) {
                i -= next - SLAM_GRID_A; /* the row's end: on to the next row */
            }
            continue;
        }
        if (grid_state(g, i) == GRID_FREE) {
            set_bit(e->explored, k);
        }
        i++;
    }
    e->free_scan = i;
}

/* A block's centre, in cells of the grid. */
static void block_centre(uint32_t k, int32_t *a, int32_t *b)
{
    *a = (int32_t)((k % EXPLORE_BLOCKS_A) << EXPLORE_BLOCK_SHIFT) + (1 << (EXPLORE_BLOCK_SHIFT - 1u));
    *b = (int32_t)((k / EXPLORE_BLOCKS_A) << EXPLORE_BLOCK_SHIFT) + (1 << (EXPLORE_BLOCK_SHIFT - 1u));
}

/* An unexplored block, not given up, next to an explored one. */
static bool frontier(const explore_t *e, uint32_t k)
{
    if (bit(e->explored, k) || bit(e->dead, k)) {
        return false;
    }
    uint32_t ba = k % EXPLORE_BLOCKS_A;
    uint32_t bb = k / EXPLORE_BLOCKS_A;
    return (ba > 0u && bit(e->explored, k - 1u)) ||
           (ba + 1u < EXPLORE_BLOCKS_A && bit(e->explored, k + 1u)) ||
           (bb > 0u && bit(e->explored, k - EXPLORE_BLOCKS_A)) ||
           (bb + 1u < EXPLORE_BLOCKS_B && bit(e->explored, k + EXPLORE_BLOCKS_A));
}

/* Begin the line of sight to candidate i: from the robot's cell centre to the block's. */
static void sight_begin(explore_t *e)
{
    int32_t ta;
    int32_t tb;
    block_centre(e->cand[e->cand_i], &ta, &tb);
    int32_t dx = ta - (int32_t)e->seek_a;
    int32_t dy = tb - (int32_t)e->seek_b;
    uint32_t len = explore_isqrt((uint32_t)(dx * dx + dy * dy));
    len = len < 1u ? 1u : len;
    e->ray_fx = ((int32_t)e->seek_a << 16) + 0x8000;
    e->ray_fy = ((int32_t)e->seek_b << 16) + 0x8000;
    e->ray_dx = (int32_t)((dx * 65536) / (int32_t)len);
    e->ray_dy = (int32_t)((dy * 65536) / (int32_t)len);
    e->ray_left = len;
}

/* A few cells of the line of sight; false when an occupied cell blocks it. */
static bool sight_walk(explore_t *e, const grid_t *g)
{
    for (uint32_t n = 0; n < EXPLORE_SIGHT_CELLS && e->ray_left > 0u; n++) {
        e->ray_fx += e->ray_dx;
        e->ray_fy += e->ray_dy;
        e->ray_left--;
        uint32_t a = (uint32_t)(e->ray_fx >> 16);
        uint32_t b = (uint32_t)(e->ray_fy >> 16);
        if (e->ray_fx < 0 || e->ray_fy < 0 || a >= SLAM_GRID_A || b >= SLAM_GRID_B ||
            grid_state(g, b * SLAM_GRID_A + a) == GRID_OCCUPIED) {
            return false;
        }
    }
    return true;
}

/* Begin seeking: stand, and weigh the frontier blocks from the robot's cell. */
void explore_seek(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    grid_cell_t c;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &c) != 0) {
        explore_decide(e, 1u, 5u, EXPLORE_FORWARD);
        return;
    }
    e->seek_a = c.a;
    e->seek_b = c.b;
    e->seek_next = 0u;
    e->ncand = 0u;
    e->cand_i = 0u;
    e->seek_rounds = 0u;
    e->target = EXPLORE_NONE;
    explore_enter(e, EXPLORE_SEEK);
}

/*
 * SEEK, a tick at a time: the nearest frontier blocks within reach (the four nearest are
 * kept), then, nearest first, a straight line to each through the map: the first one no
 * occupied cell hides becomes the target and the robot turns to face it. Without one,
 * the ways to the left are weighed by TM as before.
 */
void explore_seek_step(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    if (e->seek_next < EXPLORE_BLOCKS) {
        uint32_t reach = EXPLORE_SEEK_REACH_UM / e->cell_um;
        for (uint32_t n = 0; n < EXPLORE_SEEK_BLOCKS && e->seek_next < EXPLORE_BLOCKS; n++) {
            uint32_t k = e->seek_next++;
            if (!frontier(e, k)) {
                continue;
            }
            int32_t ta;
            int32_t tb;
            block_centre(k, &ta, &tb);
            int32_t dx = ta - (int32_t)e->seek_a;
            int32_t dy = tb - (int32_t)e->seek_b;
            uint32_t d2 = (uint32_t)(dx * dx + dy * dy);
            if (d2 > reach * reach) {
                continue;
            }
            /* Insert into the nearest four, nearest first. */
            uint8_t at = e->ncand < EXPLORE_SEEK_CANDIDATES ? e->ncand : EXPLORE_SEEK_CANDIDATES;
            while (at > 0u && e->cand_d2[at - 1u] > d2) {
                if (at < EXPLORE_SEEK_CANDIDATES) {
                    e->cand[at] = e->cand[at - 1u];
                    e->cand_d2[at] = e->cand_d2[at - 1u];
                }
                at--;
            }
            if (at < EXPLORE_SEEK_CANDIDATES) {
                e->cand[at] = (uint16_t)k;
                e->cand_d2[at] = d2;
                e->ncand = (uint8_t)(e->ncand < EXPLORE_SEEK_CANDIDATES ? e->ncand + 1u : e->ncand);
            }
        }
        if (e->seek_next >= EXPLORE_BLOCKS && e->ncand > 0u) {
            sight_begin(e);
        }
        return;
    }
    if (e->cand_i < e->ncand) {
        if (!sight_walk(e, g)) {
            /* Out of sight: behind a wall seen, most likely outside the room. It is not
             * sought again; if it lies in a room beyond an opening, the robot explores
             * it by passing the opening. */
            set_bit(e->dead, e->cand[e->cand_i]);
            if (++e->cand_i < e->ncand) {
                sight_begin(e);
            } else if (++e->seek_rounds < EXPLORE_SEEK_ROUNDS) {
                e->seek_next = 0u; /* the next nearest four */
                e->ncand = 0u;
                e->cand_i = 0u;
            }
            return;
        }
        if (e->ray_left > 0u) {
            return;
        }
        /* In sight: the target. */
        uint32_t k = e->cand[e->cand_i];
        int32_t ta;
        int32_t tb;
        block_centre(k, &ta, &tb);
        e->target = (uint16_t)k;
        e->target_since = e->now;
        e->target_x_um = g->origin_x_um + ta * (int32_t)g->cell_um;
        e->target_y_um = g->origin_y_um + tb * (int32_t)g->cell_um;
        e->seeks++;
        explore_face(e, e->target_x_um, e->target_y_um, EXPLORE_FORWARD);
        return;
    }
    (void)pose;
    e->leaves++;
    explore_decide(e, 1u, 5u, EXPLORE_FORWARD);
}

void explore_face(explore_t *e, int32_t x_um, int32_t y_um, explore_state_t then)
{
    e->face_x_um = x_um;
    e->face_y_um = y_um;
    e->after_turn = (uint8_t)then;
    e->turns++;
    explore_enter(e, EXPLORE_FACE);
}

/* FACE: turn in place until the point lies straight ahead, then look. */
void explore_face_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    q1_30_t c = fix_cos(pose->heading);
    q1_30_t s = fix_sin(pose->heading);
    int32_t dx = (int32_t)((uint32_t)e->face_x_um - (uint32_t)pose->x_um);
    int32_t dy = (int32_t)((uint32_t)e->face_y_um - (uint32_t)pose->y_um);
    int32_t ahead = (int32_t)(((int64_t)dx * c + (int64_t)dy * s) >> 30);
    int32_t side = (int32_t)(((int64_t)dy * c - (int64_t)dx * s) >> 30);
    int32_t mag = side < 0 ? -side : side;
    if ((ahead > 0 && mag <= ahead / EXPLORE_FACE_DONE) || e->ticks > 1500u) {
        e->front = false;
        e->door = false;
        explore_enter(e, EXPLORE_LOOK);
        return;
    }
    int32_t speed = e->turn_mm_s;
    if (ahead > 0 && mag < ahead / 3) { /* within about 18°: slow down */
        speed = speed * 3 * (mag >> 8) / ((ahead >> 8) + 1);
        speed = speed < 30 ? 30 : speed;
    }
    int32_t dir = side > 0 || (side == 0 && ahead < 0) ? 1 : -1; /* left is counter-clockwise */
    target_mm_s[ODOM_LEFT] = -dir * speed;
    target_mm_s[ODOM_RIGHT] = dir * speed;
}

/*
 * Crossing toward a target: a gentle steer toward it; a new target once it is reached,
 * behind, or overdue (then it is given up). Returns the steer (positive turns right).
 */
int32_t explore_seek_steer(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    if (e->target == EXPLORE_NONE) {
        if (e->reached) {
            e->reached = false;
            explore_seek(e, pose, g);
        }
        return 0;
    }
    if (e->now - e->target_since > EXPLORE_TARGET_TICKS) {
        set_bit(e->dead, e->target);
        explore_seek(e, pose, g);
        return 0;
    }
    int32_t side;
    int32_t ahead = explore_robot_frame(e, pose, e->target_x_um, e->target_y_um, &side);
    if (ahead <= 0) {
        explore_seek(e, pose, g);
        return 0;
    }
    if (side > ahead / 16) {
        return -EXPLORE_STEER_TARGET_MM_S;
    }
    if (side < -ahead / 16) {
        return EXPLORE_STEER_TARGET_MM_S;
    }
    return 0;
}
