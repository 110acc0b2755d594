/* SPDX-License-Identifier: MIT */
/* EXPLORE_SQUARE: square_laps counter-clockwise squares of square_side by odometry
 * (UMBmark's path), turning in place at the corners, then stop. An odometry test, blind
 * by design: it runs no pass over the memory, so nothing is ever ahead of it, and it
 * drives its legs at cruise whatever the sonar hears. */
#include "modes.h"

void explore_square_init(explore_t *e)
{
    e->machine.blind = true;
    explore_enter(e, EXPLORE_FORWARD);
}

void explore_square_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2])
{
    (void)e, (void)pose, (void)g, (void)held;
}

/* Never reached: the square neither looks nor meets anything ahead nor backs off. */
void explore_square_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)
{
    (void)e, (void)pose, (void)why;
}

/* A leg is measured from where the last turn ended (moves.leg). */
void explore_square_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        int32_t target_mm_s[2])
{
    (void)g;
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = e->cfg.cruise_mm_s;
    int64_t side = e->cfg.square_side_um;
    if (explore_dist2(pose, e->moves.leg_x_um, e->moves.leg_y_um) < (uint64_t)(side * side)) {
        return;
    }
    e->square.legs++;
    if (e->cfg.laps != 0u && e->square.legs >= 4u * e->cfg.laps) {
        explore_enter(e, EXPLORE_STOP);
        target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    } else {
        /* Square corners are absolute: start heading + 90° per leg. */
        e->moves.target_heading += EXPLORE_DEG(90);
        e->count.turns++;
        explore_enter(e, EXPLORE_TURN);
    }
}

void explore_square_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2])
{
    (void)e, (void)pose, (void)g, (void)target_mm_s;
}
