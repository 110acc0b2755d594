/* SPDX-License-Identifier: MIT */
/* The exploration's sight, above base.h: what the sonar heard and the obstacle points it
 * placed (memory.c), the corridor ahead on the map (corridor.c), the pass over both that
 * tells what is ahead and on the right (ahead.c), and the wall on the right (wall.c). */
#ifndef SLAM_EXPLORE_SIGHT_H
#define SLAM_EXPLORE_SIGHT_H

#include <stddef.h>

#include "base.h"

/* ---- memory.c ----------------------------------------------------------------------- */

#define EXPLORE_ECHO_WINDOW 12u /* readings whose echoes are counted: a sweep */
#define EXPLORE_ECHO_MASK ((1u << EXPLORE_ECHO_WINDOW) - 1u)
_Static_assert(EXPLORE_ECHO_WINDOW <= 16u, "memory.echo_bits holds the window");
#define EXPLORE_SLOW_UM 700000       /* what lies further ahead of the sonar does not matter */
#define EXPLORE_PASS_CLEAR_UM 105000 /* half the corridor through an opening (narrow) */
/* The sonar is the robot's only sight: when no stop has heard an echo for a second (an
 * echo line stuck high, pings lost) the robot stands, for up to three seconds (a fault
 * that passes has passed by then; open space beyond the sonar's reach stays silent, and
 * the robot goes on into it). */
#define EXPLORE_DEAF_TICKS 100u
#define EXPLORE_DEAF_STAND_TICKS 300u

/* A tick that completes a reading: its echo into the count of the last sweep's, and its
 * point, copied now (the background loop may map older readings, and change the
 * mapper's last outcome, before the next tick), to join the memory in the next tick.
 * Inline: such a tick carries the map update. */
static inline void explore_memory_note(explore_t *e, const sweep_out_t *sw, const mapper_t *m)
{
    explore_memory_t *mem = &e->memory;
    uint32_t echo = sw->reading.echo ? 1u : 0u;
    uint32_t out = (mem->echo_bits >> (EXPLORE_ECHO_WINDOW - 1u)) & 1u;
    mem->echoes = (uint8_t)(mem->echoes + echo - out);
    mem->echo_bits = (uint16_t)((((uint32_t)mem->echo_bits << 1) | echo) & EXPLORE_ECHO_MASK);
    if (echo) {
        mem->heard = e->machine.now;
        mem->deaf_stood = 0u;
    }
    mem->pending = echo && (m->last == MAPPER_HIT || m->last == MAPPER_OUTSIDE) ? 1u : 0u;
    mem->pending_x_um = m->last_x_um;
    mem->pending_y_um = m->last_y_um;
}

/* Deaf while driving on (FORWARD, FOLLOW, PASS): true when the robot stands this tick,
 * which it counts. A blind mode drives on regardless. */
static inline bool explore_memory_deaf(explore_t *e)
{
    uint8_t s = e->machine.state;
    if (e->machine.now - e->memory.heard > EXPLORE_DEAF_TICKS &&
        e->memory.deaf_stood < EXPLORE_DEAF_STAND_TICKS &&
        (s == EXPLORE_FORWARD || s == EXPLORE_FOLLOW || s == EXPLORE_PASS) && !e->machine.blind) {
        e->memory.deaf_stood++;
        return true;
    }
    return false;
}

/* The point of the last reading, noted in its tick, into the memory. */
void explore_memory_take(explore_t *e);

/* A world point into the memory, in place of the oldest. */
void explore_memory_put(explore_t *e, int32_t x_um, int32_t y_um);

/* Begin a pass over the memory in a frame. */
void explore_memory_begin(explore_t *e, const explore_frame_t *f);

/* Check the next few points of the pass; true when the pass is complete (its result
 * then in e->memory.work). */
bool explore_memory_points(explore_t *e);

/* ---- corridor.c --------------------------------------------------------------------- */

/* Its size, from the configuration. */
void explore_corridor_init(explore_t *e, const slam_config_t *cfg);

/* Begin reading it in a frame (the robot's at a pose). */
void explore_corridor_begin(explore_t *e, const grid_t *g, const explore_frame_t *f);

/* Read the next few cells; true when complete (the nearest occupied row in work_um). */
bool explore_corridor_cells(explore_t *e, const grid_t *g);

/* ---- ahead.c ------------------------------------------------------------------------ */

/* Nothing seen yet. */
void explore_ahead_init(explore_t *e);

/* One slice of the pass over the memory and the map's corridor, with the held-back
 * obstacle ahead (explore_step()'s held). True when the slice is the one a pass keeps
 * for the mode after it is complete (ahead.spare): the mode's to use. */
bool explore_pass_slice(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2]);

/* The next slice begins a new pass (the heading has just been chosen). */
static inline void explore_pass_restart(explore_t *e)
{
    e->ahead.phase = 0u;
}

/* The frame the points are measured in: at a pose (NULL: where the last complete pass
 * began), facing the heading of the last pass begun. */
static inline explore_frame_t explore_pass_frame(const explore_t *e, const odom_pose_t *pose)
{
    return (explore_frame_t){pose != NULL ? pose->x_um : e->ahead.ox_um,
                             pose != NULL ? pose->y_um : e->ahead.oy_um, e->memory.frame.cos,
                             e->memory.frame.sin};
}

/* The nearest point ahead in the corridor, remembered or on the map, from the sonar, as
 * of the last complete pass and less what the robot may have driven since (from where
 * the pass began to the pose); INT32_MAX if none. */
int32_t explore_ahead_um(const explore_t *e, const odom_pose_t *pose);

/* ---- wall.c ------------------------------------------------------------------------- */

#define EXPLORE_WALL_NEAR_UM 100000 /* a point of the wall on the right is 0.1 m or more */
#define EXPLORE_WALL_FAR_UM 150000  /* and up to 0.15 m beyond the follow distance aside */
#define EXPLORE_DOOR_MAX_UM 1000000 /* an opening at most this wide is passed */

/* A new point while following: is it on the wall, and does it open a gap? */
void explore_wall_point(explore_t *e, const odom_pose_t *pose, int32_t x_um, int32_t y_um);

/* What lay ahead along a wall is measured again (after a turn). */
static inline void explore_wall_forget(explore_t *e)
{
    e->wall.front = false;
    e->wall.door = false;
}

/* Following begins afresh: nothing has been missed beside yet. */
static inline void explore_wall_afresh(explore_t *e)
{
    e->wall.lost_um = 0u;
    e->wall.arc_ticks = 0u;
}

#endif /* SLAM_EXPLORE_SIGHT_H */
