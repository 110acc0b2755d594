/* SPDX-License-Identifier: MIT */
/* Tests of the odometry: fixed point against a double-precision Eq. 8-12, exact cases,
 * counter wrap-around and the UMBmark calibration factors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "world_origin.h"
#include "slam/config.h"
#include "slam/odometry.h"
#include "test_rng.h"

static const double PI = 3.14159265358979323846;
static const double Q30 = 1073741824.0;
static const double BAM_RAD = 6.283185307179586476925 / 4294967296.0;

/* ---- the double-precision reference: Eq. 8-12 with the midpoint heading ---------------- */

typedef struct {
    double x_um;
    double y_um;
    double th;      /* rad */
    double path_um; /* distance travelled by the axle centre */
    double um_per_count[2];
    double base_um;
} ref_odom_t;

static void ref_init(ref_odom_t *r, const slam_config_t *c)
{
    r->um_per_count[0] =
        PI * c->wheel_diameter_left_um * (c->cal_left / Q30) / c->encoder_counts_per_rev;
    r->um_per_count[1] =
        PI * c->wheel_diameter_right_um * (c->cal_right / Q30) / c->encoder_counts_per_rev;
    r->base_um = c->wheel_base_um * (c->cal_base / Q30);
    r->x_um = c->start_x_um;
    r->y_um = c->start_y_um;
    r->th = c->start_heading_mdeg * PI / 180000.0;
    r->path_um = 0.0;
}

static void ref_step(ref_odom_t *r, int dl, int dr)
{
    double ul = dl * r->um_per_count[0];
    double ur = dr * r->um_per_count[1];
    double dth = (ur - ul) / r->base_um; /* Eq. 8 */
    double du = (ur + ul) / 2.0;         /* Eq. 9 */
    double mid = r->th + dth / 2.0;
    r->x_um += du * cos(mid); /* Eq. 10 */
    r->y_um += du * sin(mid); /* Eq. 11 */
    r->th += dth;             /* Eq. 12 */
    r->path_um += fabs(du);
}

/* ---- a robot whose encoders the tests turn ----------------------------------------------- */

typedef struct {
    odom_t o;
    ref_odom_t ref;
    uint16_t count[2];
} rig_t;

static void rig_init(rig_t *g, const slam_config_t *c, uint16_t left, uint16_t right)
{
    g->count[0] = left;
    g->count[1] = right;
    odom_init(&g->o, c, left, right);
    ref_init(&g->ref, c);
}

static void rig_step(rig_t *g, int dl, int dr)
{
    g->count[0] = (uint16_t)(g->count[0] + dl);
    g->count[1] = (uint16_t)(g->count[1] + dr);
    odom_step(&g->o, g->count[0], g->count[1]);
    ref_step(&g->ref, dl, dr);
}

static double heading_err_rad(const rig_t *g)
{
    double fixed_th = (double)(g->o.heading_q16 & 0xFFFFFFFFFFFFull) / 65536.0 * BAM_RAD;
    double e = fmod(fixed_th - g->ref.th, 2.0 * PI);
    if (e > PI) {
        e -= 2.0 * PI;
    } else if (e < -PI) {
        e += 2.0 * PI;
    }
    return fabs(e);
}

/* A Q48.16 µm accumulator in µm. */
static double um(q48_16_t v)
{
    return (double)v / 65536.0;
}

static double pos_err_um(const rig_t *g)
{
    return hypot(um(g->o.x_um) - g->ref.x_um, um(g->o.y_um) - g->ref.y_um);
}

/* ---- random drives ------------------------------------------------------------------------ */

/* Per-tick wheel counts of one segment of a random drive. At 700 counts per 204 mm turn,
 * 10 counts per 10 ms tick is 0.29 m/s, the robot's top speed. */
typedef enum { SEG_STRAIGHT, SEG_ARC, SEG_SPIN, SEG_ALTERNATE, SEG_KINDS } seg_kind_t;

static void random_drive(rig_t *g, test_rng_t *rng, int steps)
{
    int left = 0;
    int right = 0;
    int remaining = 0;
    seg_kind_t kind = SEG_STRAIGHT;
    for (int i = 0; i < steps; i++) {
        if (remaining == 0) {
            kind = (seg_kind_t)test_rng_range(rng, 0, SEG_KINDS - 1);
            remaining = test_rng_range(rng, 1, 3000);
            int v = test_rng_range(rng, -10, 10);
            switch (kind) {
            case SEG_STRAIGHT:
                left = right = v;
                break;
            case SEG_ARC:
                left = v;
                right = v + test_rng_range(rng, -6, 6);
                break;
            case SEG_SPIN:
                left = v;
                right = -v;
                break;
            default:
                left = test_rng_range(rng, -10, 10);
                right = test_rng_range(rng, -10, 10);
                break;
            }
        }
        remaining--;
        if (kind == SEG_ALTERNATE) {
            left = -left;
            right = -right;
        }
        /* One count of jitter now and then, as a real encoder gives. */
        int jitter = (test_rng_u64(rng) & 7u) == 0u ? 1 : 0;
        rig_step(g, left + jitter, right);
    }
}

/* Error bounds after 60 000 steps (10 minutes at 10 ms). The heading is integrated with
 * exact gains and 16 extra fraction bits, so its error stays near 1e-9 rad. The position
 * error is the sine table's (at most 5e-6 on each of cos and sin, so 7.1e-6 of the
 * distance travelled) plus rounding. At the default robot's top speed, 10 minutes are at
 * most 175 m of travel, so the bound there is 1.25 mm. */
#define BOUND_HEADING_RAD 1e-7
#define BOUND_POS_PER_UM 7.1e-6
#define BOUND_POS_UM(path_um) (2.0 + BOUND_POS_PER_UM * (path_um))

static void random_config(slam_config_t *c, test_rng_t *rng, int vary)
{
    test_config_default(c);
    if (vary) {
        c->wheel_diameter_left_um = (uint32_t)test_rng_range(rng, 30000, 120000);
        c->wheel_diameter_right_um =
            c->wheel_diameter_left_um + (uint32_t)test_rng_range(rng, 0, 500);
        c->wheel_base_um = (uint32_t)test_rng_range(rng, 80000, 400000);
        c->encoder_counts_per_rev = (uint32_t)test_rng_range(rng, 100, 4000);
        c->cal_left = FIX_Q30_ONE + test_rng_range(rng, -2000000, 2000000);
        c->cal_right = FIX_Q30_ONE + test_rng_range(rng, -2000000, 2000000);
        c->cal_base = FIX_Q30_ONE + test_rng_range(rng, -20000000, 20000000);
        c->start_x_um = test_rng_range(rng, -3000000, 3000000);
        c->start_y_um = test_rng_range(rng, -3000000, 3000000);
        c->start_heading_mdeg = test_rng_range(rng, -180000, 180000);
    }
}

/* 10 000 random drives of 60 000 steps each, on the default robot and on random ones (the
 * builds other than the plain host's drive the first 1 000 of them: tests/CMakeLists.txt). */
#ifndef TEST_ODOMETRY_DRIVES
#define TEST_ODOMETRY_DRIVES 10000
#endif
#define DRIVES TEST_ODOMETRY_DRIVES
#define STEPS 60000

static void test_random_drives_against_double(void **state)
{
    (void)state;
    double worst_pos_default = 0.0; /* the default robot, µm */
    double worst_ratio = 0.0;       /* any robot, error per distance */
    double worst_th = 0.0;
    test_rng_t rng = {2024u};
    for (int d = 0; d < DRIVES; d++) {
        slam_config_t c;
        int vary = d % 2;
        random_config(&c, &rng, vary);
        rig_t g;
        rig_init(&g, &c, (uint16_t)test_rng_u64(&rng), (uint16_t)test_rng_u64(&rng));
        random_drive(&g, &rng, STEPS);
        double ep = pos_err_um(&g);
        double eh = heading_err_rad(&g);
        assert_true(ep <= BOUND_POS_UM(g.ref.path_um));
        assert_true(eh <= BOUND_HEADING_RAD);
        if (!vary && ep > worst_pos_default) {
            worst_pos_default = ep;
        }
        if (g.ref.path_um > 0.0 && ep / g.ref.path_um > worst_ratio) {
            worst_ratio = ep / g.ref.path_um;
        }
        worst_th = eh > worst_th ? eh : worst_th;
    }
    printf("%d drives x %d steps: worst position error %.1f um on the default robot "
           "(bound %.0f um), %.2g of the distance on any (bound %.2g); "
           "worst heading error %.2g rad (bound %.0g)\n",
           DRIVES, STEPS, worst_pos_default, BOUND_POS_UM(175e6), worst_ratio, BOUND_POS_PER_UM,
           worst_th, BOUND_HEADING_RAD);
    assert_true(worst_pos_default <= BOUND_POS_UM(175e6));
}

static void test_straight_line_is_exact(void **state)
{
    (void)state;
    slam_config_t c;
    test_config_default(&c);
    rig_t g;
    rig_init(&g, &c, 100u, 200u);
    for (int i = 0; i < 1000; i++) {
        rig_step(&g, 7, 7);
    }
    odom_pose_t p = odom_pose(&g.o);
    assert_int_equal(p.heading, 0u);
    assert_int_equal(g.o.y_um, 0);
    assert_int_equal(g.o.x_um, 7000 * g.o.um_per_count[ODOM_LEFT]);
    /* 7000 counts of a 65 mm wheel with 700 counts a turn: 10 turns, 2.042 m. */
    assert_true(fabs(p.x_um - 10.0 * PI * 65000.0) <= 1.0);
}

static void test_full_turn_in_place_returns_to_start(void **state)
{
    (void)state;
    slam_config_t c;
    test_config_default(&c);
    c.start_heading_mdeg = 30000;
    c.start_x_um = 1234567;
    c.start_y_um = -7654321;
    rig_t g;
    rig_init(&g, &c, 0u, 0u);
    odom_pose_t start = odom_pose(&g.o);
    /* With a 130 mm base and 65 mm wheels of 700 counts, a full turn is 1400 counts per
     * wheel, in any slicing. */
    int moved = 0;
    test_rng_t rng = {5u};
    while (moved < 1400) {
        int n = test_rng_range(&rng, 1, 9);
        n = moved + n > 1400 ? 1400 - moved : n;
        rig_step(&g, -n, n);
        moved += n;
        if (moved == 700) {
            odom_pose_t half = odom_pose(&g.o);
            assert_true(
                llabs((long long)fix_bam_diff(half.heading, start.heading + FIX_BAM_HALF)) <= 1);
        }
    }
    odom_pose_t end = odom_pose(&g.o);
    assert_true(llabs((long long)fix_bam_diff(end.heading, start.heading)) <= 1);
    assert_int_equal(end.x_um, start.x_um);
    assert_int_equal(end.y_um, start.y_um);
}

static void test_encoder_wraparound(void **state)
{
    (void)state;
    slam_config_t c;
    test_config_default(&c);
    rig_t near_wrap;
    rig_t plain;
    rig_init(&near_wrap, &c, 65530u, 5u);
    rig_init(&plain, &c, 30000u, 30000u);
    static const int script[][2] = {{9, -9}, {10, 10}, {-10, -10}, {-10, 3}, {4, -8}, {10, 10}};
    for (size_t i = 0; i < sizeof script / sizeof script[0]; i++) {
        for (int k = 0; k < 50; k++) {
            rig_step(&near_wrap, script[i][0], script[i][1]);
            rig_step(&plain, script[i][0], script[i][1]);
        }
    }
    assert_int_equal(near_wrap.o.x_um, plain.o.x_um);
    assert_int_equal(near_wrap.o.y_um, plain.o.y_um);
    assert_int_equal(near_wrap.o.heading_q16, plain.o.heading_q16);
    assert_true(pos_err_um(&near_wrap) < 1.0);
    /* The largest step either way: +32767 and -32768 counts in one tick. */
    odom_t o;
    odom_init(&o, &c, 0u, 0u);
    odom_step(&o, 32767u, 32767u);
    assert_true(o.x_um > 0);
    odom_init(&o, &c, 0u, 0u);
    odom_step(&o, 32768u, 32768u);
    assert_true(o.x_um < 0);
}

static void test_umbmark_factors(void **state)
{
    (void)state;
    q1_30_t cl;
    q1_30_t cr;
    odom_umbmark_factors(FIX_Q30_ONE, &cl, &cr);
    assert_int_equal(cl, FIX_Q30_ONE);
    assert_int_equal(cr, FIX_Q30_ONE);
    q1_30_t ed = (q1_30_t)(1.02 * Q30);
    odom_umbmark_factors(ed, &cl, &cr);
    assert_true(fabs(cl / Q30 - 2.0 / 2.02) < 1e-9);
    assert_true(fabs(cr / Q30 - 2.0 * 1.02 / 2.02) < 1e-9);
    /* The corrected diameters keep their mean and have the measured ratio. */
    assert_true(fabs(((double)cl + cr) / Q30 - 2.0) < 1e-9);
    assert_true(fabs((double)cr / cl - 1.02) < 1e-9);
}

/* A robot whose wheels are 64 mm and 66 mm where 65 mm were meant (E_d = 1.03125), driven
 * with equal counts: it curves to the left. Uncalibrated odometry believes in a straight
 * line; with the UMBmark factors it follows the true path. */
static void test_calibration_unequal_diameters(void **state)
{
    (void)state;
    double ed = 66.0 / 64.0;
    slam_config_t nominal;
    test_config_default(&nominal);
    slam_config_t truth = nominal;
    truth.wheel_diameter_left_um = 64000u;
    truth.wheel_diameter_right_um = 66000u;
    slam_config_t calibrated = nominal;
    odom_umbmark_factors((q1_30_t)(ed * Q30), &calibrated.cal_left, &calibrated.cal_right);

    rig_t real;
    rig_t uncal;
    rig_t cal;
    rig_init(&real, &truth, 0u, 0u);
    rig_init(&uncal, &nominal, 0u, 0u);
    rig_init(&cal, &calibrated, 0u, 0u);
    for (int i = 0; i < 3000; i++) { /* 30 s at 0.29 m/s: 8.8 m */
        rig_step(&real, 10, 10);
        rig_step(&uncal, 10, 10);
        rig_step(&cal, 10, 10);
    }
    /* The real robot turned left; uncalibrated odometry saw no turn at all. */
    assert_true(real.ref.th > 0.05);
    assert_int_equal(odom_pose(&uncal.o).heading, 0u);
    double err_uncal = hypot(um(uncal.o.x_um) - real.ref.x_um, um(uncal.o.y_um) - real.ref.y_um);
    double err_cal = hypot(um(cal.o.x_um) - real.ref.x_um, um(cal.o.y_um) - real.ref.y_um);
    printf("unequal wheels, 8.8 m: position error %.1f mm uncalibrated, %.3f mm calibrated\n",
           err_uncal / 1000.0, err_cal / 1000.0);
    assert_true(err_uncal > 100000.0);
    assert_true(err_cal < 1000.0);
}

/* A robot whose real wheel base is 3 % longer than nominal turns less than odometry thinks;
 * with E_b in cal_base the turn is right. */
static void test_calibration_wheel_base(void **state)
{
    (void)state;
    double eb = 1.03;
    slam_config_t nominal;
    test_config_default(&nominal);
    slam_config_t truth = nominal;
    truth.wheel_base_um = (uint32_t)lround(130000.0 * eb);
    slam_config_t calibrated = nominal;
    calibrated.cal_base = (q1_30_t)(eb * Q30);

    rig_t real;
    rig_t uncal;
    rig_t cal;
    rig_init(&real, &truth, 0u, 0u);
    rig_init(&uncal, &nominal, 0u, 0u);
    rig_init(&cal, &calibrated, 0u, 0u);
    for (int i = 0; i < 560; i++) { /* 2800 counts a wheel: two nominal turns */
        rig_step(&real, -5, 5);
        rig_step(&uncal, -5, 5);
        rig_step(&cal, -5, 5);
    }
    double th_real = fmod(real.ref.th, 2.0 * PI);
    double th_uncal = odom_pose(&uncal.o).heading * BAM_RAD;
    double th_cal = odom_pose(&cal.o).heading * BAM_RAD;
    /* Two nominal turns are 4π/1.03 real: 0.366 rad short of a full second turn. */
    assert_true(fabs(th_uncal) < 1e-6 || fabs(th_uncal - 2.0 * PI) < 1e-6);
    assert_true(fabs(th_cal - th_real) < 1e-6);
    assert_true(fabs(th_real - (4.0 * PI / eb - 2.0 * PI)) < 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straight_line_is_exact),
        cmocka_unit_test(test_full_turn_in_place_returns_to_start),
        cmocka_unit_test(test_encoder_wraparound),
        cmocka_unit_test(test_umbmark_factors),
        cmocka_unit_test(test_calibration_unequal_diameters),
        cmocka_unit_test(test_calibration_wheel_base),
        cmocka_unit_test(test_random_drives_against_double),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
