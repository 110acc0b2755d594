/* SPDX-License-Identifier: MIT */
/* The wall on the right while the walls mode follows it: its furthest point, and an
 * opening in it, from the sonar's points as they come. */
#include "sight.h"

#define EXPLORE_WALL_OFF_UM 100000 /* a point of the wall lies within 0.1 m of its line */
#define EXPLORE_DOOR_MIN_UM 180000 /* an opening seen this wide or wider is measured */

/*
 * A new point while following: is it on the wall to the right, and does it lie further
 * along than the furthest so far by an opening's width? The sweep's right stops find the
 * wall every few centimetres of travel, so a stretch without points is an opening. Its
 * exact edges are read from the map once the robot is past it (door.c).
 */
void explore_wall_point(explore_t *e, const odom_pose_t *pose, int32_t x_um, int32_t y_um)
{
    explore_wall_t *w = &e->wall;
    explore_frame_t f = explore_pass_frame(e, pose);
    int32_t side;
    int32_t ahead = fix_frame_point(&f, x_um, y_um, &side);
    if (side > -EXPLORE_WALL_NEAR_UM || side < -(e->cfg.follow_um + EXPLORE_WALL_FAR_UM) ||
        ahead < 0 || ahead > EXPLORE_DOOR_MAX_UM) {
        return;
    }
    if (w->front) {
        int32_t front_side;
        int32_t front = fix_frame_point(&f, w->front_x_um, w->front_y_um, &front_side);
        int32_t off = side - front_side;
        off = off < 0 ? -off : off;
        if (ahead <= front || off >= EXPLORE_WALL_OFF_UM) {
            return; /* behind the front, or not on the wall's line (a jamb's far corner) */
        }
        if (!w->door && ahead - front >= EXPLORE_DOOR_MIN_UM &&
            ahead - front <= EXPLORE_DOOR_MAX_UM) {
            w->door = true;
            w->edge_x_um = w->front_x_um;
            w->edge_y_um = w->front_y_um;
            w->far_x_um = x_um;
            w->far_y_um = y_um;
        }
    }
    w->front = true;
    w->front_x_um = x_um;
    w->front_y_um = y_um;
}
