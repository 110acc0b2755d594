/* SPDX-License-Identifier: MIT */
/* Tests of the pose correction's fixed-point filter (src/localize/loc_filter.c) against a
 * double-precision one. */
#include <setjmp.h>
#include <stdarg.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "localize/loc_filter.h"
#include "test_rng.h"

#define PI 3.14159265358979323846

/* ---- the filter against doubles ----------------------------------------------------------- */

/* A random covariance: A·Aᵀ for A the identity plus a random part (correlations up to about
 * ±0.8, never ±1, as a filter's covariance has them), scaled to standard deviations from
 * 5 mm to 0.3 m, 0.02° to 6°, 10 to 5000 nrad/mm and ppm, log-uniform. */
static void random_cov(test_rng_t *rng, lkf_cov_t *c, double m[LKF_N][LKF_N])
{
    static const double lo[LKF_N] = {5e3, 5e3, 350.0, 1e4, 1e4};
    static const double hi[LKF_N] = {3e5, 3e5, 1.0e5, 2.5e6, 2.5e6};
    double a[LKF_N][LKF_N];
    double scale[LKF_N];
    for (int i = 0; i < LKF_N; i++) {
        for (int j = 0; j < LKF_N; j++) {
            a[i][j] = (i == j ? 1.0 : 0.0) + (double)test_rng_range(rng, -400, 400) / 1000.0;
        }
        double u = (double)test_rng_range(rng, 0, 1000) / 1000.0;
        scale[i] = exp(log(lo[i]) + (log(hi[i]) - log(lo[i])) * u);
    }
    for (int i = 0; i < LKF_N; i++) {
        for (int j = 0; j < LKF_N; j++) {
            double s = 0.0;
            for (int k = 0; k < LKF_N; k++) {
                s += a[i][k] * a[j][k];
            }
            c->p[i][j] = (int64_t)(s * scale[i] * scale[j] / 3.0);
        }
    }
    lkf_sane(c);
    for (int i = 0; i < LKF_N; i++) {
        for (int j = 0; j < LKF_N; j++) {
            m[i][j] = (double)c->p[i][j];
        }
    }
}

/* One scalar update in double precision: the Kalman filter's textbook form. */
static void ref_update(double d[LKF_N], double p[LKF_N][LKF_N], const double lin[LKF_N], double h,
                       const double j[3], double r)
{
    double pj[LKF_N];
    for (int i = 0; i < LKF_N; i++) {
        pj[i] = p[i][0] * j[0] + p[i][1] * j[1] + p[i][2] * j[2];
    }
    double s = j[0] * pj[0] + j[1] * pj[1] + j[2] * pj[2] + r;
    double pred = h + j[0] * (d[0] - lin[0]) + j[1] * (d[1] - lin[1]) + j[2] * (d[2] - lin[2]);
    for (int i = 0; i < LKF_N; i++) {
        d[i] -= pj[i] / s * pred;
    }
    for (int i = 0; i < LKF_N; i++) {
        for (int m = 0; m < LKF_N; m++) {
            p[i][m] -= pj[i] / s * pj[m];
        }
    }
}

/* A hundred hits on walls of random directions and levers, processed in sequence, in
 * fixed point and in double: the state stays within 0.1 mm, 10 µrad (0.0006°) and 20
 * nrad/mm or ppm, plus 0.2 % of its size; the covariance within 1 % of each diagonal's
 * scale (or of a floor for each). */
/* The integer square root is the floor of the exact one, on both sides of 2^32 (where it
 * changes from 32-bit to 64-bit words) and at squares and their neighbours. */
static void test_isqrt_is_the_floor(void **state)
{
    (void)state;
    static const uint64_t roots[] = {0u, 1u, 2u, 3u, 65535u, 65536u, 65537u, 4294967295u};
    for (size_t i = 0; i < sizeof roots / sizeof roots[0]; i++) {
        uint64_t sq = roots[i] * roots[i];
        assert_int_equal(lkf_isqrt(sq), roots[i]);
        if (sq != 0u) {
            assert_int_equal(lkf_isqrt(sq - 1u), roots[i] - 1u);
        }
        if (roots[i] != 4294967295u) {
            assert_int_equal(lkf_isqrt(sq + 2u * roots[i]), roots[i]); /* (r+1)^2 - 1 */
        }
    }
    assert_int_equal(lkf_isqrt(UINT64_MAX), 4294967295u);
    assert_int_equal(lkf_isqrt(UINT32_MAX), 65535u);
    assert_int_equal(lkf_isqrt((uint64_t)UINT32_MAX + 1u), 65536u);
    /* Every length of v: the first step depends on it. */
    for (unsigned k = 0; k < 64u; k++) {
        for (int64_t d = -1; d <= 1; d++) {
            uint64_t v = ((uint64_t)1 << k) + (uint64_t)d;
            uint64_t r = lkf_isqrt(v);
            assert_true(r * r <= v && (r == UINT32_MAX || (r + 1u) * (r + 1u) > v));
        }
    }
    for (uint64_t v = 0u; v < 70000u; v++) {
        uint64_t r = lkf_isqrt(v);
        assert_true(r * r <= v && (r + 1u) * (r + 1u) > v);
    }
    test_rng_t rng = {5u};
    for (int i = 0; i < 100000; i++) {
        uint64_t v = test_rng_u64(&rng) >> (test_rng_u64(&rng) % 64u);
        uint64_t r = lkf_isqrt(v);
        assert_true(r * r <= v && (r == UINT32_MAX || (r + 1u) * (r + 1u) > v));
    }
}

static void test_update_against_double(void **state)
{
    (void)state;
    test_rng_t rng = {2024u};
    double worst_d = 0.0;
    double worst_p = 0.0;
    /* κ's variance is compared at (100 nrad/mm)² and (100 ppm)² (0.006° a metre, 0.01 % of
     * a turn): below that, the gains' Q20 rounds its updates by a few units. */
    static const double floor_var[LKF_N] = {LKF_VAR_XY_MIN, LKF_VAR_XY_MIN, LKF_VAR_TH_MIN, 1e10,
                                            1e10};
    for (int trial = 0; trial < 2000; trial++) {
        lkf_cov_t c;
        double pd[LKF_N][LKF_N];
        random_cov(&rng, &c, pd);
        lkf_state_t d = {{0}};
        lkf_state_t lin = {{test_rng_range(&rng, -20000, 20000),
                            test_rng_range(&rng, -20000, 20000), test_rng_range(&rng, -5000, 5000),
                            0, 0}};
        double dd[LKF_N] = {0};
        double lind[LKF_N];
        for (int i = 0; i < LKF_N; i++) {
            lind[i] = (double)lin.v[i];
        }
        for (int n = 0; n < 100; n++) {
            double ang = 2.0 * PI * (double)test_rng_range(&rng, 0, 3600) / 3600.0;
            double lever = (double)test_rng_range(&rng, -1200, 1200) / 1000.0; /* m */
            int32_t j[3] = {(int32_t)lround(cos(ang) * LKF_J_ONE),
                            (int32_t)lround(sin(ang) * LKF_J_ONE),
                            (int32_t)lround(lever * LKF_J_ONE)};
            int64_t h = test_rng_range(&rng, -100000, 100000);
            int64_t r = 900000000LL * (1 + test_rng_range(&rng, 0, 30));
            lkf_update(&d, &c, &lin, h, j, r);
            const double jd[3] = {j[0] / (double)LKF_J_ONE, j[1] / (double)LKF_J_ONE,
                                  j[2] / (double)LKF_J_ONE};
            ref_update(dd, pd, lind, (double)h, jd, (double)r);
        }
        const double tol[LKF_N] = {100.0, 100.0, 10.0, 20000.0, 20000.0};
        for (int i = 0; i < LKF_N; i++) {
            double err = fabs((double)d.v[i] - dd[i]) - 0.002 * fabs(dd[i]);
            worst_d = fmax(worst_d, err / tol[i]);
        }
        for (int i = 0; i < LKF_N; i++) {
            for (int m = 0; m < LKF_N; m++) {
                /* Against each variance's scale, or its floor in the filter where smaller. */
                double sc = sqrt(fmax(pd[i][i], floor_var[i]) * fmax(pd[m][m], floor_var[m]));
                worst_p = fmax(worst_p, fabs((double)c.p[i][m] - pd[i][m]) / sc);
            }
        }
    }
    print_message("filter update vs double: state %.3f of its bound, covariance %.5f\n", worst_d,
                  worst_p);
    assert_true(worst_d <= 1.0);
    assert_true(worst_p <= 0.01);
}

/* lkf_sane() bounds each correlation, not the matrix: X and θ fully anti-correlated and κd
 * fully correlated with both is within its bounds yet no covariance. Along a normal with a
 * 50 m lever whose X and θ parts cancel, s is r alone and κd's gain times its P Jᵀ leaves 64
 * bits (what the replay's fuzz target found): the update must be skipped, not overflow. */
static void test_update_skips_an_overflowing_gain(void **state)
{
    (void)state;
    lkf_cov_t c = {{{0}}};
    c.p[LKF_X][LKF_X] = LKF_VAR_XY_MAX; /* (0.5 m)², root 500 000 */
    c.p[LKF_Y][LKF_Y] = LKF_VAR_XY_MIN;
    c.p[LKF_T][LKF_T] = 100000000LL; /* (10 mrad)², root 10 000 */
    c.p[LKF_KD][LKF_KD] = LKF_VAR_K_MAX;
    c.p[LKF_KT][LKF_KT] = LKF_VAR_K_MIN;
    const int64_t root_kd = lkf_isqrt((uint64_t)LKF_VAR_K_MAX);
    c.p[LKF_X][LKF_T] = c.p[LKF_T][LKF_X] = -500000LL * 10000;
    c.p[LKF_X][LKF_KD] = c.p[LKF_KD][LKF_X] = 500000LL * root_kd;
    c.p[LKF_T][LKF_KD] = c.p[LKF_KD][LKF_T] = 10000LL * root_kd;
    const lkf_cov_t before = c;
    lkf_sane(&c);
    assert_memory_equal(&c, &before, sizeof c); /* within every bound it checks */
    /* 4096 · 500 000 = j_θ · 10 000: the X and θ parts of J P Jᵀ cancel. */
    const int32_t j[3] = {LKF_J_ONE, 0, LKF_J_ONE * 500000 / 10000};
    const lkf_state_t lin = {{0}};
    lkf_state_t d = {{0}};
    lkf_update(&d, &c, &lin, 1000, j, 900000000LL * 15);
    for (int i = 0; i < LKF_N; i++) {
        assert_int_equal(d.v[i], 0);
    }
    assert_memory_equal(&c, &before, sizeof c);
}

/* A move's prediction against P' = F P Fᵀ + Q in double, F the move's Jacobian: within
 * 0.1 % of the diagonal's scale (integer division truncates the small terms). */
static void test_predict_against_double(void **state)
{
    (void)state;
    test_rng_t rng = {77u};
    double worst = 0.0;
    for (int trial = 0; trial < 20000; trial++) {
        lkf_cov_t c;
        double pd[LKF_N][LKF_N];
        random_cov(&rng, &c, pd);
        int64_t dx = test_rng_range(&rng, -60, 60);
        int64_t dy = test_rng_range(&rng, -60, 60);
        int64_t ds = test_rng_range(&rng, -60, 60);
        int64_t turn = test_rng_range(&rng, -300000, 300000);
        lkf_predict(&c, dx, dy, ds, turn);
        /* θ += κd·ds/10⁶ + κt·turn/10⁹, then x −= dy/1000·θ, y += dx/1000·θ. */
        double f[LKF_N][LKF_N] = {{0}};
        for (int i = 0; i < LKF_N; i++) {
            f[i][i] = 1.0;
        }
        f[2][3] = (double)ds / 1e6;
        f[2][4] = (double)turn / 1e9;
        double g[LKF_N][LKF_N] = {{0}};
        for (int i = 0; i < LKF_N; i++) {
            g[i][i] = 1.0;
        }
        g[0][2] = -(double)dy / 1000.0;
        g[1][2] = (double)dx / 1000.0;
        double fg[LKF_N][LKF_N];
        for (int i = 0; i < LKF_N; i++) {
            for (int k = 0; k < LKF_N; k++) {
                double s = 0.0;
                for (int a = 0; a < LKF_N; a++) {
                    s += g[i][a] * f[a][k];
                }
                fg[i][k] = s;
            }
        }
        double out[LKF_N][LKF_N];
        for (int i = 0; i < LKF_N; i++) {
            for (int m = 0; m < LKF_N; m++) {
                double s = 0.0;
                for (int a = 0; a < LKF_N; a++) {
                    for (int b = 0; b < LKF_N; b++) {
                        s += fg[i][a] * pd[a][b] * fg[m][b];
                    }
                }
                out[i][m] = s;
            }
        }
        double dist = fabs((double)ds);
        double turned = fabs((double)turn);
        out[0][0] += 1000.0 * dist;
        out[1][1] += 1000.0 * dist;
        out[2][2] += 26000.0 * dist + 2200.0 * floor(turned / 1000.0);
        out[3][3] += 1e3 * dist;
        out[4][4] += 1e3 * dist;
        static const double lo[LKF_N] = {LKF_VAR_XY_MIN, LKF_VAR_XY_MIN, LKF_VAR_TH_MIN,
                                         LKF_VAR_K_MIN, LKF_VAR_K_MIN};
        static const double hi[LKF_N] = {LKF_VAR_XY_MAX, LKF_VAR_XY_MAX, LKF_VAR_TH_MAX,
                                         LKF_VAR_K_MAX, LKF_VAR_K_MAX};
        bool clipped = false;
        for (int i = 0; i < LKF_N; i++) {
            clipped |= out[i][i] < lo[i] || out[i][i] > hi[i];
        }
        if (clipped) {
            continue; /* where lkf_sane() clipped a variance, the clip is the answer */
        }
        for (int i = 0; i < LKF_N; i++) {
            for (int m = 0; m < LKF_N; m++) {
                double sc = sqrt(out[i][i] * out[m][m]);
                worst = fmax(worst, fabs((double)c.p[i][m] - out[i][m]) / sc);
            }
        }
    }
    print_message("filter prediction vs double: %.6f of the diagonal's scale\n", worst);
    assert_true(worst <= 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_isqrt_is_the_floor),
        cmocka_unit_test(test_update_against_double),
        cmocka_unit_test(test_update_skips_an_overflowing_gain),
        cmocka_unit_test(test_predict_against_double),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
