/* SPDX-License-Identifier: MIT */
/* EXPLORE_RANDOM, the paper's: drive straight; when something is ahead, turn away from
 * it by a random 90°..180°; now and then, and after driving straight too long, turn by a
 * random angle anyway. */
#include "modes.h"

#define EXPLORE_FORWARD_MAX_TICKS 2000u /* turn anyway after 20 s straight */
#define EXPLORE_RANDOM_TURN_MASK 1023u  /* a random turn on average every 10 s */

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
    return e->ahead.scan.lateral_um > 0 ? -1 : 1;
}

void explore_random_init(explore_t *e)
{
    explore_enter(e, EXPLORE_LOOK);
}

void explore_random_job(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2])
{
    if (e->machine.state == EXPLORE_LOOK || e->machine.state == EXPLORE_FORWARD) {
        (void)explore_pass_slice(e, pose, g, held);
    }
}

void explore_random_next(explore_t *e, const odom_pose_t *pose, explore_why_t why)
{
    switch (why) {
    case EXPLORE_WHY_CLEAR:
        explore_enter(e, EXPLORE_FORWARD);
        break;
    case EXPLORE_WHY_BLOCKED:
    case EXPLORE_WHY_AHEAD:
        random_turn(e, pose, EXPLORE_DEG(90), away(e));
        break;
    case EXPLORE_WHY_BACKED:
        random_turn(e, pose, EXPLORE_DEG(90), 0);
        break;
    }
}

void explore_random_way(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        int32_t target_mm_s[2])
{
    (void)g, (void)target_mm_s;
    if (e->machine.ticks > EXPLORE_FORWARD_MAX_TICKS ||
        explore_rng_below(e, EXPLORE_RANDOM_TURN_MASK + 1u) == 0u) {
        random_turn(e, pose, EXPLORE_DEG(30), 0);
    }
}

void explore_random_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2])
{
    (void)e, (void)pose, (void)g, (void)target_mm_s;
}
