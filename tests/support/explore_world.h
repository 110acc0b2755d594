/* SPDX-License-Identifier: MIT */
/* The exploration's tests' world: an ideal robot, straight walls, a sonar that sees them. */
#ifndef TEST_EXPLORE_WORLD_H
#define TEST_EXPLORE_WORLD_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "slam/explore.h"
#include "slam/localize.h"

#define EW_PI 3.14159265358979323846
#define EW_WALLS 16
#define EW_TIMEOUT (-1.0)    /* tick()'s range_mm: the ping timed out, no echo */
#define EW_NO_READING (-2.0) /* tick()'s range_mm: no reading completes in this tick */

/* The robot's state and the world. Positions in µm, the heading in radians. */
static slam_config_t cfg;
static explore_t ex;
static mapper_t mapper;
static grid_t grid;
static bool stalled; /* what motion_stalled() says in the next tick */
static double px, py, pth;
static int32_t target[2];
/* The held-back obstacle ahead that exploration is told of (none unless a test sets it). */
static int32_t world_held[2] = {LOC_AHEAD_NONE, 0};
static double walls[EW_WALLS][4]; /* x1, y1, x2, y2 in µm */
static unsigned nwalls;
static unsigned world_ticks; /* ticks run by world_tick() */
static unsigned world_seq;   /* position in the sweep's back-and-forth cycle */

static odom_pose_t pose(void)
{
    double th = fmod(pth, 2.0 * EW_PI);
    th = th < 0 ? th + 2.0 * EW_PI : th;
    return (odom_pose_t){(int32_t)lround(px), (int32_t)lround(py),
                         (bam32_t)(uint64_t)llround(th / (2.0 * EW_PI) * 4294967296.0)};
}

/* An ideal robot: the wheels do exactly what the exploration asks. */
static void move(void)
{
    double vl = target[0] * 10.0; /* µm per tick */
    double vr = target[1] * 10.0;
    double dth = (vr - vl) / cfg.wheel_base_um;
    double du = (vl + vr) / 2.0;
    px += du * cos(pth + dth / 2.0);
    py += du * sin(pth + dth / 2.0);
    pth += dth;
}

/* OM bytes that grid_state() reads as occupied and as free in the grid's mode. */
static inline uint8_t ew_om_occupied(void)
{
    return grid.mode == OM_MODE_EVIDENCE ? (uint8_t)(GRID_EVIDENCE_ZERO + 72u) : 1u;
}

static inline uint8_t ew_om_free(void)
{
    return grid.mode == OM_MODE_EVIDENCE ? (uint8_t)(GRID_EVIDENCE_ZERO - 28u) : 0u;
}

static void setup_mode(uint8_t mode)
{
    slam_config_default(&cfg);
    /* The readings tick() makes are at the paper's six stops. */
    cfg.sweep_first_mdeg = 65000;
    cfg.sweep_last_mdeg = 155000;
    cfg.sweep_stops = 6u;
    cfg.explore_mode = mode;
    explore_init(&ex, &cfg);
    mapper_init(&mapper, &cfg);
    grid_init(&grid, &cfg);
    px = py = pth = 0.0;
    target[0] = target[1] = 0;
    world_held[0] = LOC_AHEAD_NONE;
    stalled = false;
    nwalls = 0u;
    world_ticks = 0u;
    world_seq = 0u;
}

/* One tick; a reading at a stop (servo 65 + 18·stop degrees) when range_mm >= 0, a
 * timeout when range_mm is EW_TIMEOUT, none when EW_NO_READING. The mapper places the
 * reading's point and counts TM, as robot_tick() does. */
static void tick(int stop, double range_mm)
{
    sweep_out_t sw = {0};
    odom_pose_t p = pose();
    if (range_mm != EW_NO_READING) {
        sw.reading_ready = true;
        sw.reading.stop = (uint8_t)stop;
        sw.reading.servo_mdeg = 65000 + 18000 * stop;
        sw.reading.servo = fix_bam_from_mdeg(sw.reading.servo_mdeg);
        sw.reading.echo = range_mm >= 0.0;
        sw.reading.echo_us = sw.reading.echo ? (uint32_t)lround(range_mm * 1000.0 / 171.5) : 0u;
        mapper.ping_pose = p;
    }
    mapper_tick(&mapper, &grid, &p, &sw);
    explore_step(&ex, &p, &sw, &mapper, &grid, world_held, stalled, target);
    move();
}

/* A tick in which no reading completes. */
static void quiet_tick(void)
{
    tick(0, EW_NO_READING);
}

static void add_wall(double x1_m, double y1_m, double x2_m, double y2_m)
{
    walls[nwalls][0] = x1_m * 1e6;
    walls[nwalls][1] = y1_m * 1e6;
    walls[nwalls][2] = x2_m * 1e6;
    walls[nwalls][3] = y2_m * 1e6;
    nwalls++;
}

/* Distance along a ray to the nearest wall, µm; HUGE_VAL (infinity) when none. */
static double ray_to_walls(double ox, double oy, double dir)
{
    double dx = cos(dir);
    double dy = sin(dir);
    double best = HUGE_VAL;
    for (unsigned i = 0; i < nwalls; i++) {
        double ex_ = walls[i][2] - walls[i][0];
        double ey = walls[i][3] - walls[i][1];
        double den = dx * ey - dy * ex_;
        if (fabs(den) < 1e-12) {
            continue;
        }
        double qx = walls[i][0] - ox;
        double qy = walls[i][1] - oy;
        double t = (qx * ey - qy * ex_) / den; /* along the ray */
        double u = (qx * dy - qy * dx) / den;  /* along the wall */
        if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < best) {
            best = t;
        }
    }
    return best;
}

/* Distance from the robot's centre to the nearest wall, µm. */
static double clearance(void)
{
    double best = HUGE_VAL;
    for (unsigned i = 0; i < nwalls; i++) {
        double ex_ = walls[i][2] - walls[i][0];
        double ey = walls[i][3] - walls[i][1];
        double l2 = ex_ * ex_ + ey * ey;
        double t = ((px - walls[i][0]) * ex_ + (py - walls[i][1]) * ey) / l2;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        double d = hypot(px - walls[i][0] - t * ex_, py - walls[i][1] - t * ey);
        best = d < best ? d : best;
    }
    return best;
}

/* One tick of the world: a reading every sixth tick (60 ms, the sweep's pace), at the
 * sweep's stops in their back-and-forth order, of the nearest wall along the beam's axis
 * from the sonar (no cone, no grazing loss: the logic is under test, not the sonar). */
static void world_tick(void)
{
    if (world_ticks++ % 6u != 5u) {
        quiet_tick();
        return;
    }
    int stop = world_seq < 6u ? (int)world_seq : (int)(11u - world_seq);
    world_seq = (world_seq + 1u) % 12u;
    double sx = px + cfg.mount_x_um * cos(pth);
    double sy = py + cfg.mount_x_um * sin(pth);
    double dir = pth + (90.0 - (65.0 + 18.0 * stop)) * EW_PI / 180.0;
    double r = ray_to_walls(sx, sy, dir);
    tick(stop, r < 4e6 ? r / 1000.0 : EW_TIMEOUT);
}

#endif /* TEST_EXPLORE_WORLD_H */
