/* SPDX-License-Identifier: MIT */
/* Tests of wheel speed control: the acceleration ramp, tracking, clamps, rest. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "slam/config.h"
#include "slam/motion.h"

static slam_config_t cfg;
static motion_t m;
static odom_t odom; /* only step_um is read */

static int setup(void **state)
{
    (void)state;
    slam_config_default(&cfg);
    memset(&odom, 0, sizeof odom);
    return 0;
}

/* A motor as the simulator models it: wheel speed follows duty·top/1000 with a first-order
 * lag of tau_ticks, times a gain (1.0 = as the controller assumes). */
typedef struct {
    double v_um_tick;
    double gain;
    double tau_ticks;
} plant_t;

static void plant_step(plant_t *p, int16_t duty)
{
    double target = duty / 1000.0 * cfg.top_speed_mm_s * 10.0 * p->gain;
    p->v_um_tick += (target - p->v_um_tick) / p->tau_ticks;
}

static void test_ramp_respects_the_acceleration_limit(void **state)
{
    (void)state;
    motion_init(&m, &cfg);
    motion_set_target(&m, 200, 200); /* 2000 µm/tick */
    int16_t duty[2];
    int32_t before = 0;
    unsigned ticks_to_target = 0;
    for (unsigned t = 1; t <= 100; t++) {
        motion_step(&m, &odom, 1u, duty);
        int32_t step = m.set_um_tick[0] - before;
        assert_true(step >= 0 && step <= 50); /* 500 mm/s² = 50 µm/tick per tick */
        before = m.set_um_tick[0];
        if (ticks_to_target == 0 && m.set_um_tick[0] == 2000) {
            ticks_to_target = t;
        }
    }
    assert_int_equal(ticks_to_target, 40); /* 0.2 m/s at 0.5 m/s²: 0.4 s */
    /* Ten times the acceleration: ten times sooner. */
    cfg.accel_mm_s2 = 5000u;
    motion_init(&m, &cfg);
    motion_set_target(&m, 200, 200);
    unsigned t = 0;
    while (m.set_um_tick[0] != 2000) {
        motion_step(&m, &odom, 1u, duty);
        t++;
    }
    assert_int_equal(t, 4);
}

static void test_feed_forward_follows_the_ramp(void **state)
{
    (void)state;
    cfg.motion_kp_q8 = 0u;
    cfg.motion_ki_q8 = 0u;
    motion_init(&m, &cfg);
    motion_set_target(&m, 150, -90);
    int16_t duty[2] = {0, 0};
    for (int t = 1; t <= 100; t++) {
        motion_step(&m, &odom, 1u, duty);
        int32_t l = t * 50 < 1500 ? t * 50 : 1500;
        int32_t r = t * 50 < 900 ? -t * 50 : -900;
        /* Within one duty step of set · 1000 / top. */
        assert_true(abs(duty[0] * 3000 - l * 1000) <= 3000);
        assert_true(abs(duty[1] * 3000 - r * 1000) <= 3000);
    }
    assert_int_equal(duty[0], 500);
    assert_int_equal(duty[1], -300);
}

/* A wheel 20 % weaker than the feed-forward assumes, with a 80 ms motor lag and encoder
 * quantisation: the PI part brings the speed to the target. */
static void test_pi_tracks_a_weaker_motor(void **state)
{
    (void)state;
    motion_init(&m, &cfg);
    motion_set_target(&m, 200, 100);
    plant_t p[2] = {{0.0, 0.8, 8.0}, {0.0, 0.8, 8.0}};
    double counts[2] = {0.0, 0.0};
    const double um_per_count = 3.14159265358979 * 65000.0 / 700.0;
    double travelled[2] = {0.0, 0.0};
    int16_t duty[2] = {0, 0};
    for (int t = 0; t < 300; t++) {
        motion_step(&m, &odom, 1u, duty);
        for (int w = 0; w < 2; w++) {
            plant_step(&p[w], duty[w]);
            /* The encoder sees whole counts. */
            double before = floor(counts[w]);
            counts[w] += p[w].v_um_tick / um_per_count;
            odom.step_um[w] = (int32_t)lround((floor(counts[w]) - before) * um_per_count);
            if (t >= 200) {
                travelled[w] += p[w].v_um_tick;
            }
            assert_true(duty[w] >= -1000 && duty[w] <= 1000);
        }
    }
    /* Mean speed over the last second within 2 % of the target. */
    assert_true(fabs(travelled[0] / 100.0 - 2000.0) < 40.0);
    assert_true(fabs(travelled[1] / 100.0 - 1000.0) < 20.0);
    assert_true(duty[0] > 2000 * 1000 / 3000); /* more than feed-forward alone */
}

/* A lost tick: the next one sees the travel of two periods. Taken over the periods it
 * spans, that is the speed it was, and the duty holds; taken as one period's, it reads as
 * twice the speed, the control brakes, then pushes (the jolts that make wheels slip). */
static void test_a_lost_tick_reads_as_the_speed_it_was(void **state)
{
    (void)state;
    const double um_per_count = 3.14159265358979 * 65000.0 / 700.0;
    for (int spans = 1; spans >= 0; spans--) {
        motion_init(&m, &cfg);
        motion_set_target(&m, 200, 200);
        plant_t p = {0.0, 0.8, 8.0};
        double counts = 0.0;
        double travelled = 0.0;
        unsigned periods = 0u;
        int16_t duty[2] = {0, 0};
        int16_t lo = INT16_MAX;
        int16_t hi = INT16_MIN;
        for (unsigned t = 0; t < 600u; t++) {
            /* From t = 300 every fifth tick is lost: the world runs on at the duty in force. */
            unsigned n = t >= 300u && t % 5u == 0u ? 2u : 1u;
            double before = floor(counts);
            for (unsigned k = 0; k < n; k++) {
                plant_step(&p, duty[0]);
                counts += p.v_um_tick / um_per_count;
                if (t >= 300u) {
                    travelled += p.v_um_tick;
                }
            }
            odom.step_um[0] = (int32_t)lround((floor(counts) - before) * um_per_count);
            odom.step_um[1] = odom.step_um[0];
            motion_step(&m, &odom, spans ? n : 1u, duty);
            if (t >= 300u) {
                periods += n;
                lo = duty[0] < lo ? duty[0] : lo;
                hi = duty[0] > hi ? duty[0] : hi;
            }
        }
        double mean = travelled / periods;
        print_message("lost ticks, travel %s: mean %.0f um/tick, duty %d..%d\n",
                      spans ? "over its periods" : "as one period's", mean, lo, hi);
        if (spans) {
            assert_true(fabs(mean - 2000.0) < 40.0); /* within 2 % of the target */
            assert_true(hi - lo < 60);
        } else {
            assert_true(hi - lo > 150); /* measured: 211, and 16 % slow */
            assert_true(mean < 1850.0);
        }
    }
}

static void test_clamps_and_a_stalled_wheel(void **state)
{
    (void)state;
    motion_init(&m, &cfg);
    motion_set_target(&m, 10000, -10000); /* beyond the top speed */
    assert_int_equal(m.target_um_tick[0], 3000);
    assert_int_equal(m.target_um_tick[1], -3000);
    int16_t duty[2];
    for (int t = 0; t < 5000; t++) { /* the wheels never move */
        motion_step(&m, &odom, 1u, duty);
        assert_true(abs(duty[0]) <= 1000 && abs(duty[1]) <= 1000);
        /* A stall is seen a quarter second after the set speed reaches 30 mm/s (in the
         * sixth tick of the ramp at 500 mm/s², t = 5): 25 slow ticks end at t = 29. */
        assert_int_equal(motion_stalled(&m), t >= 4 + (int)MOTION_STALL_TICKS);
    }
    assert_int_equal(duty[0], 1000);
    assert_int_equal(duty[1], -1000);
    /* The integral is bounded, so when the wheel frees itself the windup is short. */
    assert_true(abs(m.integral_um[0]) <= 1000 * 256 / (int32_t)cfg.motion_ki_q8);
    /* Once the wheels turn again the stall is over. */
    odom.step_um[0] = 2900;
    odom.step_um[1] = -2900;
    motion_step(&m, &odom, 1u, duty);
    assert_false(motion_stalled(&m));
    /* A huge measured speed (an encoder glitch) saturates, never overflows. */
    odom.step_um[0] = INT32_MAX;
    odom.step_um[1] = INT32_MIN;
    motion_step(&m, &odom, 1u, duty);
    assert_int_equal(duty[0], -1000);
    assert_int_equal(duty[1], 1000);
}

/* A wheel that hardly turns as asked is driven by its feed-forward alone (no push, no
 * windup); one that stalls while the other turns is told apart from a body held back. */
static void test_a_stalled_wheel_gets_feed_forward_only(void **state)
{
    (void)state;
    motion_init(&m, &cfg);
    motion_set_target(&m, 100, 100);
    int16_t duty[2];
    bool one = false;
    for (int t = 0; t < 200; t++) {
        odom.step_um[0] = 0;                /* its count has stopped */
        odom.step_um[1] = m.set_um_tick[1]; /* the other turns as asked */
        motion_step(&m, &odom, 1u, duty);
        if (m.slow_ticks[0] >= MOTION_DEAD_TICKS) {
            assert_int_equal(duty[0], m.set_um_tick[0] * 1000 / m.top_um_tick);
            assert_int_equal(m.integral_um[0], 0);
        }
        one = one || motion_one_wheel(&m);
    }
    assert_true(motion_stalled(&m));
    assert_true(one && motion_one_wheel(&m));
    /* Both held back: a stall, not one wheel. */
    motion_init(&m, &cfg);
    motion_set_target(&m, 100, 100);
    odom.step_um[0] = odom.step_um[1] = 0;
    for (int t = 0; t < 200; t++) {
        motion_step(&m, &odom, 1u, duty);
        assert_false(motion_one_wheel(&m));
    }
    assert_true(motion_stalled(&m));
}

/* A body held back at one side, asked forward (or back): pushed by turns, its wheels turn
 * it to and fro, so neither wheel's own watch lasts, and the body's sees the stall. A body
 * that goes at half the speed asked is none. The first tick a stall is seen, or -1. */
static int held_at_one_side(int32_t mm_s, int32_t share_of_eight)
{
    motion_init(&m, &cfg);
    motion_set_target(&m, mm_s, mm_s);
    int16_t duty[2];
    int first = -1;
    for (int t = 0; t < 200; t++) {
        /* Each wheel turns as asked for three ticks and back for three, out of step, on top
         * of share_of_eight eighths of the set speed for the body. */
        int32_t body = m.set_um_tick[0] * share_of_eight / 8;
        int32_t swing = (t / 3) % 2 == 0 ? m.set_um_tick[0] : -m.set_um_tick[0];
        odom.step_um[0] = body + swing;
        odom.step_um[1] = body - swing;
        motion_step(&m, &odom, 1u, duty);
        assert_false(motion_one_wheel(&m));
        assert_true(m.slow_ticks[0] < MOTION_STALL_TICKS && m.slow_ticks[1] < MOTION_STALL_TICKS);
        if (first < 0 && motion_stalled(&m)) {
            first = t;
        }
    }
    return first;
}

static void test_a_body_held_back_turning_to_and_fro(void **state)
{
    (void)state;
    /* As for a wheel: 25 slow ticks from the sixth of the ramp, when the body is asked
     * 2 x 30 mm/s (test_clamps_and_a_stalled_wheel). */
    const int seen = 4 + (int)MOTION_STALL_TICKS;
    assert_int_equal(held_at_one_side(100, 0), seen);
    assert_int_equal(held_at_one_side(-100, 0), seen);
    assert_int_equal(held_at_one_side(100, 1), seen); /* an eighth of the speed asked */
    assert_int_equal(held_at_one_side(100, 4), -1);
    assert_int_equal(held_at_one_side(-100, 4), -1);
    /* Wheels asked opposite ways (a turn about a point between them) ask nothing of the
     * body, however unequal: held still, the wheels stall, the body does not. */
    motion_init(&m, &cfg);
    motion_set_target(&m, 150, -50);
    memset(&odom, 0, sizeof odom);
    int16_t duty[2];
    for (int t = 0; t < 200; t++) {
        motion_step(&m, &odom, 1u, duty);
        assert_int_equal(m.body_slow, 0);
    }
    assert_true(motion_stalled(&m));
}

static void test_rest_means_zero_duty(void **state)
{
    (void)state;
    motion_init(&m, &cfg);
    motion_set_target(&m, 200, 200);
    int16_t duty[2];
    for (int t = 0; t < 100; t++) {
        motion_step(&m, &odom, 1u, duty); /* wheel not moving: the integral grows */
    }
    motion_set_target(&m, 0, 0);
    for (int t = 0; t < 39; t++) {
        motion_step(&m, &odom, 1u, duty);
    }
    assert_true(m.set_um_tick[0] > 0); /* still ramping down */
    motion_step(&m, &odom, 1u, duty);
    assert_int_equal(m.set_um_tick[0], 0);
    assert_int_equal(duty[0], 0);
    assert_int_equal(duty[1], 0);
    assert_int_equal(m.integral_um[0], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_ramp_respects_the_acceleration_limit, setup),
        cmocka_unit_test_setup(test_feed_forward_follows_the_ramp, setup),
        cmocka_unit_test_setup(test_pi_tracks_a_weaker_motor, setup),
        cmocka_unit_test_setup(test_a_lost_tick_reads_as_the_speed_it_was, setup),
        cmocka_unit_test_setup(test_clamps_and_a_stalled_wheel, setup),
        cmocka_unit_test_setup(test_a_stalled_wheel_gets_feed_forward_only, setup),
        cmocka_unit_test_setup(test_a_body_held_back_turning_to_and_fro, setup),
        cmocka_unit_test_setup(test_rest_means_zero_duty, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
