/* SPDX-License-Identifier: MIT */
/* The TM-guided choice of a heading: candidate rays through the maps, weighed a few cells
 * and memory points a tick. */
#include "explore_internal.h"

void explore_decide(explore_t *e, uint8_t first, uint8_t span, explore_state_t then)
{
    e->first_candidate = first;
    e->span = span;
    e->after_turn = (uint8_t)then;
    /* Candidates are weighed from a random first one, so ties between equal turns go a
     * random way. */
    e->candidate = (uint8_t)((first + explore_rng_below(e, span)) % EXPLORE_CANDIDATES);
    e->weighed = 0u;
    e->best_cost = UINT32_MAX;
    e->ray_phase = 0u;
    explore_enter(e, EXPLORE_DECIDE);
}

static bam32_t candidate_heading(const explore_t *e, const odom_pose_t *pose)
{
    return pose->heading + e->candidate * EXPLORE_CANDIDATE_BAM;
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
    uint32_t steps = EXPLORE_LOOK_UM / e->cell_um;
    steps = steps < 1u ? 1u : steps;
    bam32_t h = candidate_heading(e, pose);
    q1_30_t c = fix_cos(h);
    q1_30_t s = fix_sin(h);
    explore_scan_begin(e, pose, c, s);
    e->ray_cost = 0u;
    e->ray_left = steps;
    grid_cell_t start;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &start) != 0) {
        e->ray_cost = steps * e->tm_max;
        e->ray_left = 0u;
        return;
    }
    e->ray_fx = ((int32_t)start.a << 16) + 0x8000;
    e->ray_fy = ((int32_t)start.b << 16) + 0x8000;
    e->ray_dx = c >> 14; /* one cell, Q16 */
    e->ray_dy = s >> 14;
}

static void ray_walk(explore_t *e, const grid_t *g)
{
    for (uint32_t n = 0; n < EXPLORE_RAY_CELLS && e->ray_left > 0u; n++) {
        e->ray_fx += e->ray_dx;
        e->ray_fy += e->ray_dy;
        uint32_t a = (uint32_t)(e->ray_fx >> 16);
        uint32_t b = (uint32_t)(e->ray_fy >> 16);
        uint32_t k = b * SLAM_GRID_A + a;
        if (e->ray_fx < 0 || e->ray_fy < 0 || a >= SLAM_GRID_A || b >= SLAM_GRID_B) {
            e->ray_cost += e->ray_left * e->tm_max;
            e->ray_left = 0u;
            return;
        }
        grid_state_t st = grid_state(g, k);
        if (st == GRID_OCCUPIED) {
            e->ray_cost += e->ray_left * e->tm_max;
            e->ray_left = 0u;
            return;
        }
        e->ray_cost += g->tm[k] + (st == GRID_FREE ? 1u : 0u);
        e->ray_left--;
    }
}

void explore_decide_step(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    if (e->ray_phase == 0u) {
        ray_begin(e, pose, g);
        e->ray_phase = 1u;
        return;
    }
    if (e->ray_left > 0u) {
        ray_walk(e, g);
        return;
    }
    if (!explore_scan_points(e)) {
        return;
    }
    uint32_t cost = e->ray_cost;
    int32_t ahead = e->scan_work.ahead_um;
    if (ahead != INT32_MAX && ahead - e->mount_x_um < e->avoid_um) {
        cost += 2u * EXPLORE_LOOK_UM / e->cell_um * e->tm_max;
    }
    /* Among equally visited ways, the smallest turn: 0 for straight on, 6 for back. */
    uint32_t turn = e->candidate <= EXPLORE_CANDIDATES / 2u ? e->candidate
                                                          : EXPLORE_CANDIDATES - e->candidate;
    cost = cost * EXPLORE_CANDIDATES + turn;
    if (cost < e->best_cost) {
        e->best_cost = cost;
        e->best = e->candidate;
    }
    /* The next candidate, wrapping within the span. */
    uint8_t rel = (uint8_t)((e->candidate + EXPLORE_CANDIDATES - e->first_candidate) %
                            EXPLORE_CANDIDATES);
    rel = (uint8_t)((rel + 1u) % e->span);
    e->candidate = (uint8_t)((e->first_candidate + rel) % EXPLORE_CANDIDATES);
    e->ray_phase = 0u;
    if (++e->weighed >= e->span) {
        e->decide = false;
        e->scan_phase = 0u; /* the driving pass starts afresh, facing the way chosen */
        explore_state_t then = (explore_state_t)e->after_turn;
        if (e->best == 0u) {
            explore_enter(e, then);
        } else {
            explore_turn_by(e, pose, (int32_t)(e->best * EXPLORE_CANDIDATE_BAM), then);
        }
    }
}
