/* SPDX-License-Identifier: MIT */
/* The moves every mode shares: turning in place and facing a point, looking, the speed
 * for what is ahead, and the trail that the robot backs off along after a stall. */
#include "moves.h"

#define EXPLORE_TURN_DONE EXPLORE_DEG(1)  /* a turn ends within 1° */
#define EXPLORE_TURN_SLOW EXPLORE_DEG(20) /* and slows down over its last 20° */
#define EXPLORE_TURN_MIN_MM_S 30          /* to no slower than this */
#define EXPLORE_TURN_MAX_TICKS 1500u      /* a turn, a face or a backing off gives up after 15 s */
#define EXPLORE_FACE_DONE 32              /* facing a point: within 1/32 rad (1.8°) */
#define EXPLORE_ECHOES_SURE                                                                        \
    8u                        /* of the last sweep's readings, echoes below which                  \
                                 the robot slows down */
#define EXPLORE_CRAWL_MM_S 60 /* the slowest approach */
#define EXPLORE_BACK_MM_S 80
#define EXPLORE_BACK_REACHED_UM 20000 /* a trail position is reached this close */
/* After a stall the robot stands before it backs off: wheels that stall need not touch
 * anything (an encoder that stops counting looks the same), and a wheel driven on a
 * count that does not come would turn the robot blind. A stall while backing off stands
 * again, a few times at most. One second: most touches are then left within three
 * seconds, and three seconds did no better against stopped encoders (experiments.md). */
#define EXPLORE_HOLD_TICKS 100u
#define EXPLORE_HOLDS_MAX 3u
/* A robot that turns about in one place for EXPLORE_STUCK_TICKS (among a chair's legs,
 * every way closer than avoid_um) backs out the way it came: along the places where it
 * made progress, whose cells its body swept on the way in. */
#define EXPLORE_PROGRESS_UM 250000
#define EXPLORE_ESCAPE_BACK 3u
#define EXPLORE_BACK_PLACES 0xFFu /* back_left: BACK's first tick takes the places */
_Static_assert(EXPLORE_ESCAPE_BACK <= EXPLORE_PROGRESS_KEPT && EXPLORE_ESCAPE_BACK <= EXPLORE_TRAIL,
               "an escape backs out along places of progress kept, as its trail");
_Static_assert((EXPLORE_PROGRESS_KEPT & (EXPLORE_PROGRESS_KEPT - 1u)) == 0u,
               "the places of progress are a ring indexed by a mask");

void explore_moves_init(explore_t *e, const slam_config_t *cfg)
{
    explore_moves_t *mv = &e->moves;
    mv->leg_x_um = cfg->start_x_um;
    mv->leg_y_um = cfg->start_y_um;
    mv->trail_x_um[0] = cfg->start_x_um;
    mv->trail_y_um[0] = cfg->start_y_um;
    mv->trail_len = 1u;
    mv->stuck_x_um = cfg->start_x_um;
    mv->stuck_y_um = cfg->start_y_um;
    for (uint32_t k = 0u; k < EXPLORE_PROGRESS_KEPT; k++) {
        mv->prog_x_um[k] = cfg->start_x_um; /* (the place before the first: the start too) */
        mv->prog_y_um[k] = cfg->start_y_um;
    }
    mv->prog_n = 1u;
    mv->target_heading = fix_bam_from_mdeg(cfg->start_heading_mdeg);
    mv->after_turn = EXPLORE_FORWARD;
}

/* ---- progress and escapes --------------------------------------------------------------- */

/* The slot of the place of progress k places older than the newest. */
static inline uint32_t place(const explore_moves_t *mv, uint32_t k)
{
    return (mv->prog_head - k) & (EXPLORE_PROGRESS_KEPT - 1u);
}

void explore_progress(explore_t *e, const odom_pose_t *pose)
{
    explore_moves_t *mv = &e->moves;
    uint64_t p = EXPLORE_PROGRESS_UM;
    uint32_t h = mv->prog_head;
    uint32_t before = place(mv, 1u);
    /* (The place before it too: going to and fro is no progress. Nor is an escape that
     * got nowhere: its places have left the list, and those before lie further off.) */
    if (explore_dist2(pose, mv->prog_x_um[h], mv->prog_y_um[h]) < p * p ||
        explore_dist2(pose, mv->prog_x_um[before], mv->prog_y_um[before]) < p * p ||
        explore_dist2(pose, mv->stuck_x_um, mv->stuck_y_um) < p * p) {
        return;
    }
    h = (h + 1u) & (EXPLORE_PROGRESS_KEPT - 1u);
    mv->prog_x_um[h] = pose->x_um;
    mv->prog_y_um[h] = pose->y_um;
    mv->prog_head = (uint8_t)h;
    mv->prog_n = (uint8_t)(mv->prog_n < EXPLORE_PROGRESS_KEPT ? mv->prog_n + 1u : mv->prog_n);
    mv->prog_at = e->machine.now;
    if (mv->squeezing) {
        mv->squeezing = false;
        e->memory.narrow = false;
    }
}

/* About to turn: after EXPLORE_STUCK_TICKS without progress (at once when boxed in), back
 * out the way it came instead (BACK's first tick takes the places to back out along: this
 * tick has begun a turn's work). */
static bool escape(explore_t *e, const odom_pose_t *pose, bool boxed)
{
    explore_moves_t *mv = &e->moves;
    explore_progress(e, pose);
    if (e->machine.blind || (!boxed && e->machine.now - mv->prog_at < EXPLORE_STUCK_TICKS) ||
        (int32_t)(e->machine.now - mv->trust_from) < 0) {
        return false;
    }
    e->count.escapes++;
    mv->prog_at = e->machine.now;
    mv->stuck_x_um = pose->x_um;
    mv->stuck_y_um = pose->y_um;
    if (mv->prog_n == 1u) {
        /* No way in known (it started here, or backed out all it knew): squeeze instead,
         * the body's own corridor ahead (as through an opening) until it gets on. */
        e->memory.narrow = true;
        mv->squeezing = true;
        return false;
    }
    e->memory.narrow = false;
    e->wall.door = false;
    mv->escaping = true;
    mv->back_left = EXPLORE_BACK_PLACES;
    explore_enter(e, EXPLORE_BACK);
    return true;
}

/* The newest EXPLORE_ESCAPE_BACK places of progress become the trail to back out along;
 * all but the oldest of them leave the list: a robot that goes back into the same place
 * backs out further the next time. */
static void escape_trail(explore_moves_t *mv, const odom_pose_t *pose)
{
    uint32_t oldest = mv->prog_n < EXPLORE_ESCAPE_BACK ? mv->prog_n - 1u : EXPLORE_ESCAPE_BACK - 1u;
    for (uint32_t k = 0u; k < EXPLORE_ESCAPE_BACK; k++) {
        uint32_t i = place(mv, k < oldest ? k : oldest);
        mv->trail_x_um[EXPLORE_ESCAPE_BACK - 1u - k] = mv->prog_x_um[i];
        mv->trail_y_um[EXPLORE_ESCAPE_BACK - 1u - k] = mv->prog_y_um[i];
    }
    mv->prog_head = (uint8_t)place(mv, oldest);
    mv->prog_n = (uint8_t)(mv->prog_n - oldest);
    mv->trail_head = (uint8_t)(EXPLORE_ESCAPE_BACK - 1u);
    mv->trail_len = (uint8_t)EXPLORE_ESCAPE_BACK;
    mv->back_left = (uint8_t)EXPLORE_ESCAPE_BACK;
    mv->leg_x_um = pose->x_um;
    mv->leg_y_um = pose->y_um;
    mv->holds = 0u;
}

/* ---- turning and facing ----------------------------------------------------------------- */

bool explore_escape_boxed(explore_t *e, const odom_pose_t *pose)
{
    return escape(e, pose, true);
}

void explore_turn_by(explore_t *e, const odom_pose_t *pose, int32_t angle, explore_state_t then)
{
    if (escape(e, pose, false)) {
        return;
    }
    e->moves.target_heading = pose->heading + (bam32_t)angle;
    e->moves.after_turn = (uint8_t)then;
    e->count.turns++;
    explore_wall_forget(e);
    explore_enter(e, EXPLORE_TURN);
}

void explore_turn_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    int32_t err = fix_bam_diff(e->moves.target_heading, pose->heading);
    uint32_t mag = err < 0 ? (uint32_t)(-(int64_t)err) : (uint32_t)err;
    if (mag < EXPLORE_TURN_DONE || e->machine.ticks > EXPLORE_TURN_MAX_TICKS) {
        if (e->machine.blind) {
            /* The next leg is measured from here. */
            e->moves.leg_x_um = pose->x_um;
            e->moves.leg_y_um = pose->y_um;
            explore_enter(e, EXPLORE_FORWARD);
        } else {
            explore_enter(e, EXPLORE_LOOK);
        }
        return;
    }
    int32_t speed = e->cfg.turn_mm_s;
    if (mag < EXPLORE_TURN_SLOW) {
        speed = speed * (int32_t)(mag >> 16) / (int32_t)(EXPLORE_TURN_SLOW >> 16);
        speed = speed < EXPLORE_TURN_MIN_MM_S ? EXPLORE_TURN_MIN_MM_S : speed;
    }
    int32_t dir = err > 0 ? 1 : -1; /* counter-clockwise: right wheel forward */
    target_mm_s[ODOM_LEFT] = -dir * speed;
    target_mm_s[ODOM_RIGHT] = dir * speed;
}

void explore_face(explore_t *e, int32_t x_um, int32_t y_um, explore_state_t then)
{
    e->moves.face_x_um = x_um;
    e->moves.face_y_um = y_um;
    e->moves.after_turn = (uint8_t)then;
    e->count.turns++;
    explore_enter(e, EXPLORE_FACE);
}

void explore_face_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    explore_frame_t f = explore_frame_of(pose);
    int32_t side;
    int32_t ahead = fix_frame_point(&f, e->moves.face_x_um, e->moves.face_y_um, &side);
    int32_t mag = side < 0 ? -side : side;
    if ((ahead > 0 && mag <= ahead / EXPLORE_FACE_DONE) ||
        e->machine.ticks > EXPLORE_TURN_MAX_TICKS) {
        explore_wall_forget(e);
        explore_enter(e, EXPLORE_LOOK);
        return;
    }
    int32_t speed = e->cfg.turn_mm_s;
    if (ahead > 0 && mag < ahead / 3) { /* within about 18°: slow down */
        speed = speed * 3 * (mag >> 8) / ((ahead >> 8) + 1);
        speed = speed < EXPLORE_TURN_MIN_MM_S ? EXPLORE_TURN_MIN_MM_S : speed;
    }
    int32_t dir = side > 0 || (side == 0 && ahead < 0) ? 1 : -1; /* left is counter-clockwise */
    target_mm_s[ODOM_LEFT] = -dir * speed;
    target_mm_s[ODOM_RIGHT] = dir * speed;
}

/* ---- looking and driving ---------------------------------------------------------------- */

bool explore_look_done(explore_t *e)
{
    /* One full pass of the sweep since standing still, then a pass over the memory and
     * the map that began after the last of its readings. */
    if (e->machine.readings < e->cfg.stops) {
        return false;
    }
    if (e->moves.look_mark == 0u) {
        e->moves.look_mark = e->machine.now;
        return false;
    }
    if (e->ahead.at <= e->moves.look_mark) {
        return false;
    }
    e->moves.look_mark = 0u;
    return true;
}

int32_t explore_speed_mm_s(const explore_t *e, int32_t ahead_um)
{
    /* A sonar that hears little (pings lost, faces at grazing angles) may not have heard
     * what is ahead: no faster than the share of the last sweep it heard. */
    int32_t cruise = e->cfg.cruise_mm_s;
    int32_t top = cruise;
    if (e->memory.echoes < EXPLORE_ECHOES_SURE) {
        top = EXPLORE_CRAWL_MM_S + (cruise - EXPLORE_CRAWL_MM_S) * (int32_t)e->memory.echoes /
                                       (int32_t)EXPLORE_ECHOES_SURE;
        top = top < cruise ? top : cruise;
    }
    if (ahead_um >= EXPLORE_SLOW_UM) {
        return top;
    }
    /* In millimetres every product fits 32 bits (no 64-bit division in the tick). */
    int32_t span = (EXPLORE_SLOW_UM - e->cfg.avoid_um) / 1000;
    int32_t near = (ahead_um - e->cfg.avoid_um) / 1000;
    near = near < 0 ? 0 : near;
    span = span < 1 ? 1 : span;
    int32_t v = EXPLORE_CRAWL_MM_S + (cruise - EXPLORE_CRAWL_MM_S) * near / span;
    return v < top ? v : top;
}

/* ---- the trail, stalls and backing off ------------------------------------------------ */

/* Wheels that stall while driving: stand, then back off along the trail. */
bool explore_stall(explore_t *e, const odom_pose_t *pose)
{
    explore_moves_t *mv = &e->moves;
    uint8_t s = e->machine.state;
    if (e->machine.blind || s == EXPLORE_HOLD || s == EXPLORE_STOP || s == EXPLORE_LOOK ||
        s == EXPLORE_DECIDE || s == EXPLORE_SEEK) {
        return false;
    }
    e->count.stalls++;
    e->memory.narrow = false;
    e->wall.door = false; /* an opening being measured or passed is given up */
    /* Reversing: what stopped it is behind, or a count stopped; stand, then go on backing
     * off (it ends after a few such stalls), or look. One wheel stopped while the other
     * turned: no body against anything (that stops both), a wheel or its count that
     * failed; backing off on that count would go blind, so stand, then look. */
    bool reversing = s == EXPLORE_BACK || s == EXPLORE_DOOR;
    if (mv->one_wheel) {
        mv->trust_from = e->machine.now + EXPLORE_DOUBT_TICKS;
    }
    if (reversing || mv->one_wheel) {
        mv->hold_back = s == EXPLORE_BACK;
        mv->holds = (uint8_t)(mv->holds + reversing);
        mv->after_turn = EXPLORE_FOLLOW;
        explore_enter(e, EXPLORE_HOLD);
        return true;
    }
    /* Whatever stopped the robot is just ahead of its body: remember it there. */
    explore_memory_put(e, pose->x_um + fix_mul_q30(e->cfg.clearance_um, fix_cos(pose->heading)),
                       pose->y_um + fix_mul_q30(e->cfg.clearance_um, fix_sin(pose->heading)));
    mv->leg_x_um = pose->x_um;
    mv->leg_y_um = pose->y_um;
    mv->back_left = mv->trail_len;
    mv->holds = 0u;
    mv->hold_back = true;
    explore_enter(e, EXPLORE_HOLD);
    return true;
}

void explore_hold_step(explore_t *e)
{
    if (e->machine.ticks > EXPLORE_HOLD_TICKS) {
        explore_enter(e, e->moves.hold_back ? EXPLORE_BACK : EXPLORE_LOOK);
    }
}

/*
 * Reverse toward the trail positions, newest first: the rear is turned toward the next
 * one in place when it is more than about 27° off, and steered onto it while reversing
 * otherwise. Without a trail (a stall at the start) the robot reverses straight.
 */
bool explore_back_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2])
{
    explore_moves_t *mv = &e->moves;
    if (mv->back_left == EXPLORE_BACK_PLACES) {
        escape_trail(mv, pose);
        return false; /* (the wheels at rest this tick) */
    }
    int64_t back = EXPLORE_BACK_UM;
    if ((mv->escaping
             ? mv->back_left == 0u
             : explore_dist2(pose, mv->leg_x_um, mv->leg_y_um) >= (uint64_t)(back * back)) ||
        e->machine.ticks > EXPLORE_TURN_MAX_TICKS || mv->holds > EXPLORE_HOLDS_MAX) {
        mv->escaping = false;
        mv->trail_len = 1u;
        mv->trail_x_um[mv->trail_head] = pose->x_um;
        mv->trail_y_um[mv->trail_head] = pose->y_um;
        return true;
    }
    int32_t v = -EXPLORE_BACK_MM_S;
    explore_frame_t f = explore_frame_of(pose);
    while (mv->back_left > 0u) {
        uint8_t i = (uint8_t)((mv->trail_head + EXPLORE_TRAIL - (mv->trail_len - mv->back_left)) %
                              EXPLORE_TRAIL);
        int32_t side;
        int32_t ahead = fix_frame_point(&f, mv->trail_x_um[i], mv->trail_y_um[i], &side);
        int32_t mag = side < 0 ? -side : side;
        if (ahead > -EXPLORE_BACK_REACHED_UM && mag < EXPLORE_BACK_REACHED_UM) {
            mv->back_left--; /* reached: on to the older one */
            continue;
        }
        /* Half the turning speed, but an escape's whole: bringing the rear round to the
         * first place took most of an escape's time (experiments.md). */
        int32_t turn = mv->escaping ? e->cfg.turn_mm_s : e->cfg.turn_mm_s / 2;
        if (ahead > 0 || 2 * mag > -ahead) {
            /* Bring the rear round to it: a point to the left swings the rear left,
             * which is a clockwise turn. */
            target_mm_s[ODOM_LEFT] = side > 0 ? turn : -turn;
            target_mm_s[ODOM_RIGHT] = -target_mm_s[ODOM_LEFT];
            return false;
        }
        int32_t steer = side / 1000 * EXPLORE_BACK_MM_S / (-ahead / 1000 + 1);
        target_mm_s[ODOM_LEFT] = v + steer;
        target_mm_s[ODOM_RIGHT] = v - steer;
        return false;
    }
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = v;
    return false;
}
