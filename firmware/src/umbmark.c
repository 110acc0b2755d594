/* SPDX-License-Identifier: MIT */
/* UMBmark: the bidirectional square test, n runs each way by odometry, a pause after each. */
#include "slam/umbmark.h"

#include <string.h>

#define UMB_QUARTER 0x40000000 /* 90° */
/* A leg turns back to its heading four times as fast as a turn ends: speeds are whole
 * mm/s, and a slower hold would leave errors under 1° uncorrected. */
#define UMB_STEER_SHIFT 14u

void umbmark_init(umbmark_t *u, const slam_config_t *cfg)
{
    memset(u, 0, sizeof *u);
    u->on = cfg->explore_mode == EXPLORE_UMBMARK;
    u->runs = cfg->umbmark_runs;
    u->pause_ticks = (uint32_t)cfg->umbmark_pause_s * (1000000u / SLAM_TICK_US);
    u->side_um = (int32_t)cfg->square_side_um;
    u->cruise_mm_s = cfg->cruise_mm_s;
    u->turn_mm_s = cfg->turn_mm_s;
    /* A wheel at v stops in v²/2a; a speed of v = d·a/cruise (d to go) never asks more
     * than the acceleration limit to slow down, and comes to rest at the end. */
    uint32_t brake = ((uint32_t)cfg->accel_mm_s2 << 16) / (cfg->cruise_mm_s * 1000u);
    u->brake_q16 = brake > 0u ? brake : 1u;
    u->arc_um = cfg->wheel_base_um * 3217u >> 10; /* π·b, π within 3e-6: for speeds */
    u->stop_um = UMB_CRAWL_MM_S * UMB_CRAWL_MM_S * 500 / cfg->accel_mm_s2; /* v²/2a */
    u->start =
        (odom_pose_t){cfg->start_x_um, cfg->start_y_um, fix_bam_from_mdeg(cfg->start_heading_mdeg)};
}

static void enter(umbmark_t *u, umb_state_t s)
{
    u->state = (uint8_t)s;
    u->ticks = 0u;
}

/* The speed that brings a wheel to rest @p left_um from here: at least a crawl, at most
 * @p max_mm_s. */
static int32_t slow_down(const umbmark_t *u, int32_t left_um, int32_t max_mm_s)
{
    int64_t v = ((int64_t)left_um * u->brake_q16) >> 16;
    v = v < UMB_CRAWL_MM_S ? UMB_CRAWL_MM_S : v;
    return v > max_mm_s ? max_mm_s : (int32_t)v;
}

static void begin_leg(umbmark_t *u, int32_t x_um, int32_t y_um)
{
    u->leg_x_um = x_um;
    u->leg_y_um = y_um;
    u->leg_c = fix_cos(u->heading);
    u->leg_s = fix_sin(u->heading);
    enter(u, UMB_LEG);
}

/* Come to rest first: a turn begun while the wheels still roll forward would carry the
 * robot on by their ramps. */
static void stop_then(umbmark_t *u, umb_state_t next)
{
    u->next = (uint8_t)next;
    enter(u, UMB_STOP);
}

bool umbmark_step(umbmark_t *u, const odom_pose_t *p, int32_t target_mm_s[2])
{
    target_mm_s[ODOM_LEFT] = target_mm_s[ODOM_RIGHT] = 0;
    u->ticks++;
    bool moved =
        p->x_um != u->last.x_um || p->y_um != u->last.y_um || p->heading != u->last.heading;
    u->last = *p;
    int32_t dir = umbmark_run_cw(u, u->run) ? -1 : 1; /* counter-clockwise: turn left */
    /* How far each wheel would roll to turn the robot in place to the leg's heading. */
    int32_t arc = (int32_t)(((int64_t)fix_bam_diff(u->heading, p->heading) * u->arc_um) >> 32);
    switch (u->state) {
    case UMB_PAUSE:
        if (u->ticks < u->pause_ticks) {
            break;
        }
        if (u->run >= 2u * u->runs) {
            enter(u, UMB_DONE);
            break;
        }
        u->run++;
        u->legs = 0u;
        u->heading = u->start.heading;
        begin_leg(u, u->start.x_um, u->start.y_um);
        return true;
    case UMB_LEG: {
        /* Along the leg, as the square mode measures its legs: differences modulo 2^32, exact
         * within 2 km; the projection fits 32 bits as long as the side does. */
        int32_t dx = (int32_t)((uint32_t)p->x_um - (uint32_t)u->leg_x_um);
        int32_t dy = (int32_t)((uint32_t)p->y_um - (uint32_t)u->leg_y_um);
        int64_t left = u->side_um - (((int64_t)dx * u->leg_c + (int64_t)dy * u->leg_s) >> 30);
        if (left <= u->stop_um) {
            u->legs++;
            u->heading += (bam32_t)(dir * UMB_QUARTER);
            stop_then(u, UMB_TURN);
            break;
        }
        /* Hold the leg's heading: the difference of speeds that turns back to it as the
         * end of a turn would. */
        int32_t v = slow_down(u, (int32_t)(left < INT32_MAX ? left : INT32_MAX), u->cruise_mm_s);
        int32_t w = (int32_t)(((int64_t)arc * u->brake_q16) >> UMB_STEER_SHIFT);
        target_mm_s[ODOM_LEFT] = v - w;
        target_mm_s[ODOM_RIGHT] = v + w;
        break;
    }
    case UMB_TURN:
        if (dir * arc <= u->stop_um) {
            /* Turned far enough; after the fourth corner the run is over. */
            stop_then(u, u->legs >= 4u ? UMB_PAUSE : UMB_LEG);
            break;
        }
        target_mm_s[ODOM_RIGHT] = dir * slow_down(u, dir * arc, u->turn_mm_s);
        target_mm_s[ODOM_LEFT] = -target_mm_s[ODOM_RIGHT];
        break;
    case UMB_STOP:
        if (moved) {
            u->ticks = 0u;
        } else if (u->ticks >= UMB_STILL_TICKS) {
            if (u->next == UMB_LEG) {
                begin_leg(u, p->x_um, p->y_um);
            } else {
                enter(u, (umb_state_t)u->next);
            }
        }
        break;
    default:
        break;
    }
    return false;
}
