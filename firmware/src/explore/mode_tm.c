/* SPDX-License-Identifier: MIT */
/* EXPLORE_TM: the random mode's avoidance, but every new heading is the way of the fewest
 * visits in TM (decide.c): at the start, after backing off, when something is ahead, and
 * every few seconds of driving. */
#include "modes.h"

#define EXPLORE_TM_REDECIDE_TICKS 600u /* weigh the ways again after 6 s */

/* Something ahead: weigh the ways from straight on to 150° left, so that what was ahead
 * ends on the right, where the sweep sees it (not straight back: a wall beside would
 * then be on the blind side). */
static void avoid(explore_t *e)
{
    e->tm.fresh = false;
    explore_decide(e, 0u, 6u, EXPLORE_FORWARD);
}

void explore_tm_init(explore_t *e)
{
    e->tm.fresh = true;
    explore_enter(e, EXPLORE_LOOK);
}

void explore_tm_job(explore_t *e, const odom_pose_t *pose, const grid_t *g, const int32_t held[2])
{
    if (e->machine.state == EXPLORE_LOOK || e->machine.state == EXPLORE_FORWARD) {
        (void)explore_pass_slice(e, pose, g, held);
    }
}

void explore_tm_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)
{
    (void)pose;
    switch (why) {
    case EXPLORE_WHY_CLEAR:
        if (e->tm.fresh) {
            e->tm.fresh = false;
            explore_decide(e, 0u, EXPLORE_CANDIDATES, EXPLORE_FORWARD);
        } else {
            explore_enter(e, EXPLORE_FORWARD);
        }
        break;
    case EXPLORE_WHY_BLOCKED:
    case EXPLORE_WHY_AHEAD:
        avoid(e);
        break;
    case EXPLORE_WHY_BACKED:
        e->tm.fresh = true;
        explore_enter(e, EXPLORE_LOOK);
        break;
    }
}

void explore_tm_way(explore_t *e, const odom_pose_t *pose, const grid_t *g, int32_t target_mm_s[2])
{
    (void)pose, (void)g, (void)target_mm_s;
    if (e->machine.ticks > EXPLORE_TM_REDECIDE_TICKS) {
        /* On the way: within 60° either side, so that a wall beside is not turned onto
         * the blind side. */
        e->tm.fresh = false;
        explore_decide(e, EXPLORE_CANDIDATES - 2u, 5u, EXPLORE_FORWARD);
    }
}

void explore_tm_step(explore_t *e, const odom_pose_t *pose, const grid_t *g, int32_t target_mm_s[2])
{
    (void)e, (void)pose, (void)g, (void)target_mm_s;
}
