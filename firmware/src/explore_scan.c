/* SPDX-License-Identifier: MIT */
/* The exploration's obstacle memory and the pass over it and the map's corridor that
 * tells what is ahead and on the right, a slice a tick. */
#include "explore_internal.h"
#include "slam/localize.h"

#define EXPLORE_RIGHT_BEHIND_UM 100000    /* walls: the right side from 0.1 m behind the axle */
#define EXPLORE_RIGHT_AHEAD_UM 400000     /* to 0.4 m ahead */
#define EXPLORE_RIGHT_WIDE_UM 1000000     /* and 1 m to the side */
#define EXPLORE_CRAWL_MM_S 60             /* the slowest approach */

/* The point of the last reading, placed by the mapper inside the confidence sector, joins
 * the memory (in the tick after the reading: the mapper keeps it until the next one). */
void explore_remember(explore_t *e, const odom_pose_t *pose)
{
    e->pending = 0u;
    uint8_t i = e->next_point;
    e->pt_x_um[i] = e->pending_x_um;
    e->pt_y_um[i] = e->pending_y_um;
    e->pt_seen[i] = e->now;
    e->next_point = (uint8_t)((i + 1u) % EXPLORE_POINTS);
    if (e->state == EXPLORE_FOLLOW) {
        explore_walls_point(e, pose, e->pending_x_um, e->pending_y_um);
    }
}

void explore_scan_begin(explore_t *e, const odom_pose_t *pose, q1_30_t c, q1_30_t s)
{
    e->scan_cos = c;
    e->scan_sin = s;
    e->scan_x_um = pose->x_um;
    e->scan_y_um = pose->y_um;
    e->scan_work = (explore_scan_t){INT32_MAX, 0, INT32_MAX, INT32_MAX};
    e->scan_next = 0u;
}

bool explore_scan_points(explore_t *e)
{
    explore_scan_t *w = &e->scan_work;
    q1_30_t c = e->scan_cos;
    q1_30_t s = e->scan_sin;
    int32_t clear = e->narrow ? EXPLORE_PASS_CLEAR_UM : e->clearance_um;
    bool right = e->mode == EXPLORE_WALLS;
    for (uint32_t n = 0; n < EXPLORE_SCAN_POINTS && e->scan_next < EXPLORE_POINTS; n++) {
        uint8_t i = e->scan_next++;
        if (e->now - e->pt_seen[i] > EXPLORE_MEMORY_TICKS || e->pt_seen[i] == 0u) {
            continue;
        }
        /* The point in the robot frame. A remembered point lies within a few metres of the
         * robot, so the differences fit 32 bits (taken modulo 2^32, which is exact here),
         * and the 32 x 32-bit products (one SMULL each on a Cortex-M4) fit 64. */
        int32_t dx = (int32_t)((uint32_t)e->pt_x_um[i] - (uint32_t)e->scan_x_um);
        int32_t dy = (int32_t)((uint32_t)e->pt_y_um[i] - (uint32_t)e->scan_y_um);
        int32_t ahead = (int32_t)(((int64_t)dx * c + (int64_t)dy * s) >> 30);
        if (ahead <= -EXPLORE_RIGHT_BEHIND_UM || ahead >= EXPLORE_SLOW_UM + e->mount_x_um) {
            continue; /* behind the robot, or too far ahead to matter */
        }
        int32_t side = (int32_t)(((int64_t)dy * c - (int64_t)dx * s) >> 30);
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
    return e->scan_next >= EXPLORE_POINTS;
}

/* How far ahead of the axle, at the pass's pose, the held-back obstacle lies when it is in
 * the corridor (INT32_MAX when not): it counts as the map's occupied cells do. */
static int32_t held_ahead_um(const explore_t *e, const int32_t held[2])
{
    if (held[0] == LOC_AHEAD_NONE) {
        return INT32_MAX;
    }
    int32_t dx = (int32_t)((uint32_t)held[0] - (uint32_t)e->scan_x_um);
    int32_t dy = (int32_t)((uint32_t)held[1] - (uint32_t)e->scan_y_um);
    int32_t ahead = (int32_t)(((int64_t)dx * e->scan_cos + (int64_t)dy * e->scan_sin) >> 30);
    int32_t side = (int32_t)(((int64_t)dy * e->scan_cos - (int64_t)dx * e->scan_sin) >> 30);
    int32_t clear = e->clearance_um;
    return ahead > 0 && side > -clear && side < clear ? ahead : INT32_MAX;
}

/*
 * One slice of the pass over the memory and the corridor on the map that runs while the
 * robot looks and drives: its beginning, the memory points, the map's corridor, and (in
 * walls mode) a step of the rolling scan of the frontier, a slice a tick.
 */
void explore_scan_slice(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2])
{
    switch (e->scan_phase) {
    case 0: {
        q1_30_t c = fix_cos(pose->heading);
        q1_30_t s = fix_sin(pose->heading);
        explore_scan_begin(e, pose, c, s);
        explore_map_begin(e, pose, g, c, s);
        e->scan_begun = e->now;
        e->scan_phase = 1u;
        break;
    }
    case 1:
        if (explore_scan_points(e)) {
            e->scan_phase = 2u;
        }
        break;
    case 2:
        if (explore_map_cells(e, g)) {
            e->scan = e->scan_work;
            int32_t h = held_ahead_um(e, held);
            e->map_um = h < e->map_work_um ? h : e->map_work_um;
            e->scan_at = e->scan_begun;
            e->scan_ox_um = e->scan_x_um;
            e->scan_oy_um = e->scan_y_um;
            e->scan_phase = e->mode == EXPLORE_WALLS ? 3u : 0u;
        }
        break;
    default:
        explore_seek_scan(e, g);
        e->scan_phase = 0u;
        break;
    }
}

int32_t explore_ahead_um(const explore_t *e, const odom_pose_t *pose)
{
    int32_t ahead = e->scan.ahead_um == INT32_MAX ? INT32_MAX : e->scan.ahead_um - e->mount_x_um;
    /* The map holds more than the memory (walls seen long ago, and what the sonar's cone
     * smeared), so it stops the robot only nearer: an occupied cell EXPLORE_MAP_STOP_UM
     * ahead of the axle counts as a point avoid_um ahead of the sonar. */
    if (!e->narrow && e->map_um != INT32_MAX &&
        e->map_um - EXPLORE_MAP_STOP_UM + e->avoid_um < ahead) {
        ahead = e->map_um - EXPLORE_MAP_STOP_UM + e->avoid_um;
    }
    if (ahead == INT32_MAX) {
        return INT32_MAX;
    }
    /* The pass measured from where the robot was when it began; since then it has come
     * at most |dx| + |dy| nearer. */
    int32_t dx = (int32_t)((uint32_t)pose->x_um - (uint32_t)e->scan_ox_um);
    int32_t dy = (int32_t)((uint32_t)pose->y_um - (uint32_t)e->scan_oy_um);
    int64_t left = (int64_t)ahead - (dx < 0 ? -(int64_t)dx : dx) - (dy < 0 ? -(int64_t)dy : dy);
    return left < INT32_MIN ? INT32_MIN : (int32_t)left;
}

int32_t explore_speed_mm_s(const explore_t *e, int32_t ahead_um)
{
    /* A sonar that hears little (pings lost, faces at grazing angles) may not have heard
     * what is ahead: no faster than the share of the last sweep it heard. */
    int32_t top = e->cruise_mm_s;
    if (e->echoes < EXPLORE_ECHOES_SURE) {
        top = EXPLORE_CRAWL_MM_S + (e->cruise_mm_s - EXPLORE_CRAWL_MM_S) * (int32_t)e->echoes /
                                       (int32_t)EXPLORE_ECHOES_SURE;
        top = top < e->cruise_mm_s ? top : e->cruise_mm_s;
    }
    if (ahead_um >= EXPLORE_SLOW_UM) {
        return top;
    }
    /* In millimetres every product fits 32 bits (no 64-bit division in the tick). */
    int32_t span = (EXPLORE_SLOW_UM - e->avoid_um) / 1000;
    int32_t near = (ahead_um - e->avoid_um) / 1000;
    near = near < 0 ? 0 : near;
    span = span < 1 ? 1 : span;
    int32_t v = EXPLORE_CRAWL_MM_S + (e->cruise_mm_s - EXPLORE_CRAWL_MM_S) * near / span;
    return v < top ? v : top;
}

bool explore_blocked(const explore_t *e, const odom_pose_t *pose)
{
    explore_t copy = *e;
    explore_scan_begin(&copy, pose, fix_cos(pose->heading), fix_sin(pose->heading));
    while (!explore_scan_points(&copy)) {
    }
    return copy.scan_work.ahead_um != INT32_MAX &&
           copy.scan_work.ahead_um < e->mount_x_um + e->avoid_um;
}
