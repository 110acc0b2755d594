/* SPDX-License-Identifier: MIT */
/* The TM-guided choice of a heading: candidate rays through the maps, weighed a few cells
 * and memory points a tick, then a turn to the best. */
#include "moves.h"

#define EXPLORE_LOOK_UM 1000000 /* rays reach 1 m */
#define EXPLORE_RAY_CELLS 8u    /* cells of a ray walked a tick, at most */
#define EXPLORE_CANDIDATE_BAM ((bam32_t)(0x100000000ull / EXPLORE_CANDIDATES))

void explore_decide(explore_t *e, uint8_t first, uint8_t span, explore_state_t then)
{
    explore_decide_t *d = &e->decide;
    d->first = first;
    d->span = span;
    d->then = (uint8_t)then;
    /* Candidates are weighed from a random first one, so ties between equal turns go a
     * random way. */
    d->candidate = (uint8_t)((first + explore_rng_below(e, span)) % EXPLORE_CANDIDATES);
    d->weighed = 0u;
    d->best_cost = UINT32_MAX;
    d->phase = 0u;
    explore_enter(e, EXPLORE_DECIDE);
}

/*
 * One candidate heading: the visits along a 1 m ray, walked a cell at a time from the
 * centre of the robot's cell in Q16 cell units (no division per cell), and the obstacle
 * memory seen facing that way. The ray's cells are read through grid_state(): beyond an
 * occupied cell, or outside the grid, every cell counts as fully visited, so blocked and
 * short rays lose; a known free cell costs its visits and one more than an unknown cell,
 * so that ways into the unseen win among equals.
 */
static void ray_begin(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    explore_decide_t *d = &e->decide;
    uint32_t steps = EXPLORE_LOOK_UM / e->cfg.cell_um;
    steps = steps < 1u ? 1u : steps;
    bam32_t h = pose->heading + d->candidate * EXPLORE_CANDIDATE_BAM;
    explore_frame_t f = {pose->x_um, pose->y_um, fix_cos(h), fix_sin(h)};
    explore_memory_begin(e, &f);
    d->ray_cost = 0u;
    d->ray.left = steps;
    grid_cell_t start;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &start) != 0) {
        d->ray_cost = steps * e->cfg.tm_max;
        d->ray.left = 0u;
        return;
    }
    d->ray.fx = ((int32_t)start.a << 16) + 0x8000;
    d->ray.fy = ((int32_t)start.b << 16) + 0x8000;
    d->ray.dx = f.cos >> 14; /* one cell, Q16 */
    d->ray.dy = f.sin >> 14;
}

static void ray_walk(explore_t *e, const grid_t *g)
{
    explore_decide_t *d = &e->decide;
    const uint32_t na = g->a_cells;
    const uint32_t nb = g->b_cells;
    for (uint32_t n = 0; n < EXPLORE_RAY_CELLS && d->ray.left > 0u; n++) {
        uint32_t k = explore_ray_next(&d->ray, na, nb);
        grid_state_t st = k == EXPLORE_NO_CELL ? GRID_OCCUPIED : grid_state(g, k);
        if (st == GRID_OCCUPIED) {
            d->ray_cost += d->ray.left * e->cfg.tm_max;
            d->ray.left = 0u;
            return;
        }
        d->ray_cost += g->tm[k] + (st == GRID_FREE ? 1u : 0u);
        d->ray.left--;
    }
}

void explore_decide_step(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    explore_decide_t *d = &e->decide;
    if (d->phase == 0u) {
        ray_begin(e, pose, g);
        d->phase = 1u;
        return;
    }
    if (d->ray.left > 0u) {
        ray_walk(e, g);
        return;
    }
    if (!explore_memory_points(e)) {
        return;
    }
    uint32_t cost = d->ray_cost;
    int32_t ahead = e->memory.work.ahead_um;
    if (ahead != INT32_MAX && ahead - e->cfg.mount_x_um < e->cfg.avoid_um) {
        cost += 2u * EXPLORE_LOOK_UM / e->cfg.cell_um * e->cfg.tm_max;
    }
    /* Among equally visited ways, the smallest turn: 0 for straight on, 6 for back. */
    uint32_t turn =
        d->candidate <= EXPLORE_CANDIDATES / 2u ? d->candidate : EXPLORE_CANDIDATES - d->candidate;
    cost = cost * EXPLORE_CANDIDATES + turn;
    if (cost < d->best_cost) {
        d->best_cost = cost;
        d->best = d->candidate;
    }
    /* The next candidate, wrapping within the span. */
    uint8_t rel = (uint8_t)((d->candidate + EXPLORE_CANDIDATES - d->first) % EXPLORE_CANDIDATES);
    rel = (uint8_t)((rel + 1u) % d->span);
    d->candidate = (uint8_t)((d->first + rel) % EXPLORE_CANDIDATES);
    d->phase = 0u;
    if (++d->weighed >= d->span) {
        explore_pass_restart(e); /* the driving pass starts afresh, facing the way chosen */
        explore_state_t then = (explore_state_t)d->then;
        if (d->best == 0u) {
            explore_enter(e, then);
        } else {
            explore_turn_by(e, pose, (int32_t)(d->best * EXPLORE_CANDIDATE_BAM), then);
        }
    }
}
