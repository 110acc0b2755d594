/* SPDX-License-Identifier: MIT */
/* host_sim's fast paths against the plain definitions they replace, value for value: the
 * CSV number writer, the observable disc, metres to µm, and the wrap of an angle. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "host_sim.h"
#include "test_rng.h"

/* The one-digit-a-step writer fmt_fixed() was. */
static char *fmt_plain(char *out, double v, int decimals, char sep)
{
    static const double scale[11] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10};
    double s = v * scale[decimals];
    long long n = (long long)(s < 0 ? s - 0.5 : s + 0.5);
    if (n < 0) {
        *out++ = '-';
        n = -n;
    } else if (n == 0 && v < 0) {
        *out++ = '-';
    }
    char digits[32];
    int k = 0;
    do {
        digits[k++] = (char)('0' + n % 10);
        n /= 10;
    } while (n > 0 || k <= decimals);
    while (k > decimals) {
        *out++ = digits[--k];
    }
    if (decimals > 0) {
        *out++ = '.';
        while (k > 0) {
            *out++ = digits[--k];
        }
    }
    if (sep != 0) {
        *out++ = sep;
    }
    return out;
}

/* Both write what fits a long long once scaled: |v| < 9e8 at ten decimals (host_sim.h). */
static void check_fmt(double v, int decimals)
{
    if (fabs(v) * pow(10.0, decimals) >= 9e18) {
        return;
    }
    char a[64];
    char b[64];
    char *ea = fmt_fixed(a, v, decimals, ',');
    char *eb = fmt_plain(b, v, decimals, ',');
    *ea = '\0';
    *eb = '\0';
    if (strcmp(a, b) != 0) {
        fail_msg("fmt_fixed(%.17g, %d): '%s', the plain writer '%s'", v, decimals, a, b);
    }
}

static void test_fmt_fixed_writes_what_the_plain_writer_wrote(void **state)
{
    (void)state;
    static const double edges[] = {0.0,
                                   -0.0,
                                   0.5,
                                   -0.5,
                                   0.05,
                                   -0.05,
                                   1e-11,
                                   -1e-11,
                                   9.5,
                                   99.5,
                                   4294967295.0,
                                   4294967296.0,
                                   42949672.955,
                                   1e8,
                                   -1e8,
                                   3.14159265358979,
                                   -3.14159265358979,
                                   0.0049999999};
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        for (int d = 0; d <= 10; d++) {
            check_fmt(edges[i], d);
        }
    }
    test_rng_t rng = {7u};
    for (int i = 0; i < 300000; i++) {
        int d = (int)(test_rng_u64(&rng) % 11u);
        double mag = pow(10.0, (double)test_rng_range(&rng, -12, 8));
        double v = (test_rng_unit(&rng) * 2.0 - 1.0) * mag;
        check_fmt(v, d);
        /* Halves and their neighbours at this number of decimals. */
        double h = (floor(v * pow(10.0, d)) + 0.5) / pow(10.0, d);
        check_fmt(h, d);
        check_fmt(nextafter(h, 0.0), d);
        check_fmt(nextafter(h, HUGE_VAL), d);
    }
}

/* Every cell whose centre lies within radius_m of (x, y), each tested. */
static void disc_plain(const map_geom_t *g, uint8_t *marks, double x, double y, double radius_m)
{
    double fx = (x - g->origin_x) / g->cell_m - 0.5;
    double fy = (y - g->origin_y) / g->cell_m - 0.5;
    double r = radius_m / g->cell_m;
    for (long j = 0; j < (long)g->b; j++) {
        double dy = (double)j - fy;
        for (long i = 0; i < (long)g->a; i++) {
            double dx = (double)i - fx;
            if (dx * dx + dy * dy <= r * r) {
                marks[(size_t)j * g->a + (size_t)i] = 1u;
            }
        }
    }
}

static void test_mark_disc_marks_each_cell_the_test_admits(void **state)
{
    (void)state;
    enum { A = 64, B = 48 };
    static uint8_t fast[A * B];
    static uint8_t plain[A * B];
    test_rng_t rng = {11u};
    for (int i = 0; i < 20000; i++) {
        map_geom_t g = {.a = A, .b = B};
        g.cell_m = 0.01 + 0.2 * test_rng_unit(&rng);
        g.origin_x = (test_rng_unit(&rng) - 0.5) * 5.0;
        g.origin_y = (test_rng_unit(&rng) - 0.5) * 5.0;
        /* Centres inside, beside and far outside the grid; radii from none to most of it,
         * and some exactly on a cell's centre, where ties fall. */
        double cx = g.origin_x + (test_rng_unit(&rng) * 1.6 - 0.3) * A * g.cell_m;
        double cy = g.origin_y + (test_rng_unit(&rng) * 1.6 - 0.3) * B * g.cell_m;
        double rad = test_rng_unit(&rng) * 30.0 * g.cell_m;
        if (i % 4 == 0) {
            cx = g.origin_x + (floor(cx / g.cell_m) + 0.5) * g.cell_m;
            rad = (double)test_rng_range(&rng, 0, 20) * g.cell_m;
        }
        memset(fast, 0, sizeof fast);
        memset(plain, 0, sizeof plain);
        mark_disc(&g, fast, cx, cy, rad);
        disc_plain(&g, plain, cx, cy, rad);
        assert_memory_equal(fast, plain, sizeof fast);
    }
}

static void test_to_um_rounds_as_lround(void **state)
{
    (void)state;
    static const double edges[] = {
        0.0,       -0.0,         5e-7,          -5e-7,       2.5e-6,       -2.5e-6,
        1.0000005, 2147.4836465, -2147.4836465, 2147.483647, -2147.483648, 0.49999999999999994e-6};
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        assert_int_equal(to_um(edges[i]), (int32_t)lround(edges[i] * 1e6));
    }
    test_rng_t rng = {13u};
    for (int i = 0; i < 1000000; i++) {
        double m = (test_rng_unit(&rng) - 0.5) * 4000.0;
        if (i % 2 == 0) {
            m = ((double)test_rng_range(&rng, -2000000000, 2000000000) + 0.5) * 1e-6;
        }
        assert_int_equal(to_um(m), (int32_t)lround(m * 1e6));
    }
}

static void check_wrap(double a)
{
    double w = wrap_pi(a);
    double r = remainder(a, 2.0 * HOST_SIM_PI);
    if (memcmp(&w, &r, sizeof w) != 0 && !(isnan(w) && isnan(r))) {
        fail_msg("wrap_pi(%.17g) = %.17g, remainder %.17g", a, w, r);
    }
}

static void test_wrap_pi_is_the_ieee_remainder(void **state)
{
    (void)state;
    const double pi = HOST_SIM_PI;
    const double at[] = {0.0,
                         pi,
                         2.0 * pi,
                         3.0 * pi,
                         4.0 * pi,
                         5.0 * pi,
                         1.5 * (2.0 * pi),
                         0.5 * (2.0 * pi),
                         2.5 * (2.0 * pi),
                         100.0,
                         HUGE_VAL,
                         (double)NAN};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
        for (int s = -1; s <= 1; s += 2) {
            double a = s * at[i];
            check_wrap(a);
            check_wrap(nextafter(a, 0.0));
            check_wrap(nextafter(a, s * HUGE_VAL));
        }
    }
    test_rng_t rng = {17u};
    for (int i = 0; i < 1000000; i++) {
        check_wrap((test_rng_unit(&rng) - 0.5) * 40.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fmt_fixed_writes_what_the_plain_writer_wrote),
        cmocka_unit_test(test_mark_disc_marks_each_cell_the_test_admits),
        cmocka_unit_test(test_to_um_rounds_as_lround),
        cmocka_unit_test(test_wrap_pi_is_the_ieee_remainder),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
