/* SPDX-License-Identifier: MIT */
/* The exploration's obstacle memory: the points the sonar placed, and the pass over them
 * that tells what lies ahead and on the right, a few points a tick. */
#include "sight.h"

#define EXPLORE_SCAN_POINTS 4u        /* memory points checked a tick */
#define EXPLORE_RIGHT_BEHIND_UM 100000 /* walls: the right side from 0.1 m behind the axle */
#define EXPLORE_RIGHT_AHEAD_UM 400000  /* to 0.4 m ahead */
#define EXPLORE_RIGHT_WIDE_UM 1000000  /* and 1 m to the side */
/* A place left for want of progress is kept out of as a disc this wide about where the
 * robot stood: the nook it could not leave, and its mouth. */
#define EXPLORE_SPOT_UM 250000

void explore_memory_put(explore_t *e, int32_t x_um, int32_t y_um)
{
    explore_memory_t *m = &e->memory;
    uint8_t i = m->next_point;
    m->pt_x_um[i] = x_um;
    m->pt_y_um[i] = y_um;
    m->pt_seen[i] = e->machine.now;
    m->next_point = (uint8_t)((i + 1u) % EXPLORE_POINTS);
}

/* The point of the last reading, placed by the mapper inside the confidence sector, joins
 * the memory (in the tick after the reading: the mapper keeps it until the next one). */
void explore_memory_take(explore_t *e)
{
    e->memory.pending = 0u;
    explore_memory_put(e, e->memory.pending_x_um, e->memory.pending_y_um);
}

/* A new spot near one held moves it there: spots side by side would fence the robot in. */
void explore_memory_block(explore_t *e, int32_t x_um, int32_t y_um)
{
    explore_memory_t *m = &e->memory;
    uint8_t at = m->next_spot;
    for (uint8_t i = 0; i < m->spots; i++) {
        int32_t dx = (m->spot_x_um[i] - x_um) / 1024;
        int32_t dy = (m->spot_y_um[i] - y_um) / 1024;
        int32_t r = 2 * EXPLORE_SPOT_UM / 1024;
        if (dx * dx + dy * dy < r * r) {
            at = i;
        }
    }
    m->spot_x_um[at] = x_um;
    m->spot_y_um[at] = y_um;
    if (at == m->next_spot) {
        m->next_spot = (uint8_t)((m->next_spot + 1u) % EXPLORE_SPOTS);
        m->spots = (uint8_t)(m->spots < EXPLORE_SPOTS ? m->spots + 1u : EXPLORE_SPOTS);
    }
}

/*
 * A blocked spot in the pass: the corridor meets its disc when the centre lies ahead,
 * within clear + EXPLORE_SPOT_UM to either side; it is then as far ahead as the disc's
 * near edge. From inside the disc it is not in the way. A spot weighs against a way
 * (decide.c) but never stops the robot: spots beside a passage would close it.
 */
static void spot_in_pass(explore_memory_t *m, uint32_t i, int32_t clear)
{
    int32_t side;
    int32_t ahead = fix_frame_point(&m->frame, m->spot_x_um[i], m->spot_y_um[i], &side);
    int32_t reach = clear + EXPLORE_SPOT_UM;
    if (ahead <= 0 || side <= -reach || side >= reach) {
        return;
    }
    int32_t a = ahead / 1024;
    int32_t d = side / 1024;
    int32_t r = EXPLORE_SPOT_UM / 1024;
    if (ahead < EXPLORE_SPOT_UM && a * a + d * d < r * r) {
        return;
    }
    int32_t edge = ahead > EXPLORE_SPOT_UM ? ahead - EXPLORE_SPOT_UM : 1;
    m->work.spot_um = edge < m->work.spot_um ? edge : m->work.spot_um;
}

void explore_memory_begin(explore_t *e, const explore_frame_t *f)
{
    e->memory.frame = *f;
    e->memory.work = (explore_scan_t){INT32_MAX, 0, INT32_MAX, INT32_MAX, INT32_MAX};
    e->memory.next = 0u;
}

bool explore_memory_points(explore_t *e)
{
    explore_memory_t *m = &e->memory;
    explore_scan_t *w = &m->work;
    /* A remembered point lies within a few metres of the robot: its frame's differences
     * are exact. */
    explore_frame_t f = m->frame;
    int32_t clear = m->narrow ? EXPLORE_PASS_CLEAR_UM : e->cfg.clearance_um;
    bool right = m->right;
    for (uint32_t n = 0; n < EXPLORE_SCAN_POINTS && m->next < EXPLORE_POINTS + m->spots; n++) {
        uint8_t i = m->next++;
        if (i >= EXPLORE_POINTS) {
            spot_in_pass(m, i - EXPLORE_POINTS, clear);
            continue;
        }
        if (e->machine.now - m->pt_seen[i] > EXPLORE_MEMORY_TICKS || m->pt_seen[i] == 0u) {
            continue;
        }
        int32_t side;
        int32_t ahead = fix_frame_point(&f, m->pt_x_um[i], m->pt_y_um[i], &side);
        if (ahead <= -EXPLORE_RIGHT_BEHIND_UM || ahead >= EXPLORE_SLOW_UM + e->cfg.mount_x_um) {
            continue; /* behind the robot, or too far ahead to matter */
        }
        if (side > -clear && side < clear && ahead > 0 && ahead < w->ahead_um) {
            w->ahead_um = ahead;
            w->lateral_um = side;
        }
        if (right && side < 0 && side > -EXPLORE_RIGHT_WIDE_UM && ahead < EXPLORE_RIGHT_AHEAD_UM) {
            /* Walls mode keeps what is on the right at follow_um: the offset of what lies
             * beside and ahead; and, round a corner, the distance of what lies behind.
             * In 1.024 mm units the squares of the band's offsets fit 32 bits. */
            int32_t a = ahead / 1024;
            int32_t d = side / 1024;
            if (ahead >= 0) {
                w->right_q10 = d * d < w->right_q10 ? d * d : w->right_q10;
            } else if (a * a + d * d < w->behind_q10) {
                w->behind_q10 = a * a + d * d;
            }
        }
    }
    return m->next >= EXPLORE_POINTS + m->spots;
}

bool explore_blocked(const explore_t *e, const odom_pose_t *pose)
{
    explore_t copy = *e;
    explore_frame_t f = explore_frame_of(pose);
    explore_memory_begin(&copy, &f);
    while (!explore_memory_points(&copy)) {
    }
    return copy.memory.work.ahead_um != INT32_MAX &&
           copy.memory.work.ahead_um < e->cfg.mount_x_um + e->cfg.avoid_um;
}
