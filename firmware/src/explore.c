/* SPDX-License-Identifier: MIT */
/* Exploration: the states, looking, turning, backing off along the trail, and the random,
 * TM-guided and square modes. The memory and what is ahead are in explore_scan.c, the
 * weighing of headings in explore_decide.c, the walls mode in explore_walls.c (openings
 * in explore_door.c, the frontier in explore_seek.c), the map's corridor in
 * explore_map.c. */
#include "explore_internal.h"

#include <string.h>

#define EXPLORE_TURN_DONE EXPLORE_DEG(1)  /* a turn ends within 1° */
#define EXPLORE_TURN_SLOW EXPLORE_DEG(20) /* and slows down over its last 20° */
#define EXPLORE_TURN_MIN_MM_S 30
#define EXPLORE_TURN_MAX_TICKS 1500u
#define EXPLORE_RANDOM_TURN_MASK 1023u    /* a random turn on average every 10 s */
#define EXPLORE_BACK_MM_S 80
#define EXPLORE_BACK_REACHED_UM 20000     /* a trail position is reached this close */
/* After a stall the robot stands before it backs off: wheels that stall need not touch
 * anything (an encoder that stops counting looks the same), and a wheel driven on a
 * count that does not come would turn the robot blind. A stall while backing off stands
 * again, a few times at most. */
#define EXPLORE_HOLD_TICKS 300u
#define EXPLORE_HOLDS_MAX 3u

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
    e->follow_um = (int32_t)cfg->follow_um;
    e->mount_x_um = cfg->mount_x_um;
    e->mount_y_um = cfg->mount_y_um;
    e->square_side_um = (int32_t)cfg->square_side_um;
    e->laps = cfg->square_laps;
    e->cell_um = cfg->cell_um;
    e->tm_max = cfg->tm_max;
    e->leg_x_um = cfg->start_x_um;
    e->leg_y_um = cfg->start_y_um;
    e->trail_x_um[0] = cfg->start_x_um;
    e->trail_y_um[0] = cfg->start_y_um;
    e->trail_len = 1u;
    e->target_heading = fix_bam_from_mdeg(cfg->start_heading_mdeg);
    e->scan.ahead_um = INT32_MAX;
    e->scan.right_q10 = INT32_MAX;
    e->scan.behind_q10 = INT32_MAX;
    e->map_um = INT32_MAX;
    explore_map_init(e, cfg);
    explore_seek_init(e);
    e->decide = true;
    e->after_turn = EXPLORE_FORWARD;
    switch (e->mode) {
    case EXPLORE_RANDOM:
    case EXPLORE_TM:
    case EXPLORE_WALLS:
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
uint32_t explore_rng_below(explore_t *e, uint32_t n)
{
    uint32_t x = e->rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    e->rng = x;
    return x % n;
}

uint32_t explore_isqrt(uint32_t v)
{
    uint32_t r = 0u;
    for (uint32_t b = 1u << 15; b != 0u; b >>= 1) {
        if ((r + b) * (r + b) <= v) {
            r += b;
        }
    }
    return r;
}

void explore_enter(explore_t *e, explore_state_t s)
{
    e->state = (uint8_t)s;
    e->ticks = 0u;
    e->look_readings = 0u;
}

void explore_turn_by(explore_t *e, const odom_pose_t *pose, int32_t angle, explore_state_t then)
{
    e->target_heading = pose->heading + (bam32_t)angle;
    e->after_turn = (uint8_t)then;
    e->turns++;
    e->front = false; /* what lay ahead along a wall is measured again after a turn */
    e->door = false;
    explore_enter(e, EXPLORE_TURN);
}

/* ---- the trail ------------------------------------------------------------------------- */

/* A new trail position each EXPLORE_TRAIL_STEP_UM driven. */
static bool trail_step(explore_t *e, const odom_pose_t *pose)
{
    uint64_t step = EXPLORE_TRAIL_STEP_UM;
    if (explore_dist2(pose, e->trail_x_um[e->trail_head], e->trail_y_um[e->trail_head]) <
        step * step) {
        return false;
    }
    e->trail_head = (uint8_t)((e->trail_head + 1u) % EXPLORE_TRAIL);
    e->trail_x_um[e->trail_head] = pose->x_um;
    e->trail_y_um[e->trail_head] = pose->y_um;
    e->trail_len = (uint8_t)(e->trail_len < EXPLORE_TRAIL ? e->trail_len + 1u : EXPLORE_TRAIL);
    return true;
}

/* ---- the states ------------------------------------------------------------------------- */

/* A random turn of min..180° (in binary angle units), to the left (dir > 0), the right
 * (dir < 0) or either way (dir == 0). */
static void random_turn(explore_t *e, const odom_pose_t *pose, bam32_t min, int dir)
{
    uint32_t span = EXPLORE_DEG(180) - min;
    int32_t angle = (int32_t)(min + explore_rng_below(e, span));
    if (dir == 0) {
        dir = explore_rng_below(e, 2u) != 0u ? 1 : -1;
    }
    explore_turn_by(e, pose, dir * angle, EXPLORE_FORWARD);
}

/* The paper's avoidance: away from the side of what is ahead. (Always to the left, so
 * that it ends on the seen side, was measured too: the turns' wheel-base error then adds
 * up instead of cancelling, and the map's F1 drops by a tenth.) */
static int away(const explore_t *e)
{
    return e->scan.lateral_um > 0 ? -1 : 1;
}

/* TM mode, something ahead: weigh the ways from straight on to 150° left, so that what
 * was ahead ends on the right, where the sweep sees it (not straight back: a wall beside
 * would then be on the blind side). */
static void tm_avoid(explore_t *e)
{
    explore_decide(e, 0u, 6u, EXPLORE_FORWARD);
}

static void look_step(explore_t *e, const odom_pose_t *pose, bool reading)
{
    /* One full pass of the sweep since standing still, then a memory pass that began
     * after the last of its readings, then decide. */
    if (e->look_readings < e->stops || reading) {
        return;
    }
    if (e->look_mark == 0u) {
        e->look_mark = e->now;
        return;
    }
    if (e->scan_at <= e->look_mark) {
        return;
    }
    e->look_mark = 0u;
    bool blocked = explore_ahead_um(e, pose) < e->avoid_um;
    switch (e->mode) {
    case EXPLORE_TM:
        if (blocked) {
            tm_avoid(e);
        } else if (e->decide) {
            explore_decide(e, 0u, EXPLORE_CANDIDATES, EXPLORE_FORWARD);
        } else {
            explore_enter(e, EXPLORE_FORWARD);
        }
        break;
    case EXPLORE_WALLS:
        explore_walls_look(e, pose, blocked);
        break;
    default:
        if (blocked) {
            random_turn(e, pose, EXPLORE_DEG(90), away(e));
        } else {
            explore_enter(e, EXPLORE_FORWARD);
        }
        break;
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
            explore_enter(e, EXPLORE_FORWARD);
        } else {
            explore_enter(e, EXPLORE_LOOK);
        }
        return;
    }
    int32_t speed = e->turn_mm_s;
    if (mag < EXPLORE_TURN_SLOW) {
        speed = speed * (int32_t)(mag >> 16) / (int32_t)(EXPLORE_TURN_SLOW >> 16);
        speed = speed < EXPLORE_TURN_MIN_MM_S ? EXPLORE_TURN_MIN_MM_S : speed;
    }
    int32_t dir = err > 0 ? 1 : -1; /* counter-clockwise: right wheel forward */
    target_mm_s[ODOM_LEFT] = -dir * speed;
    target_mm_s[ODOM_RIGHT] = dir * speed;
}

/* The differences are taken modulo 2^32 (exact within 2 km, and defined after any
 * encoder glitch); the squares fit 63 bits and their sum 64. */
uint64_t explore_dist2(const odom_pose_t *pose, int32_t x_um, int32_t y_um)
{
    int32_t dx = (int32_t)((uint32_t)pose->x_um - (uint32_t)x_um);
    int32_t dy = (int32_t)((uint32_t)pose->y_um - (uint32_t)y_um);
    return (uint64_t)((int64_t)dx * dx) + (uint64_t)((int64_t)dy * dy);
}

/* The squared distance from the start of the leg. */
static uint64_t leg_dist2(const odom_pose_t *pose, const explore_t *e)
{
    return explore_dist2(pose, e->leg_x_um, e->leg_y_um);
}

static void square_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = e->cruise_mm_s;
    int64_t side = e->square_side_um;
    if (leg_dist2(pose, e) < (uint64_t)(side * side)) {
        return;
    }
    e->leg++;
    if (e->laps != 0u && e->leg >= 4u * e->laps) {
        explore_enter(e, EXPLORE_STOP);
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    } else {
        /* Square corners are absolute: start heading + 90° per leg. */
        e->target_heading += EXPLORE_DEG(90);
        e->turns++;
        explore_enter(e, EXPLORE_TURN);
    }
}

static void forward_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2])
{
    int32_t ahead = explore_ahead_um(e, pose);
    if (ahead < e->avoid_um) {
        e->avoidances++;
        switch (e->mode) {
        case EXPLORE_TM:
            tm_avoid(e);
            break;
        case EXPLORE_WALLS:
            /* Turn so that what is ahead is on the right, and follow it. */
            explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
            break;
        default:
            random_turn(e, pose, EXPLORE_DEG(90), away(e));
            break;
        }
        return;
    }
    int32_t v = explore_speed_mm_s(e, ahead);
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = v;
    switch (e->mode) {
    case EXPLORE_TM:
        if (e->ticks > EXPLORE_TM_REDECIDE_TICKS) {
            /* On the way: within 60° either side, so that a wall beside is not turned
             * onto the blind side. */
            explore_decide(e, EXPLORE_CANDIDATES - 2u, 5u, EXPLORE_FORWARD);
        }
        break;
    case EXPLORE_WALLS:
        explore_walls_cross(e, pose, g, target_mm_s);
        break;
    default:
        if (e->ticks > EXPLORE_FORWARD_MAX_TICKS ||
            explore_rng_below(e, EXPLORE_RANDOM_TURN_MASK + 1u) == 0u) {
            random_turn(e, pose, EXPLORE_DEG(30), 0);
        }
        break;
    }
}

/* Wheels that stall while driving: stand, then back off along the trail. */
static bool stall(explore_t *e, const odom_pose_t *pose, bool stalled)
{
    if (!stalled || e->mode == EXPLORE_SQUARE || e->state == EXPLORE_HOLD ||
        e->state == EXPLORE_STOP || e->state == EXPLORE_LOOK || e->state == EXPLORE_DECIDE ||
        e->state == EXPLORE_SEEK) {
        return false;
    }
    e->stalls++;
    e->narrow = false;
    e->door = false;
    /* Reversing: what stopped it is behind, or a count stopped; stand, then go on backing
     * off (it ends after a few such stalls), or look. One wheel stopped while the other
     * turned: no body against anything (that stops both), a wheel or its count that
     * failed; backing off on that count would go blind, so stand, then look. */
    bool reversing = e->state == EXPLORE_BACK || e->state == EXPLORE_DOOR;
    if (reversing || e->one_wheel) {
        e->hold_back = e->state == EXPLORE_BACK;
        e->holds = (uint8_t)(e->holds + reversing);
        e->after_turn = EXPLORE_FOLLOW;
        explore_enter(e, EXPLORE_HOLD);
        return true;
    }
    /* Whatever stopped the robot is just ahead of its body: remember it there. */
    uint8_t i = e->next_point;
    e->pt_x_um[i] = pose->x_um + fix_mul_q30(e->clearance_um, fix_cos(pose->heading));
    e->pt_y_um[i] = pose->y_um + fix_mul_q30(e->clearance_um, fix_sin(pose->heading));
    e->pt_seen[i] = e->now;
    e->next_point = (uint8_t)((i + 1u) % EXPLORE_POINTS);
    e->leg_x_um = pose->x_um;
    e->leg_y_um = pose->y_um;
    e->back_left = e->trail_len;
    e->holds = 0u;
    e->hold_back = true;
    explore_enter(e, EXPLORE_HOLD);
    return true;
}

static void hold_step(explore_t *e)
{
    if (e->ticks > EXPLORE_HOLD_TICKS) {
        explore_enter(e, e->hold_back ? EXPLORE_BACK : EXPLORE_LOOK);
    }
}

/*
 * Reverse toward the trail positions, newest first: the rear is turned toward the next
 * one in place when it is more than about 27° off, and steered onto it while reversing
 * otherwise. Without a trail (a stall at the start) the robot reverses straight.
 */
static void back_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int64_t back = EXPLORE_BACK_UM;
    if (leg_dist2(pose, e) >= (uint64_t)(back * back) || e->ticks > EXPLORE_TURN_MAX_TICKS ||
        e->holds > EXPLORE_HOLDS_MAX) {
        e->decide = true; /* TM mode weighs the ways again */
        e->trail_len = 1u;
        e->trail_x_um[e->trail_head] = pose->x_um;
        e->trail_y_um[e->trail_head] = pose->y_um;
        switch (e->mode) {
        case EXPLORE_TM:
            explore_enter(e, EXPLORE_LOOK);
            break;
        case EXPLORE_WALLS:
            explore_turn_by(e, pose, (int32_t)EXPLORE_DEG(90), EXPLORE_FOLLOW);
            break;
        default:
            random_turn(e, pose, EXPLORE_DEG(90), 0);
            break;
        }
        return;
    }
    int32_t v = -EXPLORE_BACK_MM_S;
    while (e->back_left > 0u) {
        uint8_t i = (uint8_t)((e->trail_head + EXPLORE_TRAIL - (e->trail_len - e->back_left)) %
                              EXPLORE_TRAIL);
        int32_t px = (int32_t)((uint32_t)e->trail_x_um[i] - (uint32_t)pose->x_um);
        int32_t py = (int32_t)((uint32_t)e->trail_y_um[i] - (uint32_t)pose->y_um);
        q1_30_t c = fix_cos(pose->heading);
        q1_30_t s = fix_sin(pose->heading);
        int32_t ahead = (int32_t)(((int64_t)px * c + (int64_t)py * s) >> 30);
        int32_t side = (int32_t)(((int64_t)py * c - (int64_t)px * s) >> 30);
        int32_t mag = side < 0 ? -side : side;
        if (ahead > -EXPLORE_BACK_REACHED_UM && mag < EXPLORE_BACK_REACHED_UM) {
            e->back_left--; /* reached: on to the older one */
            continue;
        }
        int32_t turn = e->turn_mm_s / 2;
        if (ahead > 0 || 2 * mag > -ahead) {
            /* Bring the rear round to it: a point to the left swings the rear left,
             * which is a clockwise turn. */
            target_mm_s[ODOM_LEFT] = side > 0 ? turn : -turn;
            target_mm_s[ODOM_RIGHT] = -target_mm_s[ODOM_LEFT];
            return;
        }
        int32_t steer = side / 1000 * EXPLORE_BACK_MM_S / (-ahead / 1000 + 1);
        target_mm_s[ODOM_LEFT] = v + steer;
        target_mm_s[ODOM_RIGHT] = v - steer;
        return;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = v;
}

/* The background job of a tick without a reading, one at a time so that no tick carries
 * two: a reading's point into the memory, the walls mode's look at a trail step, or a
 * slice of the pass over the memory and the map. */
static void job(explore_t *e, const odom_pose_t *pose, const grid_t *g, const int32_t held[2])
{
    if (e->pending != 0u) {
        explore_remember(e, pose);
        return;
    }
    if (e->trail_due) {
        e->trail_due = false;
        explore_walls_trail(e, pose, g);
        return;
    }
    switch (e->state) {
    case EXPLORE_LOOK:
    case EXPLORE_FOLLOW:
    case EXPLORE_PASS:
        explore_scan_slice(e, pose, g, held);
        break;
    case EXPLORE_FORWARD:
        if (e->mode != EXPLORE_SQUARE) {
            explore_scan_slice(e, pose, g, held);
        }
        break;
    default:
        break;
    }
}

void explore_step(explore_t *e, const odom_pose_t *pose, const sweep_out_t *sw,
                  const mapper_t *m, const grid_t *g, const int32_t held[2], bool stalled,
                  int32_t target_mm_s[2])
{
    e->now++;
    e->ticks++;
    if (sw->reading_ready) {
        /* This tick maps the reading: only note it, and keep the wheels as they were. */
        e->look_readings++;
        /* The last sweep's echoes, counted as the window slides. */
        uint32_t echo = sw->reading.echo ? 1u : 0u;
        uint32_t out = (e->echo_bits >> (EXPLORE_ECHO_WINDOW - 1u)) & 1u;
        e->echoes = (uint8_t)(e->echoes + echo - out);
        e->echo_bits = (uint16_t)((((uint32_t)e->echo_bits << 1) | echo) & EXPLORE_ECHO_MASK);
        if (echo) {
            e->heard = e->now;
            e->deaf_stood = 0u;
        }
        /* Its point is copied now: the background loop may map older readings, and
         * change the mapper's last outcome, before the next tick. */
        e->pending = echo && (m->last == MAPPER_HIT || m->last == MAPPER_OUTSIDE) ? 1u : 0u;
        e->pending_x_um = m->last_x_um;
        e->pending_y_um = m->last_y_um;
        target_mm_s[ODOM_LEFT] = e->target_mm_s[ODOM_LEFT];
        target_mm_s[ODOM_RIGHT] = e->target_mm_s[ODOM_RIGHT];
        return;
    }
    job(e, pose, g, held);
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    if (e->now - e->heard > EXPLORE_DEAF_TICKS && e->deaf_stood < EXPLORE_DEAF_STAND_TICKS &&
        (e->state == EXPLORE_FORWARD || e->state == EXPLORE_FOLLOW || e->state == EXPLORE_PASS) &&
        e->mode != EXPLORE_SQUARE) {
        /* Deaf: stand (the wheels at 0) until an echo comes back, or for long enough. */
        e->deaf_stood++;
    } else if (!stall(e, pose, stalled)) {
        switch (e->state) {
        case EXPLORE_LOOK:
            look_step(e, pose, false);
            break;
        case EXPLORE_DECIDE:
            explore_decide_step(e, pose, g);
            break;
        case EXPLORE_TURN:
            turn_step(e, pose, target_mm_s);
            break;
        case EXPLORE_FORWARD:
            if (e->mode == EXPLORE_SQUARE) {
                square_step(e, pose, target_mm_s);
            } else {
                forward_step(e, pose, g, target_mm_s);
            }
            break;
        case EXPLORE_FOLLOW:
            explore_follow_step(e, pose, g, target_mm_s);
            break;
        case EXPLORE_DOOR:
            explore_door_step(e, pose, g, target_mm_s);
            break;
        case EXPLORE_SEEK:
            explore_seek_step(e, pose, g);
            break;
        case EXPLORE_FACE:
            explore_face_step(e, pose, target_mm_s);
            break;
        case EXPLORE_PASS:
            explore_pass_step(e, pose, target_mm_s);
            break;
        case EXPLORE_BACK:
            back_step(e, pose, target_mm_s);
            break;
        case EXPLORE_HOLD:
            hold_step(e);
            break;
        default:
            break;
        }
        if ((e->state == EXPLORE_FORWARD || e->state == EXPLORE_FOLLOW) && trail_step(e, pose) &&
            e->mode == EXPLORE_WALLS) {
            e->trail_due = true;
        }
    }
    e->target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_LEFT];
    e->target_mm_s[ODOM_RIGHT] = target_mm_s[ODOM_RIGHT];
}
