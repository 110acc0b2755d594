/* SPDX-License-Identifier: MIT */
/*
 * The world's benchmark: the real firmware in the default room with the default error
 * levels for an hour of virtual time, a wandering drive that turns away from walls, and
 * the ticks per wall-clock second at the end. Run it under callgrind to count the
 * instructions of the world and of the firmware per tick (hal/host/README.md).
 *
 *   bench_world [ROOM] [TICKS] [SEED]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "hal/hal.h"
#include "host/sim.h"
#include "slam/error.h"
#include "slam/robot.h"

static robot_t robot;

/* The drive: straight on, and a turn in place of random length when a wall comes near. */
static struct {
    const room_t *room;
    sim_t *sim;
    uint64_t rng;
    uint32_t turn_ticks;
    int16_t turn_dir;
} drive;

static uint64_t drive_rand(void)
{
    uint64_t z = (drive.rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Kept out of line so callgrind can tell it from the world and the firmware. */
__attribute__((noinline)) static void bench_drive(void)
{
    if (drive.turn_ticks > 0u) {
        drive.turn_ticks--;
        hal_motor_set(HAL_WHEEL_LEFT, (int16_t)(-400 * drive.turn_dir));
        hal_motor_set(HAL_WHEEL_RIGHT, (int16_t)(400 * drive.turn_dir));
        return;
    }
    if (robot.ticks % 5u == 0u) {
        sim_truth_t t = sim_truth(drive.sim);
        double ax = t.x + 0.12 * cos(t.th);
        double ay = t.y + 0.12 * sin(t.th);
        if (t.contact || room_clearance(drive.room, ax, ay, 0.2) < 0.11) {
            drive.turn_ticks = 30u + (uint32_t)(drive_rand() % 150u);
            drive.turn_dir = (drive_rand() & 1u) ? 1 : -1;
            return;
        }
    }
    hal_motor_set(HAL_WHEEL_LEFT, 600);
    hal_motor_set(HAL_WHEEL_RIGHT, 600);
}

static void tick(void *ctx)
{
    robot_tick(ctx);
    bench_drive();
}

static double now_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : HOST_DEFAULT_ROOM;
    unsigned long ticks = argc > 2 ? strtoul(argv[2], NULL, 10) : 360000ul;
    uint64_t seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 1u;

    room_t room;
    char err[300];
    if (room_load(&room, path, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "bench_world: %s\n", err);
        return 2;
    }
    if (!room.has_start &&
        room_find_start(&room, 0.2, &room.start_x, &room.start_y, &room.start_th) != 0) {
        fprintf(stderr, "bench_world: %s: no free start pose\n", path);
        return 2;
    }
    sim_params_t p;
    sim_errors_t e;
    sim_params_default(&p);
    sim_errors_default(&e);
    sim_t *sim = sim_create(&room, &p, &e, seed);
    if (sim == NULL) {
        fprintf(stderr, "bench_world: cannot create the world\n");
        return 1;
    }
    hal_host_attach(sim);
    if (hal_init() != HAL_OK) {
        return 1;
    }
    slam_config_t cfg;
    slam_config_default(&cfg);
    cfg.start_x_um = (int32_t)lround(room.start_x * 1e6);
    cfg.start_y_um = (int32_t)lround(room.start_y * 1e6);
    cfg.start_heading_mdeg = (int32_t)lround(room.start_th * (180000.0 / 3.14159265358979323846));
    if (robot_init(&robot, &cfg) != SLAM_OK) {
        fprintf(stderr, "bench_world: robot_init failed\n");
        return 1;
    }
    drive.room = &room;
    drive.sim = sim;
    drive.rng = seed ^ 0x5DEECE66Dull;
    hal_tick_start(tick, &robot);

    double t0 = now_s();
    for (unsigned long i = 0; i < ticks; i++) {
        hal_host_step();
    }
    double wall = now_s() - t0;

    sim_truth_t t = sim_truth(sim);
    double ex = (double)robot.pose.x_um * 1e-6 - t.x;
    double ey = (double)robot.pose.y_um * 1e-6 - t.y;
    printf("%lu ticks (%.0f s virtual) in %.3f s: %.0f ticks/s, %.0fx real time\n", ticks,
           (double)ticks * 0.01, wall, (double)ticks / wall, (double)ticks * 0.01 / wall);
    printf("pings %u (echoes %u, timeouts %u), OM hits %u, collisions %u, "
           "odometry error %.3f m\n",
           robot.sweep.pings, robot.sweep.echoes, robot.sweep.timeouts, robot.mapper.hits,
           t.collisions, hypot(ex, ey));
    hal_host_attach(NULL);
    sim_destroy(sim);
    room_free(&room);
    return 0;
}
