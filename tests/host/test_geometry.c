/* SPDX-License-Identifier: MIT */
/* Tests of room geometry: rays against analytic distances, clearance, ground truth. */
#include <math.h>

#include "host_test.h"

/* The tests' own random numbers (splitmix64), uniform in [0, 1). */
static uint64_t rng_state = 12345u;
static double unit(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static void test_ray_axis_walls(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 4 0\nwall 4 0 4 4\nwall 4 4 0 4\nwall 0 4 0 0\nstart 1 1.5 0\n");
    double c = 0.0;
    assert_true(fabs(room_ray(&r, 1.0, 1.5, 0.0, 10.0, &c) - 3.0) < 1e-12);
    assert_true(fabs(c - 1.0) < 1e-12);
    assert_true(fabs(room_ray(&r, 1.0, 1.5, TEST_PI, 10.0, &c) - 1.0) < 1e-12);
    assert_true(fabs(room_ray(&r, 1.0, 1.5, -TEST_PI / 2.0, 10.0, &c) - 1.5) < 1e-12);
    /* At 45° the top wall (2.5 m up) comes before the right one (3 m across). */
    double d = room_ray(&r, 1.0, 1.5, TEST_PI / 4.0, 10.0, &c);
    assert_true(fabs(d - 2.5 * sqrt(2.0)) < 1e-12);
    assert_true(fabs(c - sqrt(0.5)) < 1e-12);
    /* Nothing within max: a value beyond it, and the incidence untouched. */
    c = -7.0;
    assert_true(room_ray(&r, 1.0, 1.5, 0.0, 2.0, &c) > 2.0);
    assert_true(c == -7.0);
    room_free(&r);
}

static void test_ray_slanted_wall(void **state)
{
    (void)state;
    /* The wall x + y = 2 from (2, 0) to (0, 2), seen from the origin. */
    room_t r;
    test_room(&r, "wall 2 0 0 2\nstart -1 -1 0\n");
    for (int i = 0; i < 2000; i++) {
        double th = 0.001 + (TEST_PI / 2.0 - 0.002) * unit();
        double c = 0.0;
        double d = room_ray(&r, 0.0, 0.0, th, 10.0, &c);
        double want = 2.0 / (cos(th) + sin(th));
        assert_true(fabs(d - want) < 1e-12);
        assert_true(fabs(c - (cos(th) + sin(th)) / sqrt(2.0)) < 1e-12);
    }
    /* Beyond its ends and behind it: nothing. */
    assert_true(room_ray(&r, 0.0, 0.0, -0.1, 10.0, NULL) > 10.0);
    assert_true(room_ray(&r, 0.0, 0.0, TEST_PI + 0.7, 10.0, NULL) > 10.0);
    room_free(&r);
}

static void test_ray_circle_and_solids(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "circle 3 0 1\nbox 0 5 1 1\nstart 0 0 0\n");
    double c = 0.0;
    assert_true(fabs(room_ray(&r, 0.0, 0.0, 0.0, 10.0, &c) - 2.0) < 1e-12);
    assert_true(fabs(c - 1.0) < 1e-12);
    /* Off-centre: the hit is at x = 3 - sqrt(1 - 0.25), its normal tilted by asin(0.5). */
    double d = room_ray(&r, 0.0, 0.5, 0.0, 10.0, &c);
    assert_true(fabs(d - (3.0 - sqrt(0.75))) < 1e-12);
    assert_true(fabs(c - sqrt(0.75)) < 1e-12);
    /* Tangent-missing and away. */
    assert_true(room_ray(&r, 0.0, 1.01, 0.0, 10.0, NULL) > 10.0);
    assert_true(room_ray(&r, 0.0, 0.0, TEST_PI, 10.0, NULL) > 10.0);
    /* From inside solids: 0. */
    assert_true(room_ray(&r, 3.2, 0.1, 1.0, 10.0, &c) == 0.0);
    assert_true(room_ray(&r, 0.5, 5.5, 1.0, 10.0, &c) == 0.0);
    /* The box's edges from outside. */
    assert_true(fabs(room_ray(&r, 0.5, 4.0, TEST_PI / 2.0, 10.0, &c) - 1.0) < 1e-12);
    room_free(&r);
}

/* A raster room built in memory: w x h pixels of res, lower-left at (x0, y0). */
static void raster_room(room_t *r, uint32_t w, uint32_t h, double res, double x0, double y0)
{
    memset(r, 0, sizeof *r);
    r->occ = calloc((size_t)w * h, 1u);
    r->occ_free = calloc((size_t)w * h, 1u);
    assert_non_null(r->occ);
    assert_non_null(r->occ_free);
    r->occ_w = w;
    r->occ_h = h;
    r->occ_res = res;
    r->occ_x0 = x0;
    r->occ_y0 = y0;
    r->min_x = x0;
    r->min_y = y0;
    r->max_x = x0 + w * res;
    r->max_y = y0 + h * res;
}

static void set_px(room_t *r, long x, long y)
{
    if (x >= 0 && y >= 0 && x < (long)r->occ_w && y < (long)r->occ_h) {
        r->occ[(size_t)y * r->occ_w + (size_t)x] = 1u;
    }
}

static void test_ray_raster_wall(void **state)
{
    (void)state;
    room_t r;
    raster_room(&r, 100u, 100u, 0.05, -1.0, -1.0);
    for (long y = 0; y < 100; y++) {
        set_px(&r, 70, y); /* a vertical wall at x = 2.5 .. 2.55 */
    }
    double c = 0.0;
    assert_true(fabs(room_ray(&r, 1.0, 0.33, 0.0, 5.0, &c) - 1.5) < 1e-9);
    assert_true(fabs(c - 1.0) < 1e-9);
    for (int i = 0; i < 500; i++) {
        double th = (unit() - 0.5) * 2.4; /* within ±69° of the normal */
        double d = room_ray(&r, 1.0, 0.33, th, 10.0, &c);
        double want = 1.5 / cos(th);
        double hy = 0.33 + want * sin(th);
        if (hy >= 4.0 || hy < -1.0) {
            assert_true(d > 10.0); /* leaves the raster: outside is empty */
            continue;
        }
        if (hy >= 3.9 || hy < -0.9) {
            continue; /* near the wall's ends its normal tilts, as it should */
        }
        assert_true(fabs(d - want) < 1e-9);
        assert_true(fabs(c - cos(th)) < 1e-9);
    }
    /* From outside the raster, entering it. */
    assert_true(fabs(room_ray(&r, -3.0, 0.33, 0.0, 10.0, &c) - 5.5) < 1e-9);
    /* Beyond max. */
    assert_true(room_ray(&r, 1.0, 0.33, 0.0, 1.4, &c) > 1.4);
    /* Starting in an occupied pixel. */
    assert_true(room_ray(&r, 2.52, 0.33, 1.0, 5.0, &c) == 0.0);
    room_free(&r);
}

static void test_ray_raster_staircase_normal(void **state)
{
    (void)state;
    /* A diagonal wall drawn as a staircase of pixels: y = x + 0 in pixels. Its pixel faces
       are all axis-aligned; the occupancy gradient recovers the 45° normal. */
    room_t r;
    raster_room(&r, 200u, 200u, 0.02, 0.0, 0.0);
    for (long i = 0; i < 200; i++) {
        set_px(&r, i, i);
        set_px(&r, i + 1, i);
    }
    /* From (2.5, 1.5) along the wall's normal (-1, 1)/sqrt(2): the line x = y is
       1/sqrt(2) m away, the band's near edge up to two pixels nearer. */
    double c = 0.0;
    double d = room_ray(&r, 2.5, 1.5, 3.0 * TEST_PI / 4.0, 5.0, &c);
    double centre = (2.5 - 1.5) / sqrt(2.0);
    assert_true(fabs(d - centre) < 2.0 * 0.02);
    assert_true(c > 0.95); /* the faces alone would say cos 45° = 0.71 */
    /* 0.3 rad off the wall's own direction: an incidence of 90° - 17°, cos = sin 0.3. */
    d = room_ray(&r, 1.5, 0.5, TEST_PI / 4.0 + 0.3, 5.0, &c);
    assert_true(d < 3.0);
    assert_true(fabs(c - sin(0.3)) < 0.1);
    room_free(&r);
}

static void test_clearance(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 4 0\nbox 2 2 1 1\ncircle 0 3 0.5\nstart 1 1 0\n");
    assert_true(fabs(room_clearance(&r, 1.0, 1.0, 10.0) - 1.0) < 1e-12); /* the wall */
    assert_true(fabs(room_clearance(&r, 5.0, -3.0, 10.0) - (sqrt(10.0) - ROOM_WALL_END_M)) <
                1e-12);                                                  /* its round end */
    assert_true(fabs(room_clearance(&r, 1.5, 2.5, 10.0) - 0.5) < 1e-12); /* the box */
    assert_true(fabs(room_clearance(&r, 0.0, 2.2, 10.0) - 0.3) < 1e-12); /* the circle */
    assert_true(room_clearance(&r, 2.5, 2.5, 10.0) == 0.0);              /* inside the box */
    assert_true(room_clearance(&r, 0.1, 3.1, 10.0) == 0.0);              /* in the circle */
    assert_true(room_clearance(&r, 1.0, 1.0, 0.25) == 0.25);             /* capped */
    assert_true(room_disc_free(&r, 1.0, 1.0, 0.99));
    assert_true(room_disc_free(&r, 1.0, 1.0, 1.0)); /* touching exactly is free */
    assert_false(room_disc_free(&r, 1.0, 1.0, 1.01));
    room_free(&r);

    raster_room(&r, 50u, 50u, 0.1, 0.0, 0.0);
    set_px(&r, 20, 20); /* 2.0..2.1 x 2.0..2.1 */
    assert_true(fabs(room_clearance(&r, 1.5, 2.05, 5.0) - 0.5) < 1e-12);
    assert_true(fabs(room_clearance(&r, 1.7, 1.6, 5.0) - 0.5) < 1e-12); /* the corner */
    assert_true(room_clearance(&r, 2.05, 2.05, 5.0) == 0.0);
    assert_true(room_clearance(&r, 1.0, 1.0, 0.3) == (double)0.3);
    room_free(&r);
}

/* Brute force: mark the cells under many points of a curve. */
static void sample_mark(uint8_t *out, uint32_t a, uint32_t b, double cell, double x, double y)
{
    long ia = (long)floor(x / cell);
    long ib = (long)floor(y / cell);
    if (ia >= 0 && ib >= 0 && ia < (long)a && ib < (long)b) {
        out[(size_t)ib * a + (size_t)ia] = 1u;
    }
}

static void test_rasterize_shapes(void **state)
{
    (void)state;
    enum { A = 40, B = 30 };
    static uint8_t got[A * B + 16];
    static uint8_t want[A * B];
    room_t r;

    /* A box 1.01..1.49 x 1.01..1.24 at 0.1 m: a ring of 5 x 3 cells, its middle empty. */
    test_room(&r, "box 1.01 1.01 0.48 0.23\nstart 0.3 0.3 0\n");
    memset(got, 0xEE, sizeof got);
    room_rasterize(&r, 0.0, 0.0, 0.1, A, B, got);
    size_t n = 0;
    for (size_t i = 0; i < (size_t)A * B; i++) {
        n += got[i];
    }
    assert_int_equal(n, 12u);
    assert_int_equal(got[10 * A + 10], 1);
    assert_int_equal(got[12 * A + 14], 1);
    assert_int_equal(got[11 * A + 12], 0);
    for (size_t i = (size_t)A * B; i < sizeof got; i++) {
        assert_int_equal(got[i], 0xEE); /* nothing written past the grid */
    }
    room_free(&r);

    /* A slanted wall and a circle, against dense sampling of their outlines. */
    test_room(&r, "wall 0.05 0.05 3.93 2.71\ncircle 2.02 1.47 0.61\nwall -5 1.234 9 1.6\n"
                  "start 3.5 0.4 0\n");
    room_rasterize(&r, 0.0, 0.0, 0.1, A, B, got);
    memset(want, 0, sizeof want);
    for (int i = 0; i <= 200000; i++) {
        double t = i / 200000.0;
        sample_mark(want, A, B, 0.1, 0.05 + t * 3.88, 0.05 + t * 2.66);
        sample_mark(want, A, B, 0.1, -5.0 + t * 14.0, 1.234 + t * 0.366);
        sample_mark(want, A, B, 0.1, 2.02 + 0.61 * cos(2.0 * TEST_PI * t),
                    1.47 + 0.61 * sin(2.0 * TEST_PI * t));
    }
    assert_memory_equal(got, want, sizeof want);
    room_free(&r);
}

static void test_rasterize_pixels(void **state)
{
    (void)state;
    uint8_t got[10 * 10];
    room_t r;
    raster_room(&r, 10u, 10u, 0.05, 0.0, 0.0);
    set_px(&r, 3, 3); /* 0.15..0.2 */
    room_rasterize(&r, 0.0, 0.0, 0.1, 10u, 10u, got);
    assert_int_equal(got[1 * 10 + 1], 1); /* within cell (1, 1) */
    size_t n = 0;
    for (size_t i = 0; i < sizeof got; i++) {
        n += got[i];
    }
    assert_int_equal(n, 1u);
    /* Shifted by a quarter cell, pixel (4, 4) (0.2..0.25) straddles four cells. */
    r.occ[3 * 10 + 3] = 0u;
    set_px(&r, 4, 4);
    room_rasterize(&r, 0.025, 0.025, 0.1, 10u, 10u, got);
    n = 0;
    for (size_t i = 0; i < sizeof got; i++) {
        n += got[i];
    }
    assert_int_equal(n, 4u);
    assert_int_equal(got[1 * 10 + 1], 1);
    assert_int_equal(got[2 * 10 + 2], 1);
    assert_int_equal(got[1 * 10 + 2], 1);
    room_free(&r);
}

/* Rays and the ground truth agree: every hit lies in (or at the edge of) a truth cell. */
static void test_rays_land_on_truth(void **state)
{
    (void)state;
    room_t r;
    char err[300];
    assert_int_equal(room_load(&r, HOST_ROOMS_DIR "/slanted.room", NULL, err, sizeof err), 0);
    enum { A = 300, B = 250 };
    static uint8_t truth[A * B];
    const double cell = 0.02;
    room_rasterize(&r, -0.5, -0.5, cell, A, B, truth);
    for (int i = 0; i < 3000; i++) {
        double th = 2.0 * TEST_PI * unit();
        double d = room_ray(&r, r.start_x, r.start_y, th, 20.0, NULL);
        assert_true(d < 20.0);
        double hx = r.start_x + d * cos(th) + 0.5;
        double hy = r.start_y + d * sin(th) + 0.5;
        long a = (long)floor(hx / cell);
        long b = (long)floor(hy / cell);
        int found = 0;
        for (long db = -1; db <= 1; db++) {
            for (long da = -1; da <= 1; da++) {
                found |= truth[(size_t)(b + db) * A + (size_t)(a + da)];
            }
        }
        assert_true(found);
    }
    room_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ray_axis_walls),
        cmocka_unit_test(test_ray_slanted_wall),
        cmocka_unit_test(test_ray_circle_and_solids),
        cmocka_unit_test(test_ray_raster_wall),
        cmocka_unit_test(test_ray_raster_staircase_normal),
        cmocka_unit_test(test_clearance),
        cmocka_unit_test(test_rasterize_shapes),
        cmocka_unit_test(test_rasterize_pixels),
        cmocka_unit_test(test_rays_land_on_truth),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
