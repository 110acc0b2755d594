/* SPDX-License-Identifier: MIT */
/* The simulated sonar against published HC-SR04 measurements: incidence limits and long, wrong
 * readings. */
#include <math.h>

#include "host_test.h"

/*
 * The measurements (hal/host/README.md, "The sonar's levels", cites them):
 *
 * UNIVPM: Robotics-UNIVPM/mapper, sensore-sonar/Misure_prove.csv (commit 0b21404b) and
 * Relazione.md (867487dd). An HC-SR04 reads a credit-card-sized plastic card on a servo,
 * turned from facing it through 50° in 1° steps, one ping a step, at 2, 4, 6 and 10 cm
 * ("verticale": turned about the vertical, as a wall turns in the robot's plane), three
 * cycles each. Read here from the CSV: the first angle of each cycle whose reading is not
 * the card's (no echo, or more than 20 cm beyond it), and of the wrong readings from
 * there to 50°, those that are a long range (0.33-3.4 m) rather than the sensor's no-echo
 * value (335-340 cm, or 0).
 *
 * Beam data (GaryDyr/HC-SR04-beam-tests README, commit 0b6ffdd2, citing the Parallax
 * PING))) guide): up to which angle off the axis a flat target is still read. Kept normal
 * to the axis ("static", no part of it faces the sensor): Parallax 30° at 0.30 m falling
 * to 10° at 1.14 m; GaryDyr 20° at 0.15 m, 9° at 0.45 m, about 10° to 1.45 m. Turned to
 * face the sensor ("aimed"): Parallax about 25° up to 0.61 m, 20° to 1.66 m.
 *
 * Each series is reproduced in the simulator: the sensor faces a flat target (the card,
 * 85.6 mm; a 1 m panel for the beam data) turned through 0-50° about its middle, one ping
 * a degree, without the random errors (range noise, dropouts, ghosts: single pings in the
 * sources, and tested in test_sonar.c). The long readings come back by the room behind the
 * set-up, which the sources do not describe (the card was on a servo fixed to the side of
 * a table): here a 4 m x 3 m room with the set-up 0.7 m from its long wall and 1.5 m from
 * its short one, chosen before the shares were looked at, and the target turned either way
 * (its mirror toward the near wall, then the far one).
 */

/* A published limit: the first wrong angle (UNIVPM) or the beam's edge (beam data), deg. */
typedef struct {
    double d; /* the target's distance, m */
    int n;    /* figures */
    double deg[3];
} limits_t;

static const limits_t univpm[] = {
    {0.02, 3, {28.0, 28.0, 28.0}},
    {0.04, 3, {28.0, 26.0, 16.0}},
    {0.06, 3, {14.0, 15.0, 17.0}},
    {0.10, 3, {17.0, 16.0, 15.0}},
};

/* Wrong readings after the first wrong angle, of which long (not the no-echo value). */
static const struct {
    double d;
    int wrong, long_;
} univpm_wrong[] = {{0.02, 43, 43}, {0.04, 58, 47}, {0.06, 87, 42}, {0.10, 66, 48}};

/* The beam data at the robot's ranges: each series interpolated straight between its
 * figures (Parallax static, Parallax aimed, GaryDyr static). */
static const limits_t beam[] = {
    {0.30, 3, {30.0, 25.0, 14.5}}, {0.50, 3, {25.2, 25.0, 9.5}},  {0.70, 3, {20.5, 24.6, 10.0}},
    {0.90, 3, {15.7, 23.6, 10.0}}, {1.10, 3, {11.0, 22.7, 10.0}},
};

#define CARD_M 0.00076 /* a credit card's thickness (ISO/IEC 7810 ID-1) */
#define SX 1.0         /* the sensor, facing +x */
#define SY 0.7
#define LEVELS 3

typedef enum { READ_RIGHT, READ_LONG, READ_NONE } reading_t;

/* One ping at the target @p d m away, @p w m wide, turned by @p deg; its range into *range. */
static reading_t ping_turned(sim_sonar_level_t level, double d, double w, double deg, double *range)
{
    double th = deg * TEST_PI / 180.0;
    double ux = -sin(th) * 0.5 * w;
    double uy = cos(th) * 0.5 * w;
    /* The target is a plate of CARD_M, a polygon: its edges are as thin as a card's, where
     * a wall's free end would be round (ROOM_WALL_END_M). */
    double tx = cos(th) * 0.5 * CARD_M;
    double ty = sin(th) * 0.5 * CARD_M;
    double x1 = SX + d - ux;
    double y1 = SY - uy;
    double x2 = SX + d + ux;
    double y2 = SY + uy;
    char text[1024];
    snprintf(text, sizeof text,
             "wall -0.5 0 3.5 0\nwall 3.5 0 3.5 3\nwall 3.5 3 -0.5 3\nwall -0.5 3 -0.5 0\n"
             "poly %.12f %.12f %.12f %.12f %.12f %.12f %.12f %.12f\nstart %.12f %.12f 0\n",
             x1 - tx, y1 - ty, x2 - tx, y2 - ty, x2 + tx, y2 + ty, x1 + tx, y1 + ty, SX - 0.10, SY);
    room_t r;
    test_room(&r, text);
    sim_params_t p;
    sim_params_default(&p);
    p.sonar_x_m = 0.10; /* the body (5 cm) well behind the sensor, clear of the card */
    p.body_radius_m = 0.05;
    sim_errors_t e;
    sim_errors_ideal(&e);
    sim_errors_sonar(&e, level);
    sim_t *s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    uint32_t w_us = 0;
    hal_sonar_status_t st;
    for (int k = 0; (st = sim_sonar_poll(s, &w_us)) == HAL_SONAR_BUSY; k++) {
        assert_true(k < 10);
        sim_step(s);
    }
    sim_ping_t pg = sim_last_ping(s);
    sim_destroy(s);
    room_free(&r);
    *range = pg.range_m;
    if (st != HAL_SONAR_ECHO) {
        return READ_NONE;
    }
    if (pg.range_m > d + 0.2) {
        assert_int_equal(pg.kind, SIM_PING_MULTIPATH);
        assert_true(pg.range_m <= p.sonar_max_m);
        return READ_LONG;
    }
    return READ_RIGHT;
}

/* A series: the first wrong angle (51: none up to 50°), and the wrong readings from there. */
typedef struct {
    int first_wrong;
    int wrong, long_;
} series_t;

static series_t sweep(sim_sonar_level_t level, double d, double w, double sign)
{
    series_t sr = {51, 0, 0};
    for (int a = 0; a <= 50; a++) {
        double range;
        reading_t rd = ping_turned(level, d, w, sign * a, &range);
        if (rd != READ_RIGHT && sr.first_wrong > 50) {
            sr.first_wrong = a;
        }
        if (a >= sr.first_wrong && rd != READ_RIGHT) {
            sr.wrong++;
            sr.long_ += rd == READ_LONG;
        }
    }
    return sr;
}

static double lowest(const limits_t *l)
{
    double m = l->deg[0];
    for (int i = 1; i < l->n; i++) {
        m = fmin(m, l->deg[i]);
    }
    return m;
}

static double highest(const limits_t *l)
{
    double m = l->deg[0];
    for (int i = 1; i < l->n; i++) {
        m = fmax(m, l->deg[i]);
    }
    return m;
}

static double median3(const limits_t *l)
{
    double a = l->deg[0], b = l->deg[1], c = l->deg[2];
    return fmax(fmin(a, b), fmin(fmax(a, b), c));
}

/*
 * The limit each level gives a turned target, against the figures (tolerance 2°: the
 * sources read the first wrong angle once a cycle in 1° steps, and the simulated one is
 * found in the same steps; a flat target is met by the cone's edge ray at exactly the
 * turn less half the cone, so the rays' spacing adds nothing):
 *   - typical, at the card's distances: the middle of the three cycles (the level's knots
 *     are those figures); at the robot's ranges: within the beam data's spread, the
 *     figures of the aimed target being its top;
 *   - pessimistic: the lowest figure at every distance;
 *   - optimistic: above every figure (it reads a flat target right up to 52.5°);
 *   - and at every distance pessimistic <= typical <= optimistic.
 * Both turning directions give the same limit: a wrong reading begins where the direct
 * echo ends, whatever comes back instead.
 */
static void check_limits(const limits_t *set, size_t n, double w, bool at_card)
{
    for (size_t i = 0; i < n; i++) {
        const limits_t *l = &set[i];
        int got[LEVELS];
        for (int lv = 0; lv < LEVELS; lv++) {
            series_t a = sweep((sim_sonar_level_t)lv, l->d, w, 1.0);
            series_t b = sweep((sim_sonar_level_t)lv, l->d, w, -1.0);
            assert_int_equal(a.first_wrong, b.first_wrong);
            got[lv] = a.first_wrong;
        }
        int opt = got[SIM_SONAR_OPTIMISTIC];
        int typ = got[SIM_SONAR_TYPICAL];
        int pes = got[SIM_SONAR_PESSIMISTIC];
        print_message("%.2f m: published %g..%g, simulated optimistic %d typical %d "
                      "pessimistic %d\n",
                      l->d, lowest(l), highest(l), opt, typ, pes);
        if (at_card) {
            assert_true(fabs(typ - median3(l)) <= 2.0);
        } else {
            assert_true(typ >= lowest(l) - 2.0 && typ <= highest(l) + 2.0);
        }
        assert_true(fabs(pes - lowest(l)) <= 2.0);
        assert_true(opt >= highest(l) + 2.0);
        assert_true(pes <= typ && typ <= opt);
    }
}

static void test_limits_at_the_card(void **state)
{
    (void)state;
    check_limits(univpm, sizeof univpm / sizeof univpm[0], 0.0856, true);
}

static void test_limits_at_the_robots_ranges(void **state)
{
    (void)state;
    check_limits(beam, sizeof beam / sizeof beam[0], 1.0, false);
}

/*
 * Beyond the limit, the typical level reads long, wrong ranges rather than only timeouts.
 * Published: 180 of the 254 wrong readings at 2-10 cm are long (71 %), by distance 100,
 * 81, 48 and 73 %. How many depends on the room behind the set-up, which is modelled, not
 * known: the simulated share over the four distances and both directions must lie within
 * the published distances' spread (48-100 %), and every distance must give some. The
 * optimistic level, the model before, gives no wrong reading at all up to 50°.
 */
static void test_long_wrong_readings_at_the_card(void **state)
{
    (void)state;
    int wrong = 0;
    int long_ = 0;
    int pub_wrong = 0;
    int pub_long = 0;
    for (size_t i = 0; i < sizeof univpm_wrong / sizeof univpm_wrong[0]; i++) {
        double d = univpm_wrong[i].d;
        series_t a = sweep(SIM_SONAR_TYPICAL, d, 0.0856, 1.0);
        series_t b = sweep(SIM_SONAR_TYPICAL, d, 0.0856, -1.0);
        print_message("%.2f m: long %d of %d wrong (published %d of %d)\n", d, a.long_ + b.long_,
                      a.wrong + b.wrong, univpm_wrong[i].long_, univpm_wrong[i].wrong);
        assert_true(a.long_ + b.long_ > 0);
        wrong += a.wrong + b.wrong;
        long_ += a.long_ + b.long_;
        pub_wrong += univpm_wrong[i].wrong;
        pub_long += univpm_wrong[i].long_;

        series_t o = sweep(SIM_SONAR_OPTIMISTIC, d, 0.0856, 1.0);
        assert_int_equal(o.wrong, 0);
    }
    double share = (double)long_ / wrong;
    print_message("long share %.2f (published %.2f)\n", share, (double)pub_long / pub_wrong);
    assert_int_equal(pub_wrong, 254);
    assert_int_equal(pub_long, 180);
    assert_true(share >= 0.48 && share <= 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limits_at_the_card),
        cmocka_unit_test(test_limits_at_the_robots_ranges),
        cmocka_unit_test(test_long_wrong_readings_at_the_card),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
