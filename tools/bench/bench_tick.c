/* SPDX-License-Identifier: MIT */
/*
 * The tick benchmark: ten minutes of driving (60 000 ticks) in a 5 m × 4 m room with the
 * full sweep running, through a scripted HAL, so callgrind can count the instructions of
 * every robot_tick() call (tools/bench.sh). The robot circles the room's centre on a 1 m
 * radius at 0.2 m/s and spins in place for two seconds every half minute.
 *
 *   bench_tick [--ticks N] [--trace FILE]
 *
 * --trace writes what the firmware saw and did at the HAL in every tick as a HAL trace
 * (hal_common/trace.h), the scenario a replay HAL plays back on the emulated MCU.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal/hal.h"
#include "hal_common/trace.h"
#include "slam/error.h"
#include "slam/robot.h"

extern robot_t bench_robot;

#define ROOM_W 5.0
#define ROOM_H 4.0
#define TICKS 60000u
#define PI 3.14159265358979323846

static const double WHEEL_D = 0.065;
static const double BASE = 0.130;
static const double COUNTS = 700.0;
static const double SOUND = 343.0;

/* The true robot and its sensors. */
static struct {
    double x, y, th; /* true pose in the room, m and rad */
    double count[2]; /* true encoder position, counts */
    uint32_t now_us;
    uint16_t servo_us;
    int ping_out;
    uint32_t echo_at_us; /* when the echo (or the timeout) completes */
    uint32_t echo_us;    /* its width; 0 for a timeout */
    int16_t duty[2];     /* motor duties in force */
} w;

/* The trace being recorded (NULL: none) and the HAL traffic of the current tick. */
static FILE *trace;
static trace_tick_t rec;

/* Distance from (x, y) along bearing th to the room's walls. */
static double wall_distance(double x, double y, double th)
{
    double c = cos(th);
    double s = sin(th);
    double d = 1e9;
    if (c > 1e-9) {
        d = fmin(d, (ROOM_W - x) / c);
    } else if (c < -1e-9) {
        d = fmin(d, -x / c);
    }
    if (s > 1e-9) {
        d = fmin(d, (ROOM_H - y) / s);
    } else if (s < -1e-9) {
        d = fmin(d, -y / s);
    }
    return d;
}

/* Wheel speeds (m/s) at tick t of the script. */
static void script(uint32_t t, double *vl, double *vr)
{
    if (t % 3000u >= 2800u) { /* spin in place */
        *vl = -0.1;
        *vr = 0.1;
        return;
    }
    double v = 0.2;
    double omega = v / 1.0; /* 1 m radius */
    *vl = v - omega * BASE / 2.0;
    *vr = v + omega * BASE / 2.0;
}

static void world_step(uint32_t t)
{
    double vl;
    double vr;
    script(t, &vl, &vr);
    double dt = HAL_TICK_PERIOD_US * 1e-6;
    double dl = vl * dt;
    double dr = vr * dt;
    double dth = (dr - dl) / BASE;
    double du = (dl + dr) / 2.0;
    w.x += du * cos(w.th + dth / 2.0);
    w.y += du * sin(w.th + dth / 2.0);
    w.th += dth;
    w.count[0] += dl / (PI * WHEEL_D) * COUNTS;
    w.count[1] += dr / (PI * WHEEL_D) * COUNTS;
    w.now_us += HAL_TICK_PERIOD_US;
}

int hal_init(void)
{
    w.x = ROOM_W / 2.0;
    w.y = ROOM_H / 2.0 - 1.0;
    w.th = 0.0;
    return HAL_OK;
}

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    (void)fn;
    (void)ctx;
    return HAL_OK;
}

uint32_t hal_time_us(void)
{
    return w.now_us;
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    uint16_t count = (uint16_t)(int64_t)floor(w.count[wheel]);
    rec.enc[wheel] = count;
    return count;
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    w.duty[wheel] = duty;
}

/* The scripted robot has the paper's servo and sonar (instance 0) only (hal_servo_count()
 * and hal_sonar_count() are hal_unsupported's 1). */

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo != HAL_SERVO_SWEEP) {
        return HAL_EINVAL;
    }
    w.servo_us = pulse_us;
    return HAL_OK;
}

static int sonar_trigger(void)
{
    if (w.ping_out) {
        return HAL_EBUSY;
    }
    double servo = (w.servo_us - 500.0) / 2000.0 * PI; /* 500..2500 µs is 0..180° */
    double sx = w.x + 0.05 * cos(w.th);
    double sy = w.y + 0.05 * sin(w.th);
    double d = wall_distance(sx, sy, w.th + PI / 2.0 - servo);
    w.ping_out = 1;
    if (d > 4.0) {
        w.echo_us = 0u;
        w.echo_at_us = w.now_us + 38000u;
    } else {
        w.echo_us = (uint32_t)(2.0 * d / SOUND * 1e6);
        w.echo_at_us = w.now_us + w.echo_us;
    }
    return HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar != HAL_SONAR_SWEPT) {
        return HAL_EINVAL;
    }
    int rc = sonar_trigger();
    rec.trig = rc == HAL_OK ? 'o' : 'b';
    return rc;
}

static hal_sonar_status_t sonar_poll(uint32_t *echo_us)
{
    if (!w.ping_out) {
        return HAL_SONAR_IDLE;
    }
    if ((int32_t)(w.now_us - w.echo_at_us) < 0) {
        return HAL_SONAR_BUSY;
    }
    w.ping_out = 0;
    if (w.echo_us == 0u) {
        return HAL_SONAR_TIMEOUT;
    }
    *echo_us = w.echo_us;
    return HAL_SONAR_ECHO;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar != HAL_SONAR_SWEPT) {
        return HAL_EINVAL;
    }
    hal_sonar_status_t st = sonar_poll(echo_us);
    static const char code[] = {'i', 'b', 'e', 't'};
    rec.poll = code[st];
    rec.echo_us = st == HAL_SONAR_ECHO ? *echo_us : 0u;
    return (int)st;
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    (void)data;
    return len;
}

/* hal_uart_read(), map storage and the bump switches are hal_unsupported's (nothing
 * received, no storage, none); the critical section, the overrun count and the watchdog
 * hal_synchronous's (one thread). */

static int usage(const char *why)
{
    fprintf(stderr, "bench_tick: %s\nusage: bench_tick [--ticks N] [--trace FILE]\n", why);
    return 2;
}

int main(int argc, char **argv)
{
    uint32_t ticks = TICKS;
    const char *trace_path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--ticks") == 0 && i + 1 < argc) {
            char *end;
            unsigned long n = strtoul(argv[++i], &end, 10);
            if (*end != '\0' || n == 0u || n > 100000000ul) {
                return usage("--ticks takes a whole number from 1 to 100000000");
            }
            ticks = (uint32_t)n;
        } else if (strcmp(argv[i], "--trace") == 0 && i + 1 < argc) {
            trace_path = argv[++i];
        } else {
            return usage("unknown or incomplete option");
        }
    }

    hal_init();
    slam_config_t cfg;
    slam_config_default(&cfg);
    if (robot_init(&bench_robot, &cfg) != SLAM_OK) {
        fprintf(stderr, "bench_tick: robot_init failed\n");
        return 1;
    }
    if (trace_path != NULL) {
        trace = fopen(trace_path, "w");
        if (trace == NULL) {
            fprintf(stderr, "bench_tick: %s: cannot write the trace\n", trace_path);
            return 1;
        }
        trace_write_header(trace, &cfg);
    }
    for (uint32_t t = 0; t < ticks; t++) {
        world_step(t);
        rec = (trace_tick_t){.poll = '-', .trig = '-'};
        robot_tick(&bench_robot);
        if (trace != NULL) {
            rec.duty[0] = w.duty[0];
            rec.duty[1] = w.duty[1];
            rec.servo_us = w.servo_us;
            trace_write_tick(trace, &rec);
        }
    }
    if (trace != NULL) {
        trace_write_end(trace, ticks);
        if (fclose(trace) != 0) {
            fprintf(stderr, "bench_tick: %s: write failed\n", trace_path);
            return 1;
        }
    }
    const robot_t *r = &bench_robot;
    double ex = (r->pose.x_um * 1e-6 + ROOM_W / 2.0) - w.x;
    double ey = (r->pose.y_um * 1e-6 + ROOM_H / 2.0 - 1.0) - w.y;
    printf("%u ticks, grid %ux%u, %u pings (%u echoes, %u timeouts), %u OM hits, "
           "%u beyond rc, odometry error %.1f mm\n",
           r->ticks, SLAM_GRID_A, SLAM_GRID_B, r->sweep.pings, r->sweep.echoes, r->sweep.timeouts,
           r->mapper.hits, r->mapper.far, 1000.0 * hypot(ex, ey));
    return 0;
}
