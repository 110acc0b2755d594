/* SPDX-License-Identifier: MIT */
/* What the exploration's source files share: state changes, the memory pass, the ways. */
#ifndef SLAM_EXPLORE_INTERNAL_H
#define SLAM_EXPLORE_INTERNAL_H

#include "slam/explore.h"
#include "slam/fixed.h"

#define EXPLORE_DEG(d) ((bam32_t)((uint64_t)(d) * 0x100000000ull / 360u))
#define EXPLORE_LOOK_UM 1000000 /* TM rays reach 1 m */
#define EXPLORE_MAP_REACH_UM 300000 /* the corridor is read on the map this far ahead */
#define EXPLORE_MAP_STOP_UM 250000  /* and an occupied cell this near ahead stops the robot */
/* The sonar is the robot's only sight: when no stop has heard an echo for a second (an
 * echo line stuck high, pings lost) the robot stands, for up to three seconds (a fault
 * that passes has passed by then; open space beyond the sonar's reach stays silent, and
 * the robot goes on into it). */
#define EXPLORE_DEAF_TICKS 100u
#define EXPLORE_DEAF_STAND_TICKS 300u
#define EXPLORE_CANDIDATE_BAM ((bam32_t)(0x100000000ull / EXPLORE_CANDIDATES))

/* A number below n from the exploration's own random stream. */
uint32_t explore_rng_below(explore_t *e, uint32_t n);

/* The integer square root of v (below 2^30: the squares stay in 32 bits). */
uint32_t explore_isqrt(uint32_t v);

/* The squared distance from a pose to a world point, defined for any two positions. */
uint64_t explore_dist2(const odom_pose_t *pose, int32_t x_um, int32_t y_um);

/* Enter a state: its tick count and look count start again. */
void explore_enter(explore_t *e, explore_state_t s);

/* Turn in place by a signed binary angle (left positive), then look and go on in
 * `then`. */
void explore_turn_by(explore_t *e, const odom_pose_t *pose, int32_t angle, explore_state_t then);

/* Stand still and weigh candidates first .. first + span - 1 (mod EXPLORE_CANDIDATES),
 * turning then to the best one; the weighing ends in `then`. */
void explore_decide(explore_t *e, uint8_t first, uint8_t span, explore_state_t then);

/* One tick of weighing (DECIDE). */
void explore_decide_step(explore_t *e, const odom_pose_t *pose, const grid_t *g);

/* The point of the last reading, noted in its tick, into the memory (in the next tick). */
void explore_remember(explore_t *e, const odom_pose_t *pose);

/* One slice of the pass over the memory and the map's corridor (with the held-back
 * obstacle ahead, explore_step()'s held). */
void explore_scan_slice(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                        const int32_t held[2]);

/* Begin a pass over the obstacle memory from a pose, facing the heading of cosine c and
 * sine s. */
void explore_scan_begin(explore_t *e, const odom_pose_t *pose, q1_30_t c, q1_30_t s);

/* Check the next EXPLORE_SCAN_POINTS points of the pass; true when the pass is complete
 * (its result then in e->scan_work). */
bool explore_scan_points(explore_t *e);

/* The corridor ahead on the map (explore_map.c): its size from the configuration, a
 * pass begun from a pose, then EXPLORE_MAP_CELLS cells a call; true when complete. */
void explore_map_init(explore_t *e, const slam_config_t *cfg);
/* A world coordinate in Q16 cells of the grid (n cells along it); -1 outside. The
 * fraction is taken to 1/256 of a cell, which keeps every product in 32 bits. */
int32_t explore_q16_cells(int32_t v_um, int32_t origin_um, uint32_t cell_um, uint32_t n);
void explore_map_begin(explore_t *e, const odom_pose_t *pose, const grid_t *g, q1_30_t c,
                       q1_30_t s);
bool explore_map_cells(explore_t *e, const grid_t *g);

/* The nearest point ahead in the corridor, remembered or on the map, from the sonar, as
 * of the last complete pass and less what the robot may have driven since (from where
 * the pass began to the pose); INT32_MAX if none. */
int32_t explore_ahead_um(const explore_t *e, const odom_pose_t *pose);

/* The forward speed for the nearest point ahead: cruise far from it, slower close to it. */
int32_t explore_speed_mm_s(const explore_t *e, int32_t ahead_um);

/* Walls mode. */
void explore_follow_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2]);
void explore_walls_look(explore_t *e, const odom_pose_t *pose, bool blocked);
void explore_walls_trail(explore_t *e, const odom_pose_t *pose, const grid_t *g);
void explore_walls_cross(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                         int32_t target_mm_s[2]);

/* The frontier of blocks (explore_seek.c). */
void explore_seek_init(explore_t *e);
void explore_seek_here(explore_t *e, grid_cell_t here);
void explore_seek_scan(explore_t *e, const grid_t *g);
void explore_seek(explore_t *e, const odom_pose_t *pose, const grid_t *g);
void explore_seek_step(explore_t *e, const odom_pose_t *pose, const grid_t *g);
/* Turn in place to face a world point, then look and go on in `then`. */
void explore_face(explore_t *e, int32_t x_um, int32_t y_um, explore_state_t then);
void explore_face_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);
int32_t explore_seek_steer(explore_t *e, const odom_pose_t *pose, const grid_t *g);

/* Openings in the wall on the right (explore_door.c). */
#define EXPLORE_DOOR_PAST_UM 150000 /* measured once the robot is this far past one */
/* A world point in the frame of the robot at a pose (NULL: where the last memory pass
 * began), facing the heading of the last pass: how far ahead of the axle (returned) and
 * to the left (in *side, if not NULL). */
int32_t explore_robot_frame(const explore_t *e, const odom_pose_t *pose, int32_t x_um,
                            int32_t y_um, int32_t *side);
void explore_walls_point(explore_t *e, const odom_pose_t *pose, int32_t x_um, int32_t y_um);
void explore_door_step(explore_t *e, const odom_pose_t *pose, const grid_t *g,
                       int32_t target_mm_s[2]);
void explore_pass_step(explore_t *e, const odom_pose_t *pose, int32_t target_mm_s[2]);
bool explore_door_nudge(explore_t *e, const odom_pose_t *pose);

#endif /* SLAM_EXPLORE_INTERNAL_H */
