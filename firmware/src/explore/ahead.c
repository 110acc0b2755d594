/* SPDX-License-Identifier: MIT */
/* What is ahead and on the right: the pass over the obstacle memory and the map's
 * corridor that runs while the robot looks and drives, a slice a tick, and what the last
 * complete pass says now. */
#include "sight.h"
#include "slam/localize.h"

#define EXPLORE_MAP_STOP_UM 250000 /* an occupied cell this near ahead stops the robot */

void explore_ahead_init(explore_t *e)
{
    e->ahead.scan.ahead_um = INT32_MAX;
    e->ahead.scan.right_q10 = INT32_MAX;
    e->ahead.scan.behind_q10 = INT32_MAX;
    e->ahead.map_um = INT32_MAX;
}

/* How far ahead of the axle, in the pass's frame, the held-back obstacle lies when it is
 * in the corridor (INT32_MAX when not): it counts as the map's occupied cells do. */
static int32_t held_ahead_um(const explore_t *e, const int32_t held[2])
{
    if (held[0] == LOC_AHEAD_NONE) {
        return INT32_MAX;
    }
    int32_t side;
    int32_t ahead = fix_frame_point(&e->memory.frame, held[0], held[1], &side);
    int32_t clear = e->cfg.clearance_um;
    return ahead > 0 && side > -clear && side < clear ? ahead : INT32_MAX;
}

/*
 * The slices of a pass: its beginning, the memory points, the map's corridor, and (when
 * the mode keeps one) a spare slice for the mode.
 */
bool explore_pass_slice(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2])
{
    explore_ahead_t *a = &e->ahead;
    switch (a->phase) {
    case 0: {
        explore_frame_t f = explore_frame_of(pose);
        explore_memory_begin(e, &f);
        explore_corridor_begin(e, g, &f);
        a->begun = e->machine.now;
        a->phase = 1u;
        break;
    }
    case 1:
        if (explore_memory_points(e)) {
            a->phase = 2u;
        }
        break;
    case 2:
        if (explore_corridor_cells(e, g)) {
            a->scan = e->memory.work;
            int32_t h = held_ahead_um(e, held);
            a->map_um = h < e->corridor.work_um ? h : e->corridor.work_um;
            a->at = a->begun;
            a->ox_um = e->memory.frame.x_um;
            a->oy_um = e->memory.frame.y_um;
            a->phase = a->spare ? 3u : 0u;
        }
        break;
    default:
        a->phase = 0u;
        return true;
    }
    return false;
}

int32_t explore_ahead_um(const explore_t *e, const odom_pose_t *pose)
{
    const explore_ahead_t *a = &e->ahead;
    int32_t ahead =
        a->scan.ahead_um == INT32_MAX ? INT32_MAX : a->scan.ahead_um - e->cfg.mount_x_um;
    /* The map holds more than the memory (walls seen long ago, and what the sonar's cone
     * smeared), so it stops the robot only nearer: an occupied cell EXPLORE_MAP_STOP_UM
     * ahead of the axle counts as a point avoid_um ahead of the sonar. */
    if (!e->memory.narrow && a->map_um != INT32_MAX &&
        a->map_um - EXPLORE_MAP_STOP_UM + e->cfg.avoid_um < ahead) {
        ahead = a->map_um - EXPLORE_MAP_STOP_UM + e->cfg.avoid_um;
    }
    if (ahead == INT32_MAX) {
        return INT32_MAX;
    }
    /* The pass measured from where the robot was when it began; since then it has come
     * at most |dx| + |dy| nearer. */
    int32_t dx = (int32_t)((uint32_t)pose->x_um - (uint32_t)a->ox_um);
    int32_t dy = (int32_t)((uint32_t)pose->y_um - (uint32_t)a->oy_um);
    int64_t left = (int64_t)ahead - (dx < 0 ? -(int64_t)dx : dx) - (dy < 0 ? -(int64_t)dy : dy);
    return left < INT32_MIN ? INT32_MIN : (int32_t)left;
}
