/* SPDX-License-Identifier: MIT */
/* Walls mode: the frontier at the scale of blocks of cells, and crossing to it. */
#include "walls.h"

#define EXPLORE_FREE_STEPS 8u         /* cells (or skipped blocks) the rolling scan reads a tick */
#define EXPLORE_SEEK_BLOCKS 4u        /* blocks weighed a tick */
#define EXPLORE_SIGHT_CELLS 8u        /* cells of a line of sight walked a tick */
#define EXPLORE_SEEK_REACH_UM 4000000 /* frontier blocks further than 4 m are not sought */
#define EXPLORE_TARGET_TICKS 6000u    /* a block not reached within a minute is given up */
#define EXPLORE_STEER_TARGET_MM_S 20  /* the steer toward a target while crossing */
#define EXPLORE_SEEK_ROUNDS 4u        /* sets of four candidates tried in one search */
#define EXPLORE_NONE 0xFFFFu
#define EXPLORE_WAYPOINT 0xFFFEu       /* the target is a way's point, not a block */
#define EXPLORE_WAY_WAIT_TICKS 500u    /* an answer later than 5 s is not waited for */
#define EXPLORE_WAY_REACHED_UM 200000u /* a way's point this near is reached */
#define EXPLORE_DONE_NONES 2u          /* answers of no way in a row, the first ... */
#define EXPLORE_DONE_TICKS 6000u       /* ... at least a minute before the last: done */
_Static_assert(EXPLORE_BLOCKS < EXPLORE_WAYPOINT, "a block's number is never a way's point");

static uint32_t block_of(const explore_seek_t *s, uint32_t a, uint32_t b)
{
    return (b >> EXPLORE_BLOCK_SHIFT) * s->blocks_a + (a >> EXPLORE_BLOCK_SHIFT);
}

void explore_seek_init(explore_t *e)
{
    e->seek.target = EXPLORE_NONE;
    e->seek.blocks_a = (uint16_t)((e->cfg.grid_a + 15u) >> EXPLORE_BLOCK_SHIFT);
    e->seek.blocks_b = (uint16_t)((e->cfg.grid_b + 15u) >> EXPLORE_BLOCK_SHIFT);
    explore_way_init(&e->way, &e->cfg);
}

void explore_seek_here(explore_t *e, grid_cell_t here)
{
    explore_seek_t *s = &e->seek;
    uint32_t k = block_of(s, here.a, here.b);
    explore_put_bit(s->explored, k, true);
    if (s->target != EXPLORE_NONE && k == s->target) {
        s->target = EXPLORE_NONE; /* reached */
        s->reached = true;
    }
}

/*
 * The rolling scan: a block with a known free cell (grid_state(), which says free where
 * the robot has been, and where beams have passed once OM holds free-space evidence) is
 * explored. A few cells a tick, skipping the rest of a block row once its block is known.
 */
void explore_seek_scan(explore_t *e, const grid_t *g)
{
    explore_seek_t *s = &e->seek;
    uint32_t i = s->free_scan;
    const uint32_t row = g->a_cells;
    const uint32_t cells = grid_cells(g);
    for (uint32_t n = 0; n < EXPLORE_FREE_STEPS; n++) {
        if (i >= cells) {
            i = 0u;
        }
        uint32_t a = i % row;
        uint32_t k = block_of(s, a, i / row);
        if (explore_bit(s->explored, k)) {
            uint32_t next = (a | ((1u << EXPLORE_BLOCK_SHIFT) - 1u)) + 1u; /* next block */
            i += next - a;
            if (next >= row) {
                i -= next - row; /* the row's end: on to the next row */
            }
            continue;
        }
        if (grid_state(g, i) == GRID_FREE) {
            explore_put_bit(s->explored, k, true);
        }
        i++;
    }
    s->free_scan = i;
}

/* A block's centre, in cells of the grid. */
static void block_centre(const explore_seek_t *s, uint32_t k, int32_t *a, int32_t *b)
{
    *a = (int32_t)((k % s->blocks_a) << EXPLORE_BLOCK_SHIFT) + (1 << (EXPLORE_BLOCK_SHIFT - 1u));
    *b = (int32_t)((k / s->blocks_a) << EXPLORE_BLOCK_SHIFT) + (1 << (EXPLORE_BLOCK_SHIFT - 1u));
}

/* The blocks of the run's grid. */
static uint32_t blocks(const explore_seek_t *s)
{
    return (uint32_t)s->blocks_a * s->blocks_b;
}

/* An unexplored block, not given up, next to an explored one. */
static bool frontier(const explore_seek_t *s, uint32_t k)
{
    if (explore_bit(s->explored, k) || explore_bit(s->dead, k)) {
        return false;
    }
    uint32_t ba = k % s->blocks_a;
    uint32_t bb = k / s->blocks_a;
    return (ba > 0u && explore_bit(s->explored, k - 1u)) ||
           (ba + 1u < s->blocks_a && explore_bit(s->explored, k + 1u)) ||
           (bb > 0u && explore_bit(s->explored, k - s->blocks_a)) ||
           (bb + 1u < s->blocks_b && explore_bit(s->explored, k + s->blocks_a));
}

/* Begin the line of sight to candidate i: from the robot's cell centre to the block's. */
static void sight_begin(explore_search_t *r, const explore_seek_t *s)
{
    int32_t ta;
    int32_t tb;
    block_centre(s, r->block[r->i], &ta, &tb);
    r->sight = explore_ray_between(r->a, r->b, (uint32_t)ta, (uint32_t)tb);
}

/* A few cells of the line of sight; false when an occupied cell blocks it. */
static bool sight_walk(explore_search_t *r, const grid_t *g)
{
    const uint32_t na = g->a_cells;
    const uint32_t nb = g->b_cells;
    for (uint32_t n = 0; n < EXPLORE_SIGHT_CELLS && r->sight.left > 0u; n++) {
        uint32_t k = explore_ray_next(&r->sight, na, nb);
        r->sight.left--;
        if (k == EXPLORE_NO_CELL || grid_state(g, k) == GRID_OCCUPIED) {
            return false;
        }
    }
    return true;
}

void explore_seek(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    grid_cell_t c;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &c) != 0) {
        explore_decide(e, EXPLORE_LEFT_FIRST, EXPLORE_LEFT_SPAN, EXPLORE_FORWARD);
        return;
    }
    explore_search_t *r = &e->search;
    r->a = c.a;
    r->b = c.b;
    r->next = 0u;
    r->n = 0u;
    r->i = 0u;
    r->rounds = 0u;
    r->asked = false;
    e->seek.target = EXPLORE_NONE;
    explore_enter(e, EXPLORE_SEEK);
}

/* Weigh a few blocks: the frontier blocks within reach, the four nearest kept. */
static void weigh_blocks(explore_t *e)
{
    explore_search_t *r = &e->search;
    const explore_seek_t *s = &e->seek;
    uint32_t reach = EXPLORE_SEEK_REACH_UM / e->cfg.cell_um;
    for (uint32_t n = 0; n < EXPLORE_SEEK_BLOCKS && r->next < blocks(s); n++) {
        uint32_t k = r->next++;
        if (!frontier(s, k)) {
            continue;
        }
        int32_t ta;
        int32_t tb;
        block_centre(s, k, &ta, &tb);
        int32_t dx = ta - (int32_t)r->a;
        int32_t dy = tb - (int32_t)r->b;
        uint32_t d2 = (uint32_t)(dx * dx + dy * dy);
        if (d2 > reach * reach) {
            continue;
        }
        /* Insert into the nearest four, nearest first. */
        uint8_t at = r->n < EXPLORE_SEEK_CANDIDATES ? r->n : EXPLORE_SEEK_CANDIDATES;
        while (at > 0u && r->d2[at - 1u] > d2) {
            if (at < EXPLORE_SEEK_CANDIDATES) {
                r->block[at] = r->block[at - 1u];
                r->d2[at] = r->d2[at - 1u];
            }
            at--;
        }
        if (at < EXPLORE_SEEK_CANDIDATES) {
            r->block[at] = (uint16_t)k;
            r->d2[at] = d2;
            r->n = (uint8_t)(r->n < EXPLORE_SEEK_CANDIDATES ? r->n + 1u : r->n);
        }
    }
    if (r->next >= blocks(s) && r->n > 0u) {
        sight_begin(r, s);
    }
}

/* Cross to a point: a block's centre or a way's point. */
static void cross_to(explore_t *e, uint32_t target, int32_t x_um, int32_t y_um)
{
    explore_seek_t *s = &e->seek;
    s->target = target;
    s->target_since = e->machine.now;
    s->target_x_um = x_um;
    s->target_y_um = y_um;
    explore_face(e, x_um, y_um, EXPLORE_FORWARD);
}

/*
 * No frontier block in sight: the way to the nearest frontier the robot can reach, which
 * the background loop works out while the robot stands. Without one, the ways to the left
 * are weighed by TM as before; and when there has been none twice, a minute apart, with no
 * way between, the exploration is done: it says so, and stands.
 */
static void way(explore_t *e, const odom_pose_t *pose)
{
    explore_search_t *r = &e->search;
    explore_seek_t *s = &e->seek;
    if (!r->asked) {
        r->asked = true;
        r->asked_at = e->machine.now;
        explore_way_ask(&e->way, pose, e->machine.now);
        return;
    }
    explore_way_result_t res;
    int32_t x_um;
    int32_t y_um;
    if (!explore_way_answer(&e->way, &res, &x_um, &y_um)) {
        if (e->machine.now - r->asked_at < EXPLORE_WAY_WAIT_TICKS) {
            return;
        }
        res = EXPLORE_WAY_PUT_OFF; /* the background loop is late: not a way, nor none */
    }
    if (res == EXPLORE_WAY_TO) {
        s->nones = 0u;
        e->count.ways++;
        cross_to(e, EXPLORE_WAYPOINT, x_um, y_um);
        return;
    }
    if (res != EXPLORE_WAY_NONE) {
        s->nones = 0u;
    } else if (s->nones == 0u) {
        s->none_at = e->machine.now;
        s->nones = 1u;
    } else if (++s->nones >= EXPLORE_DONE_NONES &&
               e->machine.now - s->none_at >= EXPLORE_DONE_TICKS) {
        e->machine.explored = true;
        explore_enter(e, EXPLORE_STOP);
        return;
    }
    e->count.leaves++;
    explore_decide(e, EXPLORE_LEFT_FIRST, EXPLORE_LEFT_SPAN, EXPLORE_FORWARD);
}

/*
 * SEEK, a tick at a time: the nearest frontier blocks within reach (the four nearest are
 * kept), then, nearest first, a straight line to each through the map: the first one no
 * occupied cell hides becomes the target and the robot turns to face it. Without one,
 * the way to a frontier out of sight (way()).
 */
void explore_seek_step(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    explore_search_t *r = &e->search;
    explore_seek_t *s = &e->seek;
    if (r->next < blocks(s)) {
        weigh_blocks(e);
        return;
    }
    if (r->i < r->n) {
        if (!sight_walk(r, g)) {
            /* Out of sight: behind a wall seen, most likely outside the room. It is not
             * sought again; if it lies in a room beyond an opening, the robot explores
             * it by passing the opening. */
            explore_put_bit(s->dead, r->block[r->i], true);
            if (++r->i < r->n) {
                sight_begin(r, s);
            } else if (++r->rounds < EXPLORE_SEEK_ROUNDS) {
                r->next = 0u; /* the next nearest four */
                r->n = 0u;
                r->i = 0u;
            }
            return;
        }
        if (r->sight.left > 0u) {
            return;
        }
        /* In sight: the target. */
        uint32_t k = r->block[r->i];
        int32_t ta;
        int32_t tb;
        block_centre(s, k, &ta, &tb);
        e->count.seeks++;
        cross_to(e, k, g->origin_x_um + ta * (int32_t)g->cell_um,
                 g->origin_y_um + tb * (int32_t)g->cell_um);
        return;
    }
    way(e, pose);
}

/* Whether a way's point is reached: within EXPLORE_WAY_REACHED_UM. The square around it
 * first, in 32 bits: the 64-bit distance only near it (this runs in the tick). */
static bool near_point(const odom_pose_t *pose, int32_t x_um, int32_t y_um)
{
    const uint32_t r = EXPLORE_WAY_REACHED_UM;
    uint32_t dx = (uint32_t)pose->x_um - (uint32_t)x_um + r;
    uint32_t dy = (uint32_t)pose->y_um - (uint32_t)y_um + r;
    return dx < 2u * r && dy < 2u * r && explore_dist2(pose, x_um, y_um) < (uint64_t)r * r;
}

int32_t explore_seek_steer(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    explore_seek_t *s = &e->seek;
    if (s->target == EXPLORE_NONE) {
        if (s->reached) {
            s->reached = false;
            explore_seek(e, pose, g);
        }
        return 0;
    }
    if (s->target == EXPLORE_WAYPOINT) {
        if (near_point(pose, s->target_x_um, s->target_y_um) ||
            e->machine.now - s->target_since > EXPLORE_TARGET_TICKS) {
            s->target = EXPLORE_NONE; /* reached, or overdue: the next search */
            explore_seek(e, pose, g);
            return 0;
        }
    } else if (e->machine.now - s->target_since > EXPLORE_TARGET_TICKS) {
        explore_put_bit(s->dead, s->target, true);
        explore_seek(e, pose, g);
        return 0;
    }
    explore_frame_t f = explore_pass_frame(e, pose);
    int32_t side;
    int32_t ahead = fix_frame_point(&f, s->target_x_um, s->target_y_um, &side);
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
