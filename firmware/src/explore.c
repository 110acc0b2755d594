/* SPDX-License-Identifier: MIT */
/* Exploration: random walk with obstacle avoidance, TM-guided headings, a test square. */
#include "slam/explore.h"

#include <string.h>

#include "slam/error.h"
#include "slam/fixed.h"

#define DEG(d) ((bam32_t)((uint64_t)(d) * 0x100000000ull / 360u))
#define EXPLORE_LOOK_UM 1000000     /* TM rays reach 1 m */
#define EXPLORE_TURN_DONE DEG(1)    /* a turn ends within 1° */
#define EXPLORE_TURN_SLOW DEG(20)   /* and slows down over its last 20° */
#define EXPLORE_TURN_MIN_MM_S 30
#define EXPLORE_TURN_MAX_TICKS 1500u
#define EXPLORE_TM_REDECIDE_TICKS 600u
#define EXPLORE_RANDOM_TURN_MASK 1023u /* a random turn on average every 10 s */

void explore_init(explore_t *e, const slam_config_t *cfg)
{
    memset(e, 0, sizeof *e);
    e->mode = cfg->explore_mode;
    e->stops = cfg->sweep_stops;
    e->rng = cfg->explore_seed;
    e->cruise_mm_s = cfg->cruise_mm_s;
    e->turn_mm_s = cfg->turn_mm_s;
    e->avoid_um = (int32_t)cfg->avoid_um;
    e->clearance_um = (int32_t)cfg->clearance_um;
    e->mount_x_um = cfg->mount_x_um;
    e->mount_y_um = cfg->mount_y_um;
    e->square_side_um = (int32_t)cfg->square_side_um;
    e->laps = cfg->square_laps;
    e->cell_um = cfg->cell_um;
    e->tm_max = cfg->tm_max;
    e->leg_x_um = cfg->start_x_um;
    e->leg_y_um = cfg->start_y_um;
    e->target_heading = fix_bam_from_mdeg(cfg->start_heading_mdeg);
    e->decide = true;
    switch (e->mode) {
    case EXPLORE_RANDOM:
    case EXPLORE_TM:
        e->state = EXPLORE_LOOK;
        break;
    case EXPLORE_SQUARE:
        e->state = EXPLORE_FORWARD;
        break;
    default:
        e->state = EXPLORE_STOP;
        break;
    }
}

/* xorshift32: the exploration's own random stream, seeded by the configuration. */
static uint32_t rng_below(explore_t *e, uint32_t n)
{
    uint32_t x = e->rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    e->rng = x;
    return x % n;
}

static void enter(explore_t *e, explore_state_t s)
{
    e->state = (uint8_t)s;
    e->ticks = 0u;
    e->look_readings = 0u;
}

/* The latest reading of each stop becomes a world point (or clears the stop). The mapper
 * has just placed the point of a reading inside the confidence sector; farther echoes
 * are too far to be in the way. */
static void remember(explore_t *e, const sweep_out_t *sw, const mapper_t *m)
{
    if (!sw->reading_ready) {
        return;
    }
    uint8_t stop = sw->reading.stop;
    e->look_readings++;
    e->obst_seen[stop] = 0u;
    if (sw->reading.echo && (m->last == MAPPER_HIT || m->last == MAPPER_OUTSIDE)) {
        e->obst_x_um[stop] = m->last_x_um;
        e->obst_y_um[stop] = m->last_y_um;
        e->obst_seen[stop] = e->now;
    }
}

/* The remembered point nearest ahead in the robot's corridor; false if none. */
static bool nearest_ahead(const explore_t *e, const odom_pose_t *pose, int32_t *lateral_um)
{
    q1_30_t c = fix_cos(pose->heading);
    q1_30_t s = fix_sin(pose->heading);
    int64_t best = INT64_MAX;
    for (uint8_t n = 0; n <= e->stops; n++) {
        /* The sweep's stops, then the point of the last stall. */
        uint8_t i = n < e->stops ? n : (uint8_t)EXPLORE_BUMP;
        uint32_t life = n < e->stops ? EXPLORE_MEMORY_TICKS : EXPLORE_BUMP_TICKS;
        if (e->obst_seen[i] == 0u || e->now - e->obst_seen[i] > life) {
            continue;
        }
        /* The point in the robot frame. A remembered point lies within a few metres of the
         * robot, so the differences fit 32 bits (taken modulo 2^32, which is exact here),
         * and the 32 x 32-bit products (one SMULL each on a Cortex-M4) fit 64. */
        int32_t dx = (int32_t)((uint32_t)e->obst_x_um[i] - (uint32_t)pose->x_um);
        int32_t dy = (int32_t)((uint32_t)e->obst_y_um[i] - (uint32_t)pose->y_um);
        int64_t ahead = ((int64_t)dx * c + (int64_t)dy * s) >> 30;
        int64_t side = ((int64_t)dy * c - (int64_t)dx * s) >> 30;
        bool in_corridor = side > -e->clearance_um && side < e->clearance_um;
        if (in_corridor && ahead > 0 && ahead < e->mount_x_um + e->avoid_um && ahead < best) {
            best = ahead;
            *lateral_um = (int32_t)side;
        }
    }
    return best != INT64_MAX;
}

bool explore_blocked(const explore_t *e, const odom_pose_t *pose)
{
    int32_t lateral;
    return nearest_ahead(e, pose, &lateral);
}

static void begin_turn(explore_t *e, const odom_pose_t *pose, int32_t angle)
{
    e->target_heading = pose->heading + (bam32_t)angle;
    e->turns++;
    enter(e, EXPLORE_TURN);
}

/* A random turn of min..180° (in binary angle units): away from an obstacle on one
 * side, or either way. */
static void random_turn(explore_t *e, const odom_pose_t *pose, bam32_t min, int away_from)
{
    uint32_t span = DEG(180) - min;
    int32_t angle = (int32_t)(min + rng_below(e, span));
    int dir = away_from != 0 ? -away_from : (rng_below(e, 2u) != 0u ? 1 : -1);
    begin_turn(e, pose, dir * angle);
}

/* TM mode, one candidate heading: the visits along a 1 m ray, walked a cell at a time
 * from the centre of the robot's cell in Q16 cell units (no division per cell). Beyond an
 * occupied OM cell, or outside the grid, every cell counts as fully visited, so blocked
 * and short rays lose. The weighing is spread over ticks to keep each one small: one tick
 * starts the ray, then EXPLORE_RAY_CELLS cells a tick, then one tick checks the obstacle
 * memory and compares. */
static bam32_t candidate_heading(const explore_t *e, const odom_pose_t *pose)
{
    return pose->heading + e->candidate * (bam32_t)(0x100000000ull / EXPLORE_CANDIDATES);
}

static void ray_begin(explore_t *e, const odom_pose_t *pose, const grid_t *g)
{
    uint32_t steps = EXPLORE_LOOK_UM / e->cell_um;
    steps = steps < 1u ? 1u : steps;
    e->ray_cost = 0u;
    e->ray_left = steps;
    grid_cell_t start;
    if (grid_cell_of(g, pose->x_um, pose->y_um, &start) != SLAM_OK) {
        e->ray_cost = steps * e->tm_max;
        e->ray_left = 0u;
        return;
    }
    bam32_t h = candidate_heading(e, pose);
    e->ray_fx = ((int32_t)start.a << 16) + 0x8000;
    e->ray_fy = ((int32_t)start.b << 16) + 0x8000;
    e->ray_dx = fix_cos(h) >> 14; /* one cell, Q16 */
    e->ray_dy = fix_sin(h) >> 14;
}

static void ray_walk(explore_t *e, const grid_t *g)
{
    for (uint32_t n = 0; n < EXPLORE_RAY_CELLS && e->ray_left > 0u; n++) {
        e->ray_fx += e->ray_dx;
        e->ray_fy += e->ray_dy;
        uint32_t a = (uint32_t)(e->ray_fx >> 16);
        uint32_t b = (uint32_t)(e->ray_fy >> 16);
        uint32_t k = b * SLAM_GRID_A + a;
        if (e->ray_fx < 0 || e->ray_fy < 0 || a >= SLAM_GRID_A || b >= SLAM_GRID_B ||
            grid_state(g, k) == GRID_OCCUPIED) {
            e->ray_cost += e->ray_left * e->tm_max;
            e->ray_left = 0u;
            return;
        }
        e->ray_cost += g->tm[k];
        e->ray_left--;
    }
}

static void decide_step(explore_t *e, const odom_pose_t *pose, const grid_t *g, bool reading)
{
    if (e->ticks == 1u) {
        /* Candidates are weighed from a random first one, so ties between equal turns go
         * a random way. */
        e->candidate = (uint8_t)rng_below(e, EXPLORE_CANDIDATES);
        e->weighed = 0u;
        e->best_cost = UINT32_MAX;
        e->ray_phase = 0u;
    }
    if (e->ray_phase == 0u) {
        ray_begin(e, pose, g);
        e->ray_phase = 1u;
        return;
    }
    if (e->ray_left > 0u) {
        ray_walk(e, g);
        return;
    }
    if (reading) {
        return; /* the memory check waits for a tick without a reading to map */
    }
    uint32_t cost = e->ray_cost;
    odom_pose_t facing = {pose->x_um, pose->y_um, candidate_heading(e, pose)};
    if (explore_blocked(e, &facing)) {
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
    e->candidate = (uint8_t)((e->candidate + 1u) % EXPLORE_CANDIDATES);
    e->ray_phase = 0u;
    if (++e->weighed >= EXPLORE_CANDIDATES) {
        e->decide = false;
        int32_t angle = (int32_t)(e->best * (bam32_t)(0x100000000ull / EXPLORE_CANDIDATES));
        if (e->best == 0u) {
            enter(e, EXPLORE_FORWARD);
        } else {
            begin_turn(e, pose, angle);
        }
    }
}

static void turn_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int32_t err = fix_bam_diff(e->target_heading, pose->heading);
    uint32_t mag = err < 0 ? (uint32_t)(-(int64_t)err) : (uint32_t)err;
    if (mag < EXPLORE_TURN_DONE || e->ticks > EXPLORE_TURN_MAX_TICKS) {
        if (e->mode == EXPLORE_SQUARE) {
            e->leg_x_um = pose->x_um;
            e->leg_y_um = pose->y_um;
            enter(e, EXPLORE_FORWARD);
        } else {
            enter(e, EXPLORE_LOOK);
        }
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
        return;
    }
    int32_t speed = e->turn_mm_s;
    if (mag < EXPLORE_TURN_SLOW) {
        speed = (int32_t)((int64_t)speed * mag / EXPLORE_TURN_SLOW);
        speed = speed < EXPLORE_TURN_MIN_MM_S ? EXPLORE_TURN_MIN_MM_S : speed;
    }
    int32_t dir = err > 0 ? 1 : -1; /* counter-clockwise: right wheel forward */
    target_mm_s[ODOM_LEFT] = -dir * speed;
    target_mm_s[ODOM_RIGHT] = dir * speed;
}

/* The squared distance from the start of the leg. As in nearest_ahead(), the differences
 * are taken modulo 2^32 (exact within 2 km, and defined after any encoder glitch); the
 * squares fit 63 bits and their sum 64. */
static uint64_t leg_dist2(const odom_pose_t *pose, const explore_t *e)
{
    int32_t dx = (int32_t)((uint32_t)pose->x_um - (uint32_t)e->leg_x_um);
    int32_t dy = (int32_t)((uint32_t)pose->y_um - (uint32_t)e->leg_y_um);
    return (uint64_t)((int64_t)dx * dx) + (uint64_t)((int64_t)dy * dy);
}

static void forward_step(explore_t *e, const odom_pose_t *pose, bool reading,
                         int32_t target_mm_s[2])
{
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = e->cruise_mm_s;
    if (e->mode == EXPLORE_SQUARE) {
        int64_t side = e->square_side_um;
        if (leg_dist2(pose, e) >= (uint64_t)(side * side)) {
            e->leg++;
            if (e->laps != 0u && e->leg >= 4u * e->laps) {
                enter(e, EXPLORE_STOP);
                target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
            } else {
                /* Square corners are absolute: start heading + 90° per leg. */
                e->target_heading += DEG(90);
                e->turns++;
                enter(e, EXPLORE_TURN);
            }
        }
        return;
    }
    /* The corridor is checked in the ticks without a new reading: a reading's tick already
     * maps it, and the check one tick (2 mm) later keeps the worst tick small. */
    int32_t lateral = 0;
    if (!reading && nearest_ahead(e, pose, &lateral)) {
        e->avoidances++;
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
        if (e->mode == EXPLORE_TM) {
            enter(e, EXPLORE_DECIDE);
        } else {
            random_turn(e, pose, DEG(90), lateral > 0 ? 1 : -1);
        }
        return;
    }
    if (e->mode == EXPLORE_TM) {
        if (e->ticks > EXPLORE_TM_REDECIDE_TICKS) {
            enter(e, EXPLORE_DECIDE);
        }
    } else if (e->ticks > EXPLORE_FORWARD_MAX_TICKS ||
               rng_below(e, EXPLORE_RANDOM_TURN_MASK + 1u) == 0u) {
        random_turn(e, pose, DEG(30), 0);
    }
}

/* Wheels that stall while driving: back off first, from where the stall happened. */
static bool stall(explore_t *e, const odom_pose_t *pose, bool stalled)
{
    if (!stalled || e->mode == EXPLORE_SQUARE ||
        (e->state != EXPLORE_FORWARD && e->state != EXPLORE_TURN)) {
        return false;
    }
    e->stalls++;
    e->leg_x_um = pose->x_um;
    e->leg_y_um = pose->y_um;
    /* Whatever stopped the robot is just ahead of its body: remember it there. */
    e->obst_x_um[EXPLORE_BUMP] = pose->x_um + fix_mul_q30(e->clearance_um, fix_cos(pose->heading));
    e->obst_y_um[EXPLORE_BUMP] = pose->y_um + fix_mul_q30(e->clearance_um, fix_sin(pose->heading));
    e->obst_seen[EXPLORE_BUMP] = e->now;
    enter(e, EXPLORE_BACK);
    return true;
}

static void back_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int64_t back = EXPLORE_BACK_UM;
    if (leg_dist2(pose, e) >= (uint64_t)(back * back) || e->ticks > EXPLORE_TURN_MAX_TICKS) {
        e->decide = true; /* TM mode weighs the ways again */
        if (e->mode == EXPLORE_TM) {
            enter(e, EXPLORE_LOOK);
        } else {
            random_turn(e, pose, DEG(90), 0);
        }
        return;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = -e->cruise_mm_s / 2;
}

void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw,
                  const mapper_t *m, const grid_t *g, bool stalled, int32_t target_mm_s[2])
{
    e->now++;
    e->ticks++;
    remember(e, sw, m);
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    if (stall(e, pose, stalled)) {
        return;
    }
    switch (e->state) {
    case EXPLORE_LOOK:
        /* One full pass of the sweep since standing still, then decide (in a tick without
         * a reading, like every corridor check). */
        if (e->look_readings >= e->stops && !sw->reading_ready) {
            int32_t lateral = 0;
            bool blocked = nearest_ahead(e, pose, &lateral);
            if (e->mode == EXPLORE_TM && (blocked || e->decide)) {
                enter(e, EXPLORE_DECIDE);
            } else if (blocked) {
                random_turn(e, pose, DEG(90), lateral > 0 ? 1 : -1);
            } else {
                enter(e, EXPLORE_FORWARD);
            }
        }
        break;
    case EXPLORE_DECIDE:
        decide_step(e, pose, g, sw->reading_ready);
        break;
    case EXPLORE_TURN:
        turn_step(e, pose, target_mm_s);
        break;
    case EXPLORE_FORWARD:
        forward_step(e, pose, sw->reading_ready, target_mm_s);
        break;
    case EXPLORE_BACK:
        back_step(e, pose, target_mm_s);
        break;
    default:
        break;
    }
}
