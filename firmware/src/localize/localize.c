/* SPDX-License-Identifier: MIT */
/* Pose correction, the background loop's side: each reading mapped, its hit held back and
 * matched, and the result published for the tick (loc_tick.c adopts it). */
#include "slam/localize.h"

#include "loc_filter.h"
#include "loc_hold.h"
#include "loc_match.h"
#include "loc_tick.h"
#include "slam/sonar.h"

void loc_reading(loc_t *l, mapper_t *m, grid_t *g, const readq_reading_t *rd)
{
    loc_filter_move(&l->filter, &rd->ping);
    odom_pose_t at = loc_apply(&l->filter.corr, &rd->ping);
    int32_t x;
    int32_t y;
    if (!rd->echo) {
        mapper_timeout(m, g, &at);
    } else if (mapper_free(m, g, &at, rd->servo, rd->range_um, &x, &y) == MAPPER_HIT) {
        /* Held back in the odometry frame; one just behind a wall the map holds is matched
         * (it says where the pose is wrong) but never mapped (mapper.c, faces()). */
        bool shadowed = m->shadowed;
        sonar_obstacle(&m->sonar, &rd->ping, rd->servo, rd->range_um, &x, &y);
        if (loc_hold_add(&l->hold, m, g, &l->filter.corr, x, y, shadowed)) {
            loc_match_hit(l, g, &rd->ping);
        }
    }
    int32_t ahead[2];
    loc_hold_ahead(&l->hold, g, &l->filter.corr, &rd->ping, ahead);
    loc_tick_publish(&l->tick, &l->filter.corr, ahead);
}

void loc_flush(loc_t *l, mapper_t *m, grid_t *g)
{
    loc_hold_flush(&l->hold, m, g, &l->filter.corr);
}
