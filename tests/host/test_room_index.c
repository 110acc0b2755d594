/* SPDX-License-Identifier: MIT */
/* Tests of the spatial index of large rooms: the same answers as looking at every object,
 * for a small share of the work, and a size that grows with the file, not the area. */
#include <math.h>

#include "host_test.h"
#include "room_internal.h"
#include "test_rng.h"

static void test_rng_seed(test_rng_t *r, uint64_t seed)
{
    r->s = seed;
}

/* A 60 m square hall with n short walls, n/8 posts and n/8 crates scattered in it, and
 * a clear spot at (30, 30) for the robot; as a .room text. */
static char *scattered_room(uint32_t n, double wall_len, uint64_t seed)
{
    size_t cap = (size_t)n * 64u + 256u;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t k = (size_t)snprintf(text, cap, "poly 0 0 60 0 60 60 0 60\n");
    test_rng_t rng;
    test_rng_seed(&rng, seed);
    for (uint32_t i = 0; i < n + n / 4u; i++) {
        double x = 1.0 + 58.0 * test_rng_unit(&rng);
        double y = 1.0 + 58.0 * test_rng_unit(&rng);
        if (fabs(x - 30.0) < 1.0 && fabs(y - 30.0) < 1.0) {
            continue;
        }
        double a = 2.0 * TEST_PI * test_rng_unit(&rng);
        double len = wall_len * (0.2 + test_rng_unit(&rng));
        room_segment_t w = {x, y, x + len * cos(a), y + len * sin(a)};
        if (i < n) {
            double ex = w.x2 - w.x1;
            double ey = w.y2 - w.y1;
            double t =
                fmax(0.0, fmin(1.0, ((30.0 - x) * ex + (30.0 - y) * ey) / (ex * ex + ey * ey)));
            if (hypot(x + t * ex - 30.0, y + t * ey - 30.0) < 0.5) {
                continue; /* keep the robot's spot clear */
            }
            k += (size_t)snprintf(text + k, cap - k, "wall %.6f %.6f %.6f %.6f\n", w.x1, w.y1, w.x2,
                                  w.y2);
        } else if (i % 2u == 0u) {
            k += (size_t)snprintf(text + k, cap - k, "circle %.6f %.6f %.6f\n", x, y,
                                  0.1 * fmin(len, 1.0));
        } else {
            k += (size_t)snprintf(text + k, cap - k, "box %.6f %.6f %.6f %.6f\n", x, y,
                                  0.2 * fmin(len, 1.0), 0.1 * fmin(len, 1.0));
        }
    }
    snprintf(text + k, cap - k, "start 30 30 0\n");
    return text;
}

/* A room from a .room text the test made (freed), large enough for an index. */
static void parse(room_t *r, const char *name, char *text)
{
    char err[300] = "";
    if (room_parse(r, name, text, strlen(text), err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    free(text);
    assert_non_null(r->index);
}

/* Loads scattered_room(n, wall_len, seed). */
static void load(room_t *r, uint32_t n, double wall_len, uint64_t seed)
{
    parse(r, "scattered.room", scattered_room(n, wall_len, seed));
    /* The index grows with the file: a few entries an object, however long they are. */
    assert_true(room_index_entries(r) <= 8u * (r->nsegs + r->ncircles + r->nboxes));
}

/* The same room without its index: every query looks at every object. */
static room_t linear(const room_t *r)
{
    room_t l = *r;
    l.index = NULL;
    return l;
}

/* Clearance and rays through the index equal those of the linear scan, bit for bit, at
 * random points (in the hall, inside obstacles, outside the hall) and directions. */
static void check_same_answers(const room_t *r, unsigned queries, double reach, uint64_t seed)
{
    room_t l = linear(r);
    test_rng_t rng;
    test_rng_seed(&rng, seed);
    unsigned zero = 0;
    unsigned hits = 0;
    for (unsigned q = 0; q < queries; q++) {
        double x = -5.0 + 70.0 * test_rng_unit(&rng);
        double y = -5.0 + 70.0 * test_rng_unit(&rng);
        double cap = q % 3u == 0u ? 0.34 : (q % 3u == 1u ? 0.09 : 3.0);
        double a = room_clearance(r, x, y, cap);
        double b = room_clearance(&l, x, y, cap);
        if (a != b) {
            fail_msg("clearance at (%.9g, %.9g) cap %g: indexed %.17g, linear %.17g", x, y, cap, a,
                     b);
        }
        zero += a == 0.0;
        double dir = 2.0 * TEST_PI * test_rng_unit(&rng);
        double ca = -1.0;
        double cb = -1.0;
        double da = room_ray(r, x, y, dir, reach, &ca);
        double db = room_ray(&l, x, y, dir, reach, &cb);
        if (da != db) {
            fail_msg("ray from (%.9g, %.9g) at %.9g: indexed %.17g, linear %.17g", x, y, dir, da,
                     db);
        }
        hits += da <= reach;
    }
    /* The points met every case: inside obstacles, free, rays that hit and that miss. */
    assert_true(zero > 0u && zero < queries);
    assert_true(hits > 0u && hits < queries);
}

/* Short walls, and walls as long as the hall in every direction (the index stays linear
 * in the file, see load()). */
static void test_index_gives_the_linear_answers(void **state)
{
    (void)state;
    const struct {
        uint32_t walls;
        double len, reach;
        unsigned queries;
    } rooms[2] = {{10000u, 0.5, 8.0, 2000u}, {1000u, 80.0, 0.1, 500u}};
    for (unsigned k = 0; k < 2u; k++) {
        room_t r;
        load(&r, rooms[k].walls, rooms[k].len, 11u + k);
        check_same_answers(&r, rooms[k].queries, rooms[k].reach, 12u + k);
        room_free(&r);
        assert_null(r.index);
    }
}

/* Every wall on one line (a room of no height): the grid does not blow up along it. */
static void test_degenerate_shapes(void **state)
{
    (void)state;
    size_t cap = 100u * 80u + 64u;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t k = 0;
    for (int i = 0; i < 100; i++) {
        k += (size_t)snprintf(text + k, cap - k, "wall %d 0 %d.5 0\n", 10 * i, 10 * i);
    }
    snprintf(text + k, cap - k, "start 5 1 0\n");
    room_t r;
    char err[300] = "";
    assert_int_equal(room_parse(&r, "line.room", text, strlen(text), err, sizeof err), 0);
    free(text);
    assert_non_null(r.index);
    assert_true(r.index->nx <= 1000u && r.index->ny <= 1000u);
    assert_true(room_index_entries(&r) <= 8u * r.nsegs);
    room_t l = linear(&r);
    for (int i = 0; i < 200; i++) {
        double x = 5.0 * i + 0.25;
        assert_true(room_clearance(&r, x, 0.5, 2.0) == room_clearance(&l, x, 0.5, 2.0));
        assert_true(room_ray(&r, x, 3.0, -TEST_PI / 2.0, 9.0, NULL) ==
                    room_ray(&l, x, 3.0, -TEST_PI / 2.0, 9.0, NULL));
    }
    room_free(&r);
}

/* The objects a query looks at, on average over a thousand: the robot's clearance at
 * random places, or rays of 4 m from the middle of the hall. */
static uint64_t examined_per_query(const room_t *r, bool rays)
{
    test_rng_t rng;
    test_rng_seed(&rng, 32u);
    uint64_t before = room_index_examined();
    for (int q = 0; q < 1000; q++) {
        double u = test_rng_unit(&rng);
        double v = test_rng_unit(&rng);
        if (rays) {
            (void)room_ray(r, 30.0, 30.0, 2.0 * TEST_PI * u, 4.0, NULL);
        } else {
            (void)room_clearance(r, 1.0 + 58.0 * u, 1.0 + 58.0 * v, 0.34);
        }
    }
    return (room_index_examined() - before) / 1000u;
}

/* The work of a query grows with what is near, not with the room: in 20 000 objects a
 * clearance query of the robot's body looks at a few dozen. */
static void test_queries_look_nearby(void **state)
{
    (void)state;
    room_t r;
    load(&r, 20000u, 0.5, 31u);
    size_t objects = r.nsegs + r.ncircles + r.nboxes;
    uint64_t per_query = examined_per_query(&r, false);
    print_message("clearance: %llu of %zu objects looked at per query\n",
                  (unsigned long long)per_query, objects);
    assert_true(per_query <= 100u);
    per_query = examined_per_query(&r, true);
    print_message("rays of 4 m: %llu objects per ray\n", (unsigned long long)per_query);
    assert_true(per_query <= 200u);
    room_free(&r);
}

/* A room of 8 m x 6 m crowded with n objects: tiny posts (1 mm) everywhere, or long walls
 * (each the room's length) stacked a micrometre apart along its four sides; a clear spot
 * at (4, 3). */
static char *crowded_room(uint32_t n, bool posts)
{
    size_t cap = (size_t)n * 64u + 256u;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t k = (size_t)snprintf(text, cap, "start 4 3 0\n");
    test_rng_t rng;
    test_rng_seed(&rng, 77u);
    for (uint32_t i = 0; i < n; i++) {
        if (posts) {
            double x = 0.01 + 7.98 * test_rng_unit(&rng);
            double y = 0.01 + 5.98 * test_rng_unit(&rng);
            if (hypot(x - 4.0, y - 3.0) < 0.3) {
                continue;
            }
            k += (size_t)snprintf(text + k, cap - k, "circle %.6f %.6f 0.001\n", x, y);
        } else {
            double e = 1e-6 * (double)(i / 4u);
            double v[4] = {-e, 8.0 + e, 6.0 + e, -e};
            double w[4][4] = {{0.0, v[0], 8.0, v[0]},
                              {v[1], 0.0, v[1], 6.0},
                              {8.0, v[2], 0.0, v[2]},
                              {v[3], 6.0, v[3], 0.0}};
            const double *p = w[i % 4u];
            k += (size_t)snprintf(text + k, cap - k, "wall %.7f %.7f %.7f %.7f\n", p[0], p[1], p[2],
                                  p[3]);
        }
    }
    return text;
}

/* N11: clearance in a crowd costs a few objects a query, not the crowd: 10^5 tiny posts
 * (a grid sized for them made a query look at thousands of cells) and 10^5 walls a room
 * long (a grid sized for them held every one in each cell); the answers still those of
 * the linear scan, bit for bit. The work is counted, never timed. */
static void test_crowds_stay_cheap(void **state)
{
    (void)state;
    for (int posts = 0; posts < 2; posts++) {
        char *text = crowded_room(100000u, posts != 0);
        room_t r;
        parse(&r, "crowd.room", text);
        room_t l = linear(&r);
        test_rng_t rng;
        test_rng_seed(&rng, 5u);
        uint64_t looked = 0u;
        for (int q = 0; q < 2000; q++) {
            double x = -0.2 + 8.4 * test_rng_unit(&rng);
            double y = -0.2 + 6.4 * test_rng_unit(&rng);
            double cap = q % 2 == 0 ? 0.5 : 0.13;
            uint64_t before = room_index_examined();
            double a = room_clearance(&r, x, y, cap);
            looked += room_index_examined() - before;
            if (q % 20 == 0) { /* the linear scan looks at all 10^5 */
                double b = room_clearance(&l, x, y, cap);
                if (a != b) {
                    fail_msg("crowd %d at (%.9g, %.9g) cap %g: indexed %.17g, linear %.17g", posts,
                             x, y, cap, a, b);
                }
            }
        }
        print_message("%s: %.1f of 100000 objects per clearance query\n",
                      posts ? "posts" : "long walls", (double)looked / 2000.0);
        assert_true(looked / 2000u <= 60u);
        room_free(&r);
    }
}

/* The simulated robot in such a room: the sonar's cone takes only nearby objects, and its
 * readings are those of the linear scan. */
static void test_world_in_a_large_room(void **state)
{
    (void)state;
    room_t r;
    load(&r, 2000u, 0.5, 41u);
    room_t l = linear(&r);
    sim_errors_t e;
    sim_errors_default(&e);
    sim_t *a = test_world(&r, &e, 5u);
    sim_t *b = test_world(&l, &e, 5u);
    unsigned echoes = 0;
    for (int t = 0; t < 3000; t++) {
        int16_t duty = (int16_t)(t % 400 < 300 ? 600 : -300);
        sim_motor_set(a, HAL_WHEEL_LEFT, duty);
        sim_motor_set(a, HAL_WHEEL_RIGHT, 500);
        sim_motor_set(b, HAL_WHEEL_LEFT, duty);
        sim_motor_set(b, HAL_WHEEL_RIGHT, 500);
        uint16_t pulse = (uint16_t)(1000 + (t * 37) % 1000);
        sim_servo_set_pulse(a, pulse);
        sim_servo_set_pulse(b, pulse);
        if (t % 7 == 0) {
            assert_int_equal(sim_sonar_trigger(a), sim_sonar_trigger(b));
        }
        uint32_t wa = 0;
        uint32_t wb = 0;
        hal_sonar_status_t sa = sim_sonar_poll(a, &wa);
        hal_sonar_status_t sb = sim_sonar_poll(b, &wb);
        assert_int_equal(sa, sb);
        assert_int_equal(wa, wb);
        echoes += sa == HAL_SONAR_ECHO;
        sim_step(a);
        sim_step(b);
        sim_truth_t ta = sim_truth(a);
        sim_truth_t tb = sim_truth(b);
        assert_true(ta.x == tb.x && ta.y == tb.y && ta.th == tb.th);
        assert_int_equal(ta.collisions, tb.collisions);
    }
    assert_true(echoes > 100u);
    sim_destroy(a);
    sim_destroy(b);
    room_free(&r);
}

/* A wall's free end (no other segment within 1 mm) becomes a post, and with many walls the
 * index finds the others: the posts are those of a look at every segment, in the same
 * order, for walls that meet end to end, meet another's side, or miss it by 0.9 or 1.1 mm. */
static void test_wall_ends_as_every_segment_says(void **state)
{
    (void)state;
    const uint32_t n = 3000u;
    size_t cap = (size_t)n * 80u + 256u;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t k = (size_t)snprintf(text, cap, "poly 0 0 30 0 30 30 0 30\nstart 15 15 0\n");
    room_segment_t *w = calloc(n, sizeof *w);
    assert_non_null(w);
    test_rng_t rng;
    test_rng_seed(&rng, 31u);
    for (uint32_t i = 0; i < n; i++) {
        double x = 1.0 + 28.0 * test_rng_unit(&rng);
        double y = 1.0 + 28.0 * test_rng_unit(&rng);
        if (i > 0u && test_rng_unit(&rng) < 0.6) {
            /* From a point of an earlier wall (an end or along it), maybe a hair aside. */
            const room_segment_t *o = &w[test_rng_range(&rng, 0, (int32_t)i - 1)];
            double t = test_rng_unit(&rng) < 0.5 ? 1.0 : test_rng_unit(&rng);
            double off =
                (double)test_rng_range(&rng, 0, 2) * (test_rng_unit(&rng) < 0.5 ? 0.0009 : 0.0011);
            x = o->x1 + t * (o->x2 - o->x1) + off;
            y = o->y1 + t * (o->y2 - o->y1);
        }
        if (fabs(x - 15.0) < 1.0 && fabs(y - 15.0) < 1.0) {
            x += 2.0;
        }
        double a = 2.0 * TEST_PI * test_rng_unit(&rng);
        w[i] = (room_segment_t){x, y, fmin(29.5, fmax(0.5, x + 0.6 * cos(a))),
                                fmin(29.5, fmax(0.5, y + 0.6 * sin(a)))};
        k += (size_t)snprintf(text + k, cap - k, "wall %.7f %.7f %.7f %.7f\n", w[i].x1, w[i].y1,
                              w[i].x2, w[i].y2);
    }
    free(w);
    room_t r;
    parse(&r, "ends.room", text);
    size_t posts = 0u;
    size_t joined = 0u;
    for (size_t i = 0; i < r.nsegs; i++) {
        for (int e = 0; e < 2; e++) {
            double x = e == 0 ? r.segs[i].x1 : r.segs[i].x2;
            double y = e == 0 ? r.segs[i].y1 : r.segs[i].y2;
            bool near = false;
            for (size_t j = 0; j < r.nsegs && !near; j++) {
                near = j != i && room_seg_dist2(&r.segs[j], x, y) < 1e-6;
            }
            if (near) {
                joined++;
                continue;
            }
            assert_true(posts < r.ncircles);
            const room_circle_t *c = &r.circles[posts++];
            if (c->cx != x || c->cy != y || c->r != ROOM_WALL_END_M) {
                fail_msg("post %zu at (%.9g, %.9g), the end of segment %zu at (%.9g, %.9g)",
                         posts - 1u, c->cx, c->cy, i, x, y);
            }
        }
    }
    print_message("%zu ends: %zu posts, %zu joined\n", 2u * r.nsegs, posts, joined);
    assert_int_equal(posts, r.ncircles);
    assert_true(posts > 500u && joined > 500u);
    room_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_index_gives_the_linear_answers),
        cmocka_unit_test(test_degenerate_shapes),
        cmocka_unit_test(test_queries_look_nearby),
        cmocka_unit_test(test_crowds_stay_cheap),
        cmocka_unit_test(test_world_in_a_large_room),
        cmocka_unit_test(test_wall_ends_as_every_segment_says),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
