/* SPDX-License-Identifier: MIT */
/* Tests of the simulated robot: motors, encoders, odometry errors, collisions, servo. */
#include <math.h>

#include "world_origin.h"
#include "host_test.h"
#include "slam/config.h"
#include "slam/odometry.h"

#define BIG_ROOM "wall -60 -60 60 -60\nwall 60 -60 60 60\nwall 60 60 -60 60\nwall -60 60 -60 -60\n"

static room_t big;

static int setup(void **state)
{
    (void)state;
    test_room(&big, BIG_ROOM "start 0 0 0\n");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    room_free(&big);
    return 0;
}

static void drive(sim_t *s, int16_t left, int16_t right, unsigned ticks)
{
    sim_motor_set(s, HAL_WHEEL_LEFT, left);
    sim_motor_set(s, HAL_WHEEL_RIGHT, right);
    for (unsigned i = 0; i < ticks; i++) {
        sim_step(s);
    }
}

/* The firmware's own odometry, fed from the world's encoders every tick. */
typedef struct {
    odom_t o;
} fw_odom_t;

static void fw_odom_init(fw_odom_t *f, const sim_t *s, const slam_config_t *cfg)
{
    odom_init(&f->o, cfg, sim_encoder_count(s, HAL_WHEEL_LEFT),
              sim_encoder_count(s, HAL_WHEEL_RIGHT));
}

static void fw_odom_step(fw_odom_t *f, const sim_t *s)
{
    odom_step(&f->o, sim_encoder_count(s, HAL_WHEEL_LEFT), sim_encoder_count(s, HAL_WHEEL_RIGHT));
}

static double fw_heading(const fw_odom_t *f)
{
    return (double)(int32_t)odom_pose(&f->o).heading * (TEST_PI / 2147483648.0);
}

static void drive_odom(sim_t *s, fw_odom_t *f, int16_t left, int16_t right, unsigned ticks)
{
    sim_motor_set(s, HAL_WHEEL_LEFT, left);
    sim_motor_set(s, HAL_WHEEL_RIGHT, right);
    for (unsigned i = 0; i < ticks; i++) {
        sim_step(s);
        fw_odom_step(f, s);
    }
}

static void test_motor_first_order(void **state)
{
    (void)state;
    sim_t *s = test_ideal_world(&big);
    sim_motor_set(s, HAL_WHEEL_LEFT, 1000);
    sim_motor_set(s, HAL_WHEEL_RIGHT, -500);
    for (int k = 1; k <= 40; k++) {
        sim_step(s);
        sim_truth_t t = sim_truth(s);
        double f = 1.0 - exp(-k * 0.01 / 0.08);
        assert_true(fabs(t.wheel_mps[0] - 0.3 * f) < 1e-9);
        assert_true(fabs(t.wheel_mps[1] + 0.15 * f) < 1e-9);
        if (k == 8) { /* one time constant: 63 % */
            assert_true(fabs(t.wheel_mps[0] / 0.3 - 0.632) < 0.001);
        }
    }
    /* Duty is clamped to full scale. */
    sim_motor_set(s, HAL_WHEEL_LEFT, 5000);
    sim_motor_set(s, HAL_WHEEL_RIGHT, -32000);
    assert_int_equal(sim_motor_duty(s, HAL_WHEEL_LEFT), 1000);
    assert_int_equal(sim_motor_duty(s, HAL_WHEEL_RIGHT), -1000);
    drive(s, 5000, -5000, 200);
    sim_truth_t t = sim_truth(s);
    assert_true(fabs(t.wheel_mps[0] - 0.3) < 1e-6 && fabs(t.wheel_mps[1] + 0.3) < 1e-6);
    sim_destroy(s);
}

static void test_encoders_count_rotation_and_wrap(void **state)
{
    (void)state;
    sim_t *s = test_ideal_world(&big);
    const double m_per_count = TEST_PI * 0.065 / 700.0;
    int64_t total[2] = {0, 0};
    uint16_t last[2] = {sim_encoder_count(s, HAL_WHEEL_LEFT),
                        sim_encoder_count(s, HAL_WHEEL_RIGHT)};
    bool wrapped = false;
    /* 80 s at full speed: 24 m, about 82 000 counts, more than the counter holds. */
    sim_motor_set(s, HAL_WHEEL_LEFT, 1000);
    sim_motor_set(s, HAL_WHEEL_RIGHT, 1000);
    assert_true(sim_place(s, -40.0, 0.0, 0.0) == 0);
    for (int k = 0; k < 8000; k++) {
        sim_step(s);
        for (int w = 0; w < 2; w++) {
            uint16_t c = sim_encoder_count(s, (hal_wheel_t)w);
            int16_t d = (int16_t)(uint16_t)(c - last[w]);
            if (c < last[w]) {
                wrapped = true;
            }
            total[w] += d;
            last[w] = c;
        }
    }
    assert_true(wrapped);
    sim_truth_t t = sim_truth(s);
    double travelled = t.x + 40.0;
    assert_true(total[0] > 65536);
    assert_true(fabs((double)total[0] * m_per_count - travelled) <= m_per_count);
    assert_true(total[0] == total[1]);
    /* Backwards counts down, through zero and below. */
    drive(s, -1000, -1000, 8100);
    t = sim_truth(s);
    /* Floor of the true rotation: the counter is the true position rounded down. */
    double pos = (t.x + 40.0) / m_per_count;
    uint16_t want = (uint16_t)(int64_t)floor(pos);
    uint16_t got = sim_encoder_count(s, HAL_WHEEL_LEFT);
    assert_true(pos < 0.0);
    assert_true((uint16_t)(got - want) <= 1u || (uint16_t)(want - got) <= 1u);
    sim_destroy(s);
}

/* A person carrying the robot back to its start (UMBmark's experimenter): the encoders
 * keep their counts, the wheels stand, and it drives on from there. */
static void test_place_keeps_the_encoders(void **state)
{
    (void)state;
    sim_t *s = test_ideal_world(&big);
    drive(s, 500, 800, 200);
    drive(s, 0, 0, 100);
    uint16_t left = sim_encoder_count(s, HAL_WHEEL_LEFT);
    uint16_t right = sim_encoder_count(s, HAL_WHEEL_RIGHT);
    assert_true(left != 0u && right != left);
    assert_int_equal(sim_place(s, 1.0, -2.0, 0.5), 0);
    sim_truth_t t = sim_truth(s);
    assert_true(t.x == 1.0 && t.y == -2.0 && t.th == 0.5);
    assert_true(t.wheel_mps[0] == 0.0 && t.wheel_mps[1] == 0.0);
    assert_int_equal(sim_encoder_count(s, HAL_WHEEL_LEFT), left);
    assert_int_equal(sim_encoder_count(s, HAL_WHEEL_RIGHT), right);
    drive(s, 0, 0, 10);
    t = sim_truth(s);
    assert_true(t.x == 1.0 && t.y == -2.0 && t.th == 0.5);
    drive(s, 500, 500, 100); /* straight on along its new heading */
    t = sim_truth(s);
    assert_true(t.x > 1.0 && fabs(atan2(t.y + 2.0, t.x - 1.0) - 0.5) < 1e-6);
    sim_destroy(s);
}

static void test_ideal_odometry_matches_truth(void **state)
{
    (void)state;
    sim_t *s = test_ideal_world(&big);
    slam_config_t cfg;
    test_config_default(&cfg);
    fw_odom_t f;
    fw_odom_init(&f, s, &cfg);
    /* Straights, arcs, spins and reversals: a minute of driving. */
    static const int16_t script[][3] = {
        {800, 800, 500}, {300, 900, 700}, {-600, 600, 300}, {1000, 400, 800}, {-700, -700, 400},
        {0, 900, 300},   {500, 500, 600}, {900, -900, 250}, {200, 1000, 900}, {0, 0, 200},
    };
    double max_th = 0.0;
    double max_pos = 0.0;
    for (size_t i = 0; i < sizeof script / sizeof script[0]; i++) {
        for (int k = 0; k < script[i][2]; k++) {
            drive_odom(s, &f, script[i][0], script[i][1], 1u);
            sim_truth_t t = sim_truth(s);
            odom_pose_t p = odom_pose(&f.o);
            max_th = fmax(max_th, fabs(test_angle_diff(fw_heading(&f), t.th)));
            max_pos = fmax(max_pos, hypot(p.x_um * 1e-6 - t.x, p.y_um * 1e-6 - t.y));
        }
    }
    /* Only quantisation separates them: one count a wheel is 0.29 mm, 2.2 mrad of heading. */
    print_message("ideal odometry vs truth: max heading error %.2e rad, position %.2e m\n", max_th,
                  max_pos);
    assert_true(max_th < 0.0050);
    assert_true(max_pos < 0.005);
    sim_destroy(s);
}

static void test_unequal_wheels_curve_the_path(void **state)
{
    (void)state;
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.wheel_ratio_ed = 1.01; /* the right wheel is 1 % larger */
    sim_t *s = test_world(&big, &e, 1u);
    slam_config_t cfg;
    test_config_default(&cfg);
    fw_odom_t f;
    fw_odom_init(&f, s, &cfg);
    drive_odom(s, &f, 800, 800, 1000);
    sim_truth_t t = sim_truth(s);
    /* The same rotation of both wheels: dθ = φ (r_R - r_L) / b. */
    double phi = (double)(uint16_t)sim_encoder_count(s, HAL_WHEEL_LEFT) / 700.0 * 2.0 * TEST_PI;
    double r_l = 0.0325 * 2.0 / 2.01;
    double r_r = 0.0325 * 2.0 * 1.01 / 2.01;
    double want = phi * (r_r - r_l) / 0.130;
    assert_true(t.th > 0.0); /* curves left */
    assert_true(fabs(t.th - want) < 0.01 * want + 0.003);
    assert_true(fabs(fw_heading(&f)) < 0.003); /* the encoders say: straight */

    /* The firmware calibrated by UMBmark for this E_d follows the true path. */
    q1_30_t ed = (q1_30_t)llround(1.01 * (1 << 30));
    odom_umbmark_factors(ed, &cfg.cal_left, &cfg.cal_right);
    assert_true(sim_place(s, 0.0, 0.0, 0.0) == 0);
    fw_odom_init(&f, s, &cfg);
    drive_odom(s, &f, 800, 800, 1000);
    t = sim_truth(s);
    assert_true(t.th > 0.05);
    assert_true(fabs(test_angle_diff(fw_heading(&f), t.th)) < 0.005);
    odom_pose_t p = odom_pose(&f.o);
    assert_true(hypot(p.x_um * 1e-6 - t.x, p.y_um * 1e-6 - t.y) < 0.01);
    sim_destroy(s);
}

static void test_wheel_base_error_scales_turns(void **state)
{
    (void)state;
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.wheel_base_eb = 1.02;
    sim_t *s = test_world(&big, &e, 1u);
    slam_config_t cfg;
    test_config_default(&cfg);
    fw_odom_t f;
    fw_odom_init(&f, s, &cfg);
    double turned_true = 0.0;
    double turned_odom = 0.0;
    double th0 = sim_truth(s).th;
    double o0 = fw_heading(&f);
    for (int k = 0; k < 300; k++) { /* spin in place, about a turn and a half */
        drive_odom(s, &f, -600, 600, 1u);
        sim_truth_t t = sim_truth(s);
        turned_true += test_angle_diff(t.th, th0);
        turned_odom += test_angle_diff(fw_heading(&f), o0);
        th0 = t.th;
        o0 = fw_heading(&f);
    }
    assert_true(turned_odom > 6.0);
    assert_true(fabs(turned_true / turned_odom - 1.0 / 1.02) < 0.001);
    sim_truth_t t = sim_truth(s);
    assert_true(fabs(t.x) < 1e-9 && fabs(t.y) < 1e-9); /* a spin does not move the axle */
    sim_destroy(s);
}

static void test_slip_grows_with_acceleration(void **state)
{
    (void)state;
    const double m_per_count = TEST_PI * 0.065 / 700.0;
    double lag[5];
    const double slips[5] = {0.0, 0.05, 0.10, 0.10, 0.10};
    /* Traction holds up to slip_free: the first three slip from any acceleration; a start
     * to 0.3 m/s with τ = 80 ms peaks at 3.75 m/s², so a limit of 1 m/s² leaves part of
     * the slip and one of 5 m/s² none. */
    const double free[5] = {0.0, 0.0, 0.0, 1.0, 5.0};
    for (int i = 0; i < 5; i++) {
        sim_errors_t e;
        sim_errors_ideal(&e);
        e.slip_per_mps2 = slips[i];
        e.slip_free_mps2 = free[i];
        sim_t *s = test_world(&big, &e, 1u);
        drive(s, 1000, 1000, 100); /* 0 to 0.3 m/s in a few tau, then steady */
        double enc = (double)sim_encoder_count(s, HAL_WHEEL_LEFT) * m_per_count;
        lag[i] = enc - sim_truth(s).x;
        /* Steady speed: no acceleration, no more slip. */
        drive(s, 1000, 1000, 100);
        double enc2 = (double)sim_encoder_count(s, HAL_WHEEL_LEFT) * m_per_count;
        assert_true(fabs((enc2 - sim_truth(s).x) - lag[i]) < 2.0 * m_per_count);
        sim_destroy(s);
    }
    /* Slip s·|a| of the travel integrates to s·v²/2: 2.25 mm at 0.05 per m/s² to 0.3 m/s. */
    assert_true(fabs(lag[0]) < m_per_count);
    assert_true(fabs(lag[1] - 0.00225) < 0.0004);
    assert_true(fabs(lag[2] - 0.0045) < 0.0006);
    assert_true(lag[3] > 2.0 * m_per_count && lag[3] < lag[2] - 2.0 * m_per_count);
    assert_true(fabs(lag[4]) < m_per_count);
}

static void test_wheel_noise_spreads_heading(void **state)
{
    (void)state;
    /* Predicted spread of the heading after 400 ticks of full speed: each tick adds
       noise·d to each wheel, so var(θ) = Σ 2 (noise·d_k)² / b². */
    const double noise = 0.02;
    sim_t *ideal = test_ideal_world(&big);
    sim_motor_set(ideal, HAL_WHEEL_LEFT, 1000);
    sim_motor_set(ideal, HAL_WHEEL_RIGHT, 1000);
    double var = 0.0;
    double x0 = 0.0;
    for (int k = 0; k < 400; k++) {
        sim_step(ideal);
        double d = sim_truth(ideal).x - x0;
        x0 = sim_truth(ideal).x;
        var += 2.0 * (noise * d) * (noise * d) / (0.13 * 0.13);
    }
    sim_destroy(ideal);
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.wheel_noise = noise;
    double sum2 = 0.0;
    double sumx = 0.0;
    const int runs = 60;
    for (int seed = 0; seed < runs; seed++) {
        sim_t *s = test_world(&big, &e, (uint64_t)seed + 100u);
        drive(s, 1000, 1000, 400);
        sim_truth_t t = sim_truth(s);
        sum2 += t.th * t.th;
        sumx += t.x;
        sim_destroy(s);
    }
    double sd = sqrt(sum2 / runs);
    double want = sqrt(var);
    print_message("heading spread %.4f rad, predicted %.4f\n", sd, want);
    /* 60 samples estimate a deviation within ±20 % (2σ of its sampling error ~18 %). */
    assert_true(sd > 0.75 * want && sd < 1.25 * want);
    assert_true(fabs(sumx / runs - x0) < 0.01); /* unbiased along the way */
}

static void test_servo_slew(void **state)
{
    (void)state;
    sim_t *s = test_ideal_world(&big);
    assert_true(sim_truth(s).servo_deg == 90.0);
    sim_servo_set_pulse(s, 1222); /* 64.98°: 25° away, 600°/s: 6° a tick */
    double want[] = {84.0, 78.0, 72.0, 66.0};
    for (int k = 0; k < 4; k++) {
        sim_step(s);
        assert_true(fabs(sim_truth(s).servo_deg - want[k]) < 1e-9);
    }
    sim_step(s);
    assert_true(fabs(sim_truth(s).servo_deg - 64.98) < 1e-9);
    /* 65° to 155°: 90° takes 150 ms. */
    sim_servo_set_pulse(s, 2222); /* 154.98° */
    for (int k = 0; k < 14; k++) {
        sim_step(s);
    }
    assert_true(sim_truth(s).servo_deg < 154.98 - 5.0);
    sim_step(s);
    assert_true(fabs(sim_truth(s).servo_deg - 154.98) < 1e-9);
    /* Pulses clamp to 400..2600 µs and the horn stops at 0° and 180°. */
    sim_servo_set_pulse(s, 3000);
    assert_int_equal(sim_servo_pulse(s), 2600);
    for (int k = 0; k < 10; k++) {
        sim_step(s);
    }
    assert_true(sim_truth(s).servo_deg == 180.0);
    sim_servo_set_pulse(s, 0);
    assert_int_equal(sim_servo_pulse(s), 400);
    for (int k = 0; k < 40; k++) {
        sim_step(s);
    }
    assert_true(sim_truth(s).servo_deg == 0.0);
    sim_destroy(s);
}

/* ---- collisions --------------------------------------------------------------------------- */

static void test_contact_stops_and_counts(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 3 0\nwall 3 0 3 2\nwall 3 2 0 2\nwall 0 2 0 0\nstart 1 1 0\n");
    sim_t *s = test_ideal_world(&r);
    drive(s, 800, 800, 1200); /* into the east wall and on pushing */
    sim_truth_t t = sim_truth(s);
    assert_true(t.contact);
    assert_int_equal(t.collisions, 1u);
    assert_true(fabs(t.x - (3.0 - 0.09)) < 1e-5); /* stopped at the surface */
    assert_true(t.x <= 3.0 - 0.09);
    /* Against the wall the wheels stall: the encoders counted what the body moved (to a
     * count), not the seconds of pushing after it stopped. */
    double enc = (double)sim_encoder_count(s, HAL_WHEEL_LEFT) * TEST_PI * 0.065 / 700.0;
    assert_true(fabs(enc - (t.x - 1.0)) < 2.0 * TEST_PI * 0.065 / 700.0);
    drive(s, -800, -800, 50); /* back off */
    t = sim_truth(s);
    assert_false(t.contact);
    drive(s, 800, 800, 200); /* and again */
    t = sim_truth(s);
    assert_true(t.contact);
    assert_int_equal(t.collisions, 2u);
    /* Turning against the wall is free: the body is a disc about the axle. */
    drive(s, 0, 0, 100);
    double x = sim_truth(s).x;
    drive(s, -500, 500, 100);
    t = sim_truth(s);
    assert_true(fabs(t.x - x) < 1e-12);
    assert_true(fabs(t.th) > 1.0);
    assert_true(t.contact);
    assert_int_equal(t.collisions, 2u);
    sim_destroy(s);
    room_free(&r);
}

/* Random drives for a long time: the body never overlaps anything, never crosses a wall. */
static void soak(const char *text, double top_speed, unsigned ticks, uint64_t seed)
{
    room_t r;
    test_room(&r, text);
    sim_params_t p;
    sim_params_default(&p);
    p.top_speed_mps = top_speed;
    sim_errors_t e;
    sim_errors_default(&e);
    sim_t *s = sim_create(&r, &p, &e, seed);
    assert_non_null(s);
    uint64_t st = seed * 7919u + 1u;
    unsigned left = 0;
    double min_clear = 1e9;
    double px = r.start_x;
    double py = r.start_y;
    for (unsigned k = 0; k < ticks; k++) {
        if (left == 0u) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            int16_t a = (int16_t)((int)((st >> 33) % 2001u) - 1000);
            int16_t b = (int16_t)((int)((st >> 45) % 2001u) - 1000);
            if ((st >> 20) % 3u == 0u) { /* often full ahead, into something */
                a = 1000;
                b = 1000;
            }
            sim_motor_set(s, HAL_WHEEL_LEFT, a);
            sim_motor_set(s, HAL_WHEEL_RIGHT, b);
            left = 20u + (unsigned)((st >> 8) % 300u);
        }
        left--;
        sim_step(s);
        sim_truth_t t = sim_truth(s);
        double c = room_clearance(&r, t.x, t.y, 1.0);
        min_clear = fmin(min_clear, c);
        if (c < p.body_radius_m - 1e-9) {
            fail_msg("tick %u: the body overlaps an obstacle at (%.4f, %.4f): clearance %.6f", k,
                     t.x, t.y, c);
        }
        /* The straight path of this tick crosses no wall (nothing is tunnelled through). */
        double dx = t.x - px;
        double dy = t.y - py;
        double len = hypot(dx, dy);
        if (len > 0.0) {
            double hit = room_ray(&r, px, py, atan2(dy, dx), len, NULL);
            assert_true(hit > len);
        }
        px = t.x;
        py = t.y;
    }
    sim_truth_t t = sim_truth(s);
    print_message("soak: %u ticks, %u collisions, min clearance %.6f m\n", ticks, t.collisions,
                  min_clear);
    assert_true(t.collisions > 10u);
    assert_true(min_clear < p.body_radius_m + 1e-4); /* it did get to the walls */
    sim_destroy(s);
    room_free(&r);
}

#define SOAK_ROOM                                                                                  \
    "wall 0 0 4 0\nwall 4 0 4 3\nwall 4 3 0 3\nwall 0 3 0 0\n"                                     \
    "wall 2 0 2 1.2\nwall 2 1.6 2 3\n" /* a thin dividing wall with a narrow gap */                \
    "wall 0.6 2.2 1.4 2.2\n"           /* a free-standing thin wall */                             \
    "poly 3 0.3 3.6 0.3 3.6 0.9\n"     /* a sharp corner */                                        \
    "circle 1 1 0.15\nbox 2.6 2.0 0.5 0.4\n"                                                       \
    "start 0.5 0.5 0\n"

static void test_soak_never_passes_through(void **state)
{
    (void)state;
    soak(SOAK_ROOM, 0.3, 200000u, 1u);
    soak(SOAK_ROOM, 0.3, 100000u, 2u);
}

static void test_soak_fast_robot_thin_walls(void **state)
{
    (void)state;
    /* 6 m/s: 6 cm a tick, more than half the body radius, so the step is split. */
    soak(SOAK_ROOM, 6.0, 50000u, 3u);
}

/* ---- determinism ------------------------------------------------------------------------- */

static void run_script(sim_t *s, sim_truth_t *out, unsigned n)
{
    for (unsigned k = 0; k < n; k++) {
        sim_motor_set(s, HAL_WHEEL_LEFT, (int16_t)((k / 97u) % 2u ? 900 : -300));
        sim_motor_set(s, HAL_WHEEL_RIGHT, (int16_t)((k / 61u) % 2u ? 800 : 200));
        if (k % 4u == 0u) {
            sim_servo_set_pulse(s, (uint16_t)(1000u + (k * 37u) % 1000u));
            (void)sim_sonar_trigger(s);
        }
        uint32_t echo = 0;
        (void)sim_sonar_poll(s, &echo);
        sim_step(s);
        out[k] = sim_truth(s);
    }
}

static void test_same_seed_same_run(void **state)
{
    (void)state;
    room_t r;
    char err[300];
    assert_int_equal(room_load(&r, HOST_ROOMS_DIR "/obstacles.room", NULL, err, sizeof err), 0);
    sim_errors_t e;
    sim_errors_default(&e);
    enum { N = 3000 };
    static sim_truth_t a[N];
    static sim_truth_t b[N];
    static sim_truth_t c[N];
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    memset(c, 0, sizeof c);
    sim_t *s1 = test_world(&r, &e, 42u);
    sim_t *s2 = test_world(&r, &e, 42u);
    sim_t *s3 = test_world(&r, &e, 43u);
    run_script(s1, a, N);
    run_script(s2, b, N);
    run_script(s3, c, N);
    for (unsigned k = 0; k < N; k++) {
        assert_true(a[k].x == b[k].x && a[k].y == b[k].y && a[k].th == b[k].th);
        assert_true(a[k].collisions == b[k].collisions && a[k].servo_deg == b[k].servo_deg);
    }
    sim_ping_t p1 = sim_last_ping(s1);
    sim_ping_t p2 = sim_last_ping(s2);
    assert_true(p1.range_m == p2.range_m && p1.echo_us == p2.echo_us && p1.kind == p2.kind);
    assert_true(a[N - 1].x != c[N - 1].x || a[N - 1].y != c[N - 1].y);
    sim_destroy(s1);
    sim_destroy(s2);
    sim_destroy(s3);
    room_free(&r);
}

static void test_create_refuses_bad_input(void **state)
{
    (void)state;
    sim_params_t p;
    sim_errors_t e;
    sim_params_default(&p);
    sim_errors_default(&e);
    const char *field = NULL;
    assert_int_equal(sim_params_check(&p, &e, &field), 0);
    p.motor_tau_s = 0.0;
    assert_int_equal(sim_params_check(&p, &e, &field), -1);
    assert_string_equal(field, "p.motor_tau_s");
    assert_null(sim_create(&big, &p, &e, 1u));
    sim_params_default(&p);
    e.sonar_dropout = (double)NAN;
    assert_int_equal(sim_params_check(&p, &e, &field), -1);
    assert_string_equal(field, "e.sonar_dropout");
    sim_errors_default(&e);
    p.sonar_timeout_us = 20000.0; /* a 4 m echo takes 23.3 ms */
    assert_int_equal(sim_params_check(&p, &e, &field), -1);
    assert_string_equal(field, "p.sonar_timeout_us");
    sim_params_default(&p);
    /* A body too big for where the room starts it. */
    room_t r;
    test_room(&r, "wall 0 0 4 0\nstart 1 0.2 0\n");
    p.body_radius_m = 0.25;
    assert_null(sim_create(&r, &p, &e, 1u));
    p.body_radius_m = 0.15;
    sim_t *s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    assert_int_equal(sim_place(s, 1.0, 0.1, 0.0), -1);
    assert_true(sim_truth(s).y == (double)0.2);
    sim_destroy(s);
    room_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_motor_first_order),
        cmocka_unit_test(test_encoders_count_rotation_and_wrap),
        cmocka_unit_test(test_place_keeps_the_encoders),
        cmocka_unit_test(test_ideal_odometry_matches_truth),
        cmocka_unit_test(test_unequal_wheels_curve_the_path),
        cmocka_unit_test(test_wheel_base_error_scales_turns),
        cmocka_unit_test(test_slip_grows_with_acceleration),
        cmocka_unit_test(test_wheel_noise_spreads_heading),
        cmocka_unit_test(test_servo_slew),
        cmocka_unit_test(test_contact_stops_and_counts),
        cmocka_unit_test(test_soak_never_passes_through),
        cmocka_unit_test(test_soak_fast_robot_thin_walls),
        cmocka_unit_test(test_same_seed_same_run),
        cmocka_unit_test(test_create_refuses_bad_input),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
