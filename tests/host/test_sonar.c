/* SPDX-License-Identifier: MIT */
/* Tests of the simulated sonar: range, cone, grazing loss, multipath, levels, timing, noise. */
#include <math.h>

#include "host_test.h"

#define SOUND 343.0

/* A 12 m x 8 m hall: its east wall at x = 10 m, its others far away. */
#define HALL "wall -2 -4 10 -4\nwall 10 -4 10 4\nwall 10 4 -2 4\nwall -2 4 -2 -4\n"

/* Ping, a measurement cycle (60 ms, the HC-SR04 datasheet's) after the last ping, and
 * wait: the status at the end and the ticks it took. */
static hal_sonar_status_t ping(sim_t *s, uint32_t *echo_us, unsigned *ticks)
{
    sim_ping_t last = sim_last_ping(s);
    while (last.kind != SIM_PING_NONE && sim_truth(s).time_us - last.time_us < 60000u) {
        sim_step(s);
    }
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    unsigned n = 0;
    for (;;) {
        hal_sonar_status_t st = sim_sonar_poll(s, echo_us);
        if (st != HAL_SONAR_BUSY) {
            if (ticks != NULL) {
                *ticks = n;
            }
            return st;
        }
        sim_step(s);
        n++;
        assert_true(n < 10u);
    }
}

static sim_t *ideal_with(const room_t *r, double grazing_deg)
{
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.grazing_deg = grazing_deg;
    return test_world(r, &e, 7u);
}

/* Point the servo and let it get there. */
static void servo_to(sim_t *s, uint16_t pulse)
{
    sim_servo_set_pulse(s, pulse);
    for (int k = 0; k < 40; k++) {
        sim_step(s);
    }
}

static void test_head_on_range(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "start 0 0 0\n");
    sim_t *s = ideal_with(&r, 45.0);
    for (int i = 0; i < 40; i++) {
        double x = 0.5 + 0.2 * i; /* sonar at x + 0.05, wall at 10: 9.45 .. 1.65 m */
        assert_int_equal(sim_place(s, x, 0.3, 0.0), 0);
        uint32_t w = 0;
        hal_sonar_status_t st = ping(s, &w, NULL);
        double d = 10.0 - (x + 0.05);
        sim_ping_t p = sim_last_ping(s);
        assert_true(fabs(p.true_range_m - d) < 1e-9 || d > 4.0);
        if (d > 4.0) { /* beyond the HC-SR04's 4 m */
            assert_int_equal(st, HAL_SONAR_TIMEOUT);
            assert_int_equal(p.kind, SIM_PING_NOTHING);
            assert_true(p.true_range_m == -1.0);
            continue;
        }
        assert_int_equal(st, HAL_SONAR_ECHO);
        assert_int_equal(p.kind, SIM_PING_ECHO);
        /* Width = round trip in µs; the firmware's range = width · c / 2. */
        assert_int_equal(w, (uint32_t)lround(2.0 * d / SOUND * 1e6));
        assert_true(fabs(w * SOUND / 2e6 - d) < 0.0002);
        assert_true(fabs(p.range_m - d) < 1e-9);
    }
    sim_destroy(s);
    room_free(&r);
}

/* A screen met end-on: its free end answers (a wall's end is round, ROOM_WALL_END_M), even
 * at a narrow incidence limit, where a line of no thickness would give nothing. */
static void test_a_screen_end_on_answers(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "wall 3 0 5 0\nstart 0 0 0\n");
    sim_t *s = ideal_with(&r, 5.0);
    assert_int_equal(sim_place(s, 1.0, 0.0, 0.0), 0);
    uint32_t w = 0;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    sim_ping_t p = sim_last_ping(s);
    assert_int_equal(p.kind, SIM_PING_ECHO);
    assert_true(fabs(p.range_m - (3.0 - ROOM_WALL_END_M - 1.05)) < 1e-9);
    sim_destroy(s);
    room_free(&r);
}

static void test_echo_waits_for_time_of_flight(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "start 7 0 0\n"); /* 2.95 m: 17 201 µs */
    sim_t *s = ideal_with(&r, 45.0);
    uint64_t t0 = sim_truth(s).time_us;
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    assert_int_equal(sim_sonar_trigger(s), HAL_EBUSY); /* one ping at a time */
    uint32_t w = 0;
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_BUSY);
    sim_step(s); /* 10 ms */
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_BUSY);
    assert_int_equal(sim_sonar_trigger(s), HAL_EBUSY);
    sim_step(s); /* 20 ms: past 17.2 ms */
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_ECHO);
    assert_int_equal(w, 17201u);
    assert_true(sim_truth(s).time_us - t0 >= w);
    assert_true(sim_last_ping(s).time_us == t0);
    /* Reported once, then idle. */
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_IDLE);
    sim_step(s);
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_IDLE);

    /* A result that came but was never read is replaced by a new ping. */
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    sim_step(s);
    sim_step(s);
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_BUSY);
    sim_destroy(s);
    room_free(&r);
}

static void test_timeout_after_38_ms(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "start 0 0 180\n"); /* the west wall 2 m behind... facing it: 1.95 */
    sim_t *s = ideal_with(&r, 45.0);
    assert_int_equal(sim_place(s, 0.0, 0.0, 0.0), 0); /* facing the east wall, 9.95 m */
    uint32_t w = 12345u;
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    for (int k = 0; k < 3; k++) {
        sim_step(s);
        assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_BUSY); /* 10, 20, 30 ms */
        assert_int_equal(sim_sonar_trigger(s), HAL_EBUSY);
    }
    sim_step(s); /* 40 ms */
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_TIMEOUT);
    assert_int_equal(w, 12345u); /* untouched without an echo */
    assert_int_equal(sim_sonar_poll(s, &w), HAL_SONAR_IDLE);
    assert_int_equal(sim_last_ping(s).kind, SIM_PING_NOTHING);
    sim_destroy(s);
    room_free(&r);
}

static void test_cone_takes_the_nearest(void **state)
{
    (void)state;
    /* Sonar at (1.05, 0). Posts 1 m away at 5° (inside the 7.5° half-cone) and 0.8 m
       away at -15° (wholly outside it), then a pencil-thin one at 3.3°, between two of
       the cone's rays. */
    char text[512];
    double c5x = 1.05 + 1.0 * cos(5.0 * TEST_PI / 180.0);
    double c5y = 1.0 * sin(5.0 * TEST_PI / 180.0);
    double c10x = 1.05 + 0.8 * cos(15.0 * TEST_PI / 180.0);
    double c10y = 0.8 * sin(-15.0 * TEST_PI / 180.0);
    snprintf(text, sizeof text,
             HALL "circle %.12f %.12f 0.05\ncircle %.12f %.12f 0.05\n"
                  "start 1 0 0\n",
             c5x, c5y, c10x, c10y);
    room_t r;
    test_room(&r, text);
    sim_t *s = ideal_with(&r, 45.0);
    uint32_t w;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    sim_ping_t p = sim_last_ping(s);
    assert_true(fabs(p.range_m - 0.95) < 1e-9); /* the 5° post, not the one at 0.75 */
    room_free(&r);
    sim_destroy(s);

    snprintf(text, sizeof text, HALL "circle %.12f %.12f 0.004\nstart 1 0 0\n",
             1.05 + 1.5 * cos(3.3 * TEST_PI / 180.0), 1.5 * sin(3.3 * TEST_PI / 180.0));
    test_room(&r, text);
    s = ideal_with(&r, 45.0);
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    assert_true(fabs(sim_last_ping(s).range_m - 1.496) < 1e-9);
    sim_destroy(s);
    room_free(&r);
}

static void test_servo_points_the_beam(void **state)
{
    (void)state;
    /* A post 1.5 m away 25° to the left of the sonar: the servo's 65° (Eq. 3). */
    char text[512];
    double a = 25.0 * TEST_PI / 180.0;
    snprintf(text, sizeof text, HALL "circle %.12f %.12f 0.1\nstart 1 0 0\n", 1.05 + 1.5 * cos(a),
             1.5 * sin(a));
    room_t r;
    test_room(&r, text);
    sim_t *s = ideal_with(&r, 45.0);
    uint32_t w;
    /* Straight ahead the post is outside the cone and the wall beyond 4 m. */
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_TIMEOUT);
    servo_to(s, 1222); /* 64.98° */
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    sim_ping_t p = sim_last_ping(s);
    assert_true(fabs(p.range_m - 1.4) < 1e-3);
    assert_true(fabs(p.servo_deg - 64.98) < 1e-9);
    assert_true(fabs(p.bearing - (90.0 - 64.98) * TEST_PI / 180.0) < 1e-9);
    /* A servo still on its way points the beam where it is, not where it was told. */
    servo_to(s, 1500);
    sim_servo_set_pulse(s, 1222);
    sim_step(s); /* 84° after one tick */
    assert_int_equal(sim_sonar_trigger(s), HAL_OK);
    assert_true(fabs(sim_last_ping(s).servo_deg - 84.0) < 1e-9);
    sim_destroy(s);
    room_free(&r);
}

/* A wall 1 m ahead of the sonar, tilted so the beam axis meets it at @p inc_deg. */
static void tilted_wall(room_t *r, double inc_deg)
{
    double a = (90.0 - inc_deg) * TEST_PI / 180.0; /* the wall's angle to the beam */
    double hx = 1.05 + 1.0;
    char text[512];
    snprintf(text, sizeof text, "wall %.12f %.12f %.12f %.12f\nstart 1 0 0\n", hx - 3.0 * cos(a),
             -3.0 * sin(a), hx + 3.0 * cos(a), 3.0 * sin(a));
    test_room(r, text);
}

static void test_grazing_loses_the_echo(void **state)
{
    (void)state;
    static const struct {
        double inc;
        double grazing;
        hal_sonar_status_t want;
        sim_ping_kind_t kind;
    } cases[] = {
        {0.0, 45.0, HAL_SONAR_ECHO, SIM_PING_ECHO},
        {30.0, 45.0, HAL_SONAR_ECHO, SIM_PING_ECHO},
        {50.0, 45.0, HAL_SONAR_ECHO, SIM_PING_ECHO}, /* the cone's edge meets it at 42.5° */
        {53.0, 45.0, HAL_SONAR_TIMEOUT, SIM_PING_GRAZING},
        {75.0, 45.0, HAL_SONAR_TIMEOUT, SIM_PING_GRAZING},
        {75.0, 80.0, HAL_SONAR_ECHO, SIM_PING_ECHO},
        {75.0, 0.0, HAL_SONAR_ECHO, SIM_PING_ECHO}, /* grazing loss off */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        room_t r;
        tilted_wall(&r, cases[i].inc);
        sim_t *s = ideal_with(&r, cases[i].grazing);
        uint32_t w = 0;
        hal_sonar_status_t st = ping(s, &w, NULL);
        sim_ping_t p = sim_last_ping(s);
        if (st != cases[i].want || p.kind != cases[i].kind) {
            fail_msg("case %zu (incidence %g°, limit %g°): status %d kind %d", i, cases[i].inc,
                     cases[i].grazing, (int)st, (int)p.kind);
        }
        assert_true(p.true_range_m > 0.0 && p.true_range_m <= 1.0 + 1e-9);
        if (st == HAL_SONAR_ECHO) {
            assert_true(p.range_m <= 1.0 + 1e-9 && p.range_m > 0.3);
        }
        sim_destroy(s);
        room_free(&r);
    }
}

/* A ROS map of 80 x 40 pixels of 5 cm, read through the loader into r: walls round its edge,
 * and down pixel column `column` too when that lies inside. Its files are removed again
 * (the room keeps what it read). */
static void raster_box(room_t *r, const char *name, int column)
{
    char tag[64];
    snprintf(tag, sizeof tag, "%s.pgm", name);
    const char *img = test_path(tag);
    FILE *f = fopen(img, "wb");
    assert_non_null(f);
    fprintf(f, "P5\n80 40\n255\n");
    for (int y = 0; y < 40; y++) {
        for (int x = 0; x < 80; x++) {
            fputc(x == column || x == 0 || x == 79 || y == 0 || y == 39 ? 0 : 254, f);
        }
    }
    fclose(f);
    char yaml_text[600];
    snprintf(yaml_text, sizeof yaml_text,
             "image: %s\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
             "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
             img);
    snprintf(tag, sizeof tag, "%s.yaml", name);
    const char *yaml = test_write(tag, yaml_text);
    char err[300];
    assert_int_equal(room_load(r, yaml, NULL, err, sizeof err), 0);
    unlink(img);
    unlink(yaml);
}

static void test_raster_head_on(void **state)
{
    (void)state;
    /* A ROS map with a wall of pixels at x = 2.0..2.05, read through the loader. */
    room_t r;
    raster_box(&r, "sonar", 40);
    r.start_x = 1.0;
    r.start_y = 1.0;
    sim_t *s = ideal_with(&r, 45.0);
    uint32_t w;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    assert_true(fabs(sim_last_ping(s).range_m - 0.95) < 1e-9);
    sim_destroy(s);
    room_free(&r);
}

static void test_noise_dropouts_and_ghosts(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "start 8 0 0\n"); /* 1.95 m */
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.sonar_noise_m = 0.01;
    e.sonar_dropout = 0.03;
    e.sonar_ghost = 0.01;
    e.grazing_deg = 45.0;
    sim_t *s = test_world(&r, &e, 2024u);
    enum { N = 20000 };
    unsigned drops = 0;
    unsigned ghosts = 0;
    unsigned echoes = 0;
    double sum = 0.0;
    double sum2 = 0.0;
    double ghost_sum = 0.0;
    for (int i = 0; i < N; i++) {
        uint32_t w = 0;
        unsigned ticks = 0;
        hal_sonar_status_t st = ping(s, &w, &ticks);
        sim_ping_t p = sim_last_ping(s);
        switch (p.kind) {
        case SIM_PING_DROPOUT:
            drops++;
            assert_int_equal(st, HAL_SONAR_TIMEOUT);
            assert_int_equal(ticks, 4u); /* 38 ms: the fourth tick */
            break;
        case SIM_PING_GHOST:
            ghosts++;
            assert_int_equal(st, HAL_SONAR_ECHO);
            assert_true(p.range_m >= 0.02 && p.range_m <= 4.0);
            ghost_sum += p.range_m;
            break;
        case SIM_PING_ECHO: {
            echoes++;
            assert_int_equal(st, HAL_SONAR_ECHO);
            double d = w * SOUND / 2e6;
            sum += d;
            sum2 += d * d;
            break;
        }
        default:
            fail_msg("unexpected ping kind %d", (int)p.kind);
        }
        assert_int_equal(p.echo_us, st == HAL_SONAR_ECHO ? w : 0u);
    }
    /* Binomial counts: 3 % of 20 000 is 600 ± 24 (1σ), 1 % of the rest 194 ± 14; allow 5σ. */
    print_message("dropouts %u, ghosts %u, echoes %u\n", drops, ghosts, echoes);
    assert_true(drops > 600u - 120u && drops < 600u + 120u);
    assert_true(ghosts > 194u - 70u && ghosts < 194u + 70u);
    /* Ghost ranges are uniform over 0.02 .. 4 m: mean 2.01, sd 1.15; 5σ of the mean is 0.41. */
    assert_true(fabs(ghost_sum / ghosts - 2.01) < 0.41);
    /* Range noise: mean the true 1.95 m, sd 10 mm (within 10 %). */
    double mean = sum / echoes;
    double sd = sqrt(sum2 / echoes - mean * mean);
    print_message("range mean %.5f m, sd %.5f m\n", mean, sd);
    assert_true(fabs(mean - 1.95) < 0.001);
    assert_true(fabs(sd - 0.01) < 0.001);
    sim_destroy(s);
    room_free(&r);
}

/* Pings sooner than the measurement cycle hear the last ping's sound coming back again:
 * its echo bounces between the sensor and the wall at every multiple of the round trip. */
static void test_late_echo_when_triggers_come_sooner(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, HALL "start 8 0 0\n"); /* 1.95 m: a round trip of 11 370 µs */
    const uint32_t w = 11370u;
    static const struct {
        unsigned ticks; /* from one trigger to the next */
        double ring_us; /* how long the sound rings */
        sim_ping_kind_t kind;
        uint32_t echo_us;
    } cases[] = {
        {6u, 60000.0, SIM_PING_ECHO, w}, /* 60 ms, as the datasheet asks */
        {9u, 60000.0, SIM_PING_ECHO, w},
        {4u, 60000.0, SIM_PING_LATE, 4u * w - 40000u}, /* the fourth return, at 45.5 ms */
        {5u, 60000.0, SIM_PING_LATE, 5u * w - 50000u}, /* the fifth, at 56.9 ms */
        {2u, 60000.0, SIM_PING_LATE, 2u * w - 20000u}, /* the second, at 22.7 ms */
        {4u, 0.0, SIM_PING_ECHO, w},                   /* no ringing: no late echo */
        {5u, 50000.0, SIM_PING_ECHO, w},               /* the fifth return is not heard */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        sim_params_t p;
        sim_params_default(&p);
        p.sonar_ring_us = cases[c].ring_us;
        sim_errors_t e;
        sim_errors_ideal(&e);
        sim_t *s = sim_create(&r, &p, &e, 1u);
        assert_non_null(s);
        for (int k = 0; k < 3; k++) {
            assert_int_equal(sim_sonar_trigger(s), HAL_OK);
            uint32_t got = 0;
            hal_sonar_status_t st = HAL_SONAR_BUSY;
            for (unsigned t = 0; t < cases[c].ticks; t++) {
                if (st == HAL_SONAR_BUSY) {
                    st = sim_sonar_poll(s, &got);
                }
                sim_step(s);
            }
            sim_ping_t pg = sim_last_ping(s);
            if (k == 0) { /* the first ping has nothing before it */
                assert_int_equal(pg.kind, SIM_PING_ECHO);
                continue;
            }
            assert_int_equal(st, HAL_SONAR_ECHO);
            assert_int_equal(pg.kind, cases[c].kind);
            assert_int_equal(got, cases[c].echo_us);
            assert_true(fabs(pg.true_range_m - 1.95) < 1e-9); /* the wall is where it was */
        }
        sim_destroy(s);
    }
    room_free(&r);
}

static void test_blind_zone_reads_minimum(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 1.1 -1 1.1 1\nstart 1 0 0\n");
    sim_params_t p;
    sim_params_default(&p);
    p.sonar_x_m = 0.085; /* the sensor 15 mm from the wall */
    p.body_radius_m = 0.09;
    sim_errors_t e;
    sim_errors_ideal(&e);
    sim_t *s = sim_create(&r, &p, &e, 1u);
    assert_non_null(s);
    assert_int_equal(sim_place(s, 1.01, 0.0, 0.0), 0);
    uint32_t w;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    assert_true(fabs(sim_last_ping(s).true_range_m - 0.005) < 1e-9);
    assert_true(fabs(sim_last_ping(s).range_m - 0.02) < 1e-12);
    sim_destroy(s);
    room_free(&r);
}

/* A world without random errors whose sonar answers up to 30° at every range (a flat
 * limit), with up to two reflections: the mirror paths alone. */
static sim_t *mirror_world(const room_t *r, uint32_t multipath)
{
    sim_errors_t e;
    sim_errors_ideal(&e);
    e.grazing_deg = 30.0;
    e.multipath = multipath;
    return test_world(r, &e, 3u);
}

/* A segment of length @p len centred at (cx, cy) along the direction @p deg, as room text. */
static int wall_at(char *out, size_t n, double cx, double cy, double deg, double len)
{
    double ux = cos(deg * TEST_PI / 180.0) * 0.5 * len;
    double uy = sin(deg * TEST_PI / 180.0) * 0.5 * len;
    return snprintf(out, n, "wall %.12f %.12f %.12f %.12f\n", cx - ux, cy - uy, cx + ux, cy + uy);
}

static void test_multipath_reads_half_the_path(void **state)
{
    (void)state;
    /* The sonar at (1.05, 0) facing +x meets a long wall 1 m ahead at 60° (beyond the
       30° limit for every ray of the cone). The axis ray's mirror leaves at -60° and
       meets, 1 m on, a short wall square to it, which answers: the sound went 1 + 1 m and
       back. The short wall is too short for the edge rays' mirrors (15° apart). */
    char text[512];
    int k = wall_at(text, sizeof text, 2.05, 0.0, 150.0, 2.0); /* its normal at 60° */
    k += wall_at(text + k, sizeof text - (size_t)k, 2.05 + cos(TEST_PI / 3.0), -sin(TEST_PI / 3.0),
                 30.0, 0.2);
    snprintf(text + k, sizeof text - (size_t)k, "start 1 0 0\n");
    room_t r;
    test_room(&r, text);
    sim_t *s = mirror_world(&r, 2u);
    uint32_t w = 0;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    sim_ping_t p = sim_last_ping(s);
    assert_int_equal(p.kind, SIM_PING_MULTIPATH);
    assert_true(fabs(p.range_m - 2.0) < 1e-5);
    assert_true(fabs(p.true_range_m - 1.0) < 0.2); /* the surface in the cone is the near one */
    assert_int_equal(w, (uint32_t)lround(2.0 * 2.0 / SOUND * 1e6));
    sim_destroy(s);

    /* Without multipath the sound is lost: a grazing timeout, as the optimistic level. */
    s = mirror_world(&r, 0u);
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_TIMEOUT);
    assert_int_equal(sim_last_ping(s).kind, SIM_PING_GRAZING);
    uint32_t counts[SIM_PING_KINDS];
    sim_ping_counts(s, counts);
    assert_int_equal(counts[SIM_PING_GRAZING], 1u);
    assert_int_equal(counts[SIM_PING_MULTIPATH], 0u);
    sim_destroy(s);
    room_free(&r);

    /* The far wall turned 40° away from square: it does not answer either, and the sound
       reflects out of the room. */
    k = wall_at(text, sizeof text, 2.05, 0.0, 150.0, 2.0);
    k += wall_at(text + k, sizeof text - (size_t)k, 2.05 + cos(TEST_PI / 3.0), -sin(TEST_PI / 3.0),
                 70.0, 0.2);
    snprintf(text + k, sizeof text - (size_t)k, "start 1 0 0\n");
    test_room(&r, text);
    s = mirror_world(&r, 2u);
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_TIMEOUT);
    assert_int_equal(sim_last_ping(s).kind, SIM_PING_GRAZING);
    sim_destroy(s);
    room_free(&r);
}

static void test_corner_reads_about_its_distance(void **state)
{
    (void)state;
    /* Two walls at a right angle, each met at 45° (beyond the limit): a corner reflector.
       The rays come back parallel to themselves after two reflections, past the receiver,
       and the corner 1 m ahead reads about 1 m, as a real one does. */
    char text[512];
    double cx = 2.05;
    double cy = 0.02; /* not exactly on the axis: no ray meets the vertex */
    int k = snprintf(text, sizeof text, "wall %.12f %.12f %.12f %.12f\n", cx, cy,
                     cx - 1.5 * cos(TEST_PI / 4.0), cy + 1.5 * sin(TEST_PI / 4.0));
    k += snprintf(text + k, sizeof text - (size_t)k, "wall %.12f %.12f %.12f %.12f\n", cx, cy,
                  cx - 1.5 * cos(TEST_PI / 4.0), cy - 1.5 * sin(TEST_PI / 4.0));
    snprintf(text + k, sizeof text - (size_t)k, "start 1 0 0\n");
    room_t r;
    test_room(&r, text);
    sim_t *s = mirror_world(&r, 2u);
    uint32_t w = 0;
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_ECHO);
    sim_ping_t p = sim_last_ping(s);
    assert_int_equal(p.kind, SIM_PING_MULTIPATH);
    print_message("corner at 1.00 m reads %.4f m\n", p.range_m);
    assert_true(fabs(p.range_m - 1.0) < 0.03);
    sim_destroy(s);
    /* One reflection is not enough for a corner. */
    s = mirror_world(&r, 1u);
    assert_int_equal(ping(s, &w, NULL), HAL_SONAR_TIMEOUT);
    sim_destroy(s);
    room_free(&r);
}

/* The typical level's limit narrows with range: a wall turned 20° from the beam answers at
 * 0.5 m and not at 2.5 m (Parallax: about 25° to 0.61 m, 20° at 1.66 m, exact targeting
 * at 3 m); the optimistic level answers at both. */
static void test_limit_narrows_with_range(void **state)
{
    (void)state;
    static const struct {
        double d;
        sim_sonar_level_t level;
        sim_ping_kind_t kind;
    } cases[] = {
        {0.5, SIM_SONAR_TYPICAL, SIM_PING_ECHO},        {2.5, SIM_SONAR_TYPICAL, SIM_PING_GRAZING},
        {0.5, SIM_SONAR_OPTIMISTIC, SIM_PING_ECHO},     {2.5, SIM_SONAR_OPTIMISTIC, SIM_PING_ECHO},
        {0.5, SIM_SONAR_PESSIMISTIC, SIM_PING_GRAZING},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[256];
        int k = wall_at(text, sizeof text, 1.05 + cases[i].d, 0.0, 90.0 + 20.0, 3.0);
        snprintf(text + k, sizeof text - (size_t)k, "start 1 0 0\n");
        room_t r;
        test_room(&r, text);
        sim_errors_t e;
        sim_errors_ideal(&e);
        sim_errors_sonar(&e, cases[i].level);
        sim_t *s = test_world(&r, &e, 1u);
        uint32_t w = 0;
        (void)ping(s, &w, NULL);
        if (sim_last_ping(s).kind != cases[i].kind) {
            fail_msg("case %zu: kind %d, want %d", i, (int)sim_last_ping(s).kind,
                     (int)cases[i].kind);
        }
        sim_destroy(s);
        room_free(&r);
    }
}

/* Mirror paths through a raster room (a ROS map, no vector geometry, no index): every
 * heading in a 4 m x 2 m box of pixels pings without fault, and some read by a mirror. */
static void test_multipath_in_a_raster_room(void **state)
{
    (void)state;
    room_t r;
    raster_box(&r, "mirror", 0);
    r.start_x = 1.0;
    r.start_y = 0.7;
    sim_errors_t e;
    sim_errors_ideal(&e);
    sim_errors_sonar(&e, SIM_SONAR_TYPICAL);
    sim_t *s = test_world(&r, &e, 1u);
    unsigned mirrored = 0;
    for (int deg = 0; deg < 360; deg += 3) {
        assert_int_equal(sim_place(s, 1.0, 0.7, deg * TEST_PI / 180.0), 0);
        uint32_t w = 0;
        hal_sonar_status_t st = ping(s, &w, NULL);
        sim_ping_t p = sim_last_ping(s);
        assert_true(st == HAL_SONAR_ECHO || st == HAL_SONAR_TIMEOUT);
        if (p.kind == SIM_PING_MULTIPATH) {
            mirrored++;
            assert_true(p.range_m > p.true_range_m && p.range_m <= 4.0);
        }
    }
    print_message("%u of 120 headings read by a mirror\n", mirrored);
    assert_true(mirrored > 0u);
    sim_destroy(s);
    room_free(&r);
}

static void test_levels_and_their_checks(void **state)
{
    (void)state;
    for (int l = 0; l < (int)SIM_SONAR_LEVELS; l++) {
        const char *name = sim_sonar_level_name((sim_sonar_level_t)l);
        assert_non_null(name);
        assert_int_equal(sim_sonar_level_of(name), l);
        sim_params_t p;
        sim_params_default(&p);
        sim_errors_t e;
        sim_errors_default(&e);
        sim_errors_sonar(&e, (sim_sonar_level_t)l);
        assert_int_equal(sim_params_check(&p, &e, NULL), 0);
    }
    assert_int_equal(sim_sonar_level_of("kind"), -1);
    assert_null(sim_sonar_level_name(SIM_SONAR_LEVELS));
    /* The default level is the default's. */
    sim_errors_t d;
    sim_errors_t l;
    sim_errors_default(&d);
    sim_errors_default(&l);
    sim_errors_sonar(&l, SIM_SONAR_DEFAULT);
    assert_memory_equal(&d, &l, sizeof d);
    /* The optimistic level is the model before: 45° at every range, no multipath. */
    sim_errors_sonar(&l, SIM_SONAR_OPTIMISTIC);
    assert_true(l.grazing_deg == 45.0 && l.grazing_curve.n == 0u && l.multipath == 0u);

    sim_params_t p;
    sim_params_default(&p);
    const char *field = NULL;
    sim_errors_sonar(&l, SIM_SONAR_TYPICAL);
    sim_errors_t bad = l;
    bad.grazing_curve.range_m[2] = bad.grazing_curve.range_m[1]; /* not ascending */
    assert_int_equal(sim_params_check(&p, &bad, &field), -1);
    assert_string_equal(field, "e.grazing_curve");
    bad = l;
    bad.grazing_curve.deg[0] = 0.0;
    assert_int_equal(sim_params_check(&p, &bad, &field), -1);
    bad = l;
    bad.grazing_curve.deg[0] = 91.0;
    assert_int_equal(sim_params_check(&p, &bad, &field), -1);
    bad = l;
    bad.grazing_curve.n = SIM_GRAZING_KNOTS + 1u;
    assert_int_equal(sim_params_check(&p, &bad, &field), -1);
    bad = l;
    bad.multipath = 9u;
    assert_int_equal(sim_params_check(&p, &bad, &field), -1);
    assert_string_equal(field, "e.multipath");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_head_on_range),
        cmocka_unit_test(test_a_screen_end_on_answers),
        cmocka_unit_test(test_echo_waits_for_time_of_flight),
        cmocka_unit_test(test_timeout_after_38_ms),
        cmocka_unit_test(test_late_echo_when_triggers_come_sooner),
        cmocka_unit_test(test_cone_takes_the_nearest),
        cmocka_unit_test(test_servo_points_the_beam),
        cmocka_unit_test(test_grazing_loses_the_echo),
        cmocka_unit_test(test_raster_head_on),
        cmocka_unit_test(test_noise_dropouts_and_ghosts),
        cmocka_unit_test(test_blind_zone_reads_minimum),
        cmocka_unit_test(test_multipath_reads_half_the_path),
        cmocka_unit_test(test_corner_reads_about_its_distance),
        cmocka_unit_test(test_limit_narrows_with_range),
        cmocka_unit_test(test_multipath_in_a_raster_room),
        cmocka_unit_test(test_levels_and_their_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
