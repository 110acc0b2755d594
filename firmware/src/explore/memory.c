/* SPDX-License-Identifier: MIT */
/* The exploration's obstacle memory: the points the sonar placed, and the pass over them
 * that tells what lies ahead and on the right, a few points a tick. */
#include "sight.h"

#define EXPLORE_SCAN_POINTS 4u         /* memory points checked a tick */
#define EXPLORE_RIGHT_BEHIND_UM 100000 /* walls: the right side from 0.1 m behind the axle */
#define EXPLORE_RIGHT_AHEAD_UM 400000  /* to 0.4 m ahead */
#define EXPLORE_RIGHT_WIDE_UM 1000000  /* and 1 m to the side */

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

void explore_memory_begin(explore_t *e, const explore_frame_t *f)
{
    e->memory.frame = *f;
    e->memory.work = (explore_scan_t){INT32_MAX, 0, INT32_MAX, INT32_MAX};
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
    for (uint32_t n = 0; n < EXPLORE_SCAN_POINTS && m->next < EXPLORE_POINTS; n++) {
        uint8_t i = m->next++;
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
    return m->next >= EXPLORE_POINTS;
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
