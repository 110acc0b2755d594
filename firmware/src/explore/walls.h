/* SPDX-License-Identifier: MIT */
/* The walls mode's parts, above moves.h and below mode_walls.c: the frontier at the
 * scale of blocks of cells and crossing to it (seek.c), and openings in the wall on the
 * right, measured on the map and passed through their middle (door.c). */
#ifndef SLAM_EXPLORE_WALLS_H
#define SLAM_EXPLORE_WALLS_H

#include "moves.h"
#include "way.h"

/* The ways to the left, 30° to 150° (decide.c's candidates 1 to 5): not straight back,
 * which would put the wall just left on the blind side. */
#define EXPLORE_LEFT_FIRST 1u
#define EXPLORE_LEFT_SPAN 5u

/* 45° left turns in a row, each looked along and blocked (a circle): boxed in. */
#define EXPLORE_LEFTS_MAX 8u

/* ---- seek.c ------------------------------------------------------------------------- */

/* No block is sought yet. */
void explore_seek_init(explore_t *e);

/* The robot stands in a cell: its block is explored (and reached, if it was sought). */
void explore_seek_here(explore_t *e, grid_cell_t here);

/* A few cells of the rolling scan that marks the blocks holding a known free cell. */
void explore_seek_scan(explore_t *e, const grid_t *g);

/* Begin seeking: stand, and weigh the frontier blocks from the robot's cell. */
void explore_seek(explore_t *e, const odom_pose_t *pose, const grid_t *g);

/* SEEK: a tick of the search; it ends facing a block in sight, or weighing the ways. */
void explore_seek_step(explore_t *e, const odom_pose_t *pose, const grid_t *g);

/* Crossing toward the target block: the steer toward it (positive turns right); a new
 * search once it is reached, behind, or overdue. */
int32_t explore_seek_steer(explore_t *e, const odom_pose_t *pose, const grid_t *g);

/* ---- door.c ------------------------------------------------------------------------- */

/* Well past an opening on the right (wall.door): stand, and measure it (DOOR). */
void explore_door_begin(explore_t *e);

/* DOOR: read the wall on the map, back up abreast of the middle, face it. */
void explore_door_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                       int32_t target_mm_s[2]);

/* Facing an opening, something is ahead: correct its middle once, if an edge is the
 * cause (true: the robot turns to get abreast of it again); false when it is no opening. */
bool explore_door_nudge(explore_t *e, const odom_pose_t *pose);

/* Facing an opening with the way clear: pass it from here. */
void explore_pass_begin(explore_t *e, const odom_pose_t *pose);

/* PASS: straight through the opening, then turn right to follow its far side. */
void explore_pass_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);

#endif /* SLAM_EXPLORE_WALLS_H */
