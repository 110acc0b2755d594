/* SPDX-License-Identifier: MIT */
/* Tests of the fixed-point helpers: table sine/cosine against libm, binary angles, saturation,
 * 64-bit division. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "slam/fixed.h"
#include "test_rng.h"

static const double Q30 = 1073741824.0;
static const double TWO_PI = 6.283185307179586476925;

static double bam_rad(bam32_t a)
{
    return (double)a * (TWO_PI / 4294967296.0);
}

static void check_sin_cos(bam32_t a, double *max_err)
{
    double s = fabs(fix_sin(a) / Q30 - sin(bam_rad(a)));
    double c = fabs(fix_cos(a) / Q30 - cos(bam_rad(a)));
    if (s > *max_err) {
        *max_err = s;
    }
    if (c > *max_err) {
        *max_err = c;
    }
}

/* Every angle of a 2^24-step grid (every table node and interval midpoint, 65536 angles
 * per table interval) plus 2^20 random angles, sine and cosine. */
static void test_sin_cos_error_bound(void **state)
{
    (void)state;
    double max_err = 0.0;
    for (uint32_t i = 0; i < (1u << 24); i++) {
        check_sin_cos(i << 8, &max_err);
    }
    test_rng_t rng = {42u};
    for (uint32_t i = 0; i < (1u << 20); i++) {
        check_sin_cos((bam32_t)test_rng_u64(&rng), &max_err);
    }
    printf("fix_sin/fix_cos max abs error: %.3g (bound %.3g)\n", max_err,
           FIX_SIN_MAX_ERR_Q30 / Q30);
    assert_true(max_err <= FIX_SIN_MAX_ERR_Q30 / Q30);
    assert_true(max_err <= 2e-4); /* the requirement; the bound above is 40 times tighter */
}

static void test_sin_cos_exact_at_right_angles(void **state)
{
    (void)state;
    assert_int_equal(fix_sin(0u), 0);
    assert_int_equal(fix_sin(FIX_BAM_QUARTER), FIX_Q30_ONE);
    assert_int_equal(fix_sin(FIX_BAM_HALF), 0);
    assert_int_equal(fix_sin(3u * FIX_BAM_QUARTER), -FIX_Q30_ONE);
    assert_int_equal(fix_cos(0u), FIX_Q30_ONE);
    assert_int_equal(fix_cos(FIX_BAM_QUARTER), 0);
    assert_int_equal(fix_cos(FIX_BAM_HALF), -FIX_Q30_ONE);
    assert_int_equal(fix_cos(3u * FIX_BAM_QUARTER), 0);
}

static void test_sin_symmetry(void **state)
{
    (void)state;
    test_rng_t rng = {7u};
    for (int i = 0; i < 100000; i++) {
        bam32_t a = (bam32_t)test_rng_u64(&rng);
        assert_int_equal(fix_sin(0u - a), -fix_sin(a)); /* odd */
        assert_int_equal(fix_cos(0u - a), fix_cos(a));  /* even */
    }
}

static void test_angle_wraparound(void **state)
{
    (void)state;
    bam32_t a350 = fix_bam_from_mdeg(350000);
    bam32_t a20 = fix_bam_from_mdeg(20000);
    bam32_t a10 = fix_bam_from_mdeg(10000);
    /* 350° + 20° = 10° (each conversion rounds, so allow one unit each). */
    assert_true(llabs((long long)fix_bam_diff(a350 + a20, a10)) <= 2);
    /* Shortest signed differences across the wrap. */
    assert_true(llabs((long long)fix_bam_diff(a10, a350) - (int32_t)fix_bam_from_mdeg(20000)) <= 2);
    assert_true(llabs((long long)fix_bam_diff(a350, a10) + (int32_t)fix_bam_from_mdeg(20000)) <= 2);
    assert_int_equal(fix_bam_diff(0u, FIX_BAM_HALF), INT32_MIN);
    assert_int_equal(fix_bam_diff(1u, 0xFFFFFFFFu), 2);
    assert_int_equal(fix_bam_diff(0xFFFFFFFFu, 1u), -2);
    /* Any number of turns and negative angles. */
    assert_int_equal(fix_bam_from_mdeg(-90000), 3u * FIX_BAM_QUARTER);
    assert_int_equal(fix_bam_from_mdeg(90000 + 5 * 360000), FIX_BAM_QUARTER);
    assert_int_equal(fix_bam_from_mdeg(-360000), 0u);
    assert_int_equal(fix_bam_from_mdeg(INT32_MIN), fix_bam_from_mdeg(INT32_MIN % 360000));
    /* Sine is continuous across the wrap. */
    assert_true(abs(fix_sin(0xFFFFFFFFu) - fix_sin(0u)) <= 2);
    /* Millidegrees round trip. */
    for (int32_t m = -179999; m < 180000; m += 997) {
        assert_int_equal(fix_bam_to_mdeg(fix_bam_from_mdeg(m)), m);
    }
    assert_int_equal(fix_bam_to_mdeg(FIX_BAM_HALF), -180000);
}

static void test_saturation_at_limits(void **state)
{
    (void)state;
    assert_int_equal(fix_sat_i32(INT64_MAX), INT32_MAX);
    assert_int_equal(fix_sat_i32(INT64_MIN), INT32_MIN);
    assert_int_equal(fix_sat_i32((int64_t)INT32_MAX + 1), INT32_MAX);
    assert_int_equal(fix_sat_i32(-5), -5);
    /* Q1.30 products: identity, rounding, saturation at both ends. */
    assert_int_equal(fix_mul_q30(123456789, FIX_Q30_ONE), 123456789);
    assert_int_equal(fix_mul_q30(3, FIX_Q30_ONE / 2), 2);   /* 1.5 rounds up */
    assert_int_equal(fix_mul_q30(-3, FIX_Q30_ONE / 2), -1); /* -1.5 rounds up */
    assert_int_equal(fix_mul_q30(INT32_MAX, INT32_MAX), INT32_MAX);
    assert_int_equal(fix_mul_q30(INT32_MIN, INT32_MAX), INT32_MIN);
    assert_int_equal(fix_mul_q30(INT32_MIN, -FIX_Q30_ONE), INT32_MAX);
}

static void test_mul_q30_i64_matches_wide_product(void **state)
{
    (void)state;
    test_rng_t rng = {3u};
    for (int i = 0; i < 200000; i++) {
        int64_t v = (int64_t)(test_rng_u64(&rng) >> 17) - ((int64_t)1 << 46); /* |v| < 2^47 */
        q1_30_t f = test_rng_range(&rng, -FIX_Q30_ONE, FIX_Q30_ONE);
        long double exact = (long double)v * (long double)f / 1073741824.0L;
        long double got = (long double)fix_mul_q30_i64(v, f);
        assert_true(fabsl(got - exact) <= 1.0L);
    }
    assert_int_equal(fix_mul_q30_i64(((int64_t)1 << 47) - 1, FIX_Q30_ONE), ((int64_t)1 << 47) - 1);
    assert_int_equal(fix_mul_q30_i64(-((int64_t)1 << 47) + 1, -FIX_Q30_ONE),
                     ((int64_t)1 << 47) - 1);
}

static void test_muldiv_u64(void **state)
{
    (void)state;
    assert_int_equal(fix_muldiv_u64(UINT64_MAX, UINT64_MAX, UINT64_MAX), UINT64_MAX);
    assert_int_equal(fix_muldiv_u64(3u, 5u, 2u), 8u); /* 7.5 rounds up */
    assert_int_equal(fix_muldiv_u64(7u, 1u, 3u), 2u);
    assert_int_equal(fix_muldiv_u64(1ull << 40, 1ull << 40, 1ull << 30), 1ull << 50);
    assert_int_equal(fix_muldiv_u64(1ull << 63, 4u, 1u), UINT64_MAX); /* does not fit */
    assert_int_equal(fix_muldiv_u64(0u, UINT64_MAX, 1u), 0u);
    test_rng_t rng = {11u};
    for (int i = 0; i < 100000; i++) {
        uint64_t a = test_rng_u64(&rng) >> 32;
        uint64_t b = test_rng_u64(&rng) >> 33;
        uint64_t c = (test_rng_u64(&rng) >> 40) + 1u;
        assert_int_equal(fix_muldiv_u64(a, b, c), (a * b + c / 2u) / c);
    }
}

/* One path of the 64-bit division against C's own '/', at the edges and for operands of
 * every length (a random number shifted right by a random amount). */
static void check_div_64(uint64_t (*du)(uint64_t, uint64_t), int64_t (*ds)(int64_t, int64_t))
{
    assert_int_equal(du(UINT64_MAX, 1u), UINT64_MAX);
    assert_int_equal(du(UINT64_MAX, UINT64_MAX), 1u);
    assert_int_equal(du(UINT64_MAX - 1u, UINT64_MAX), 0u);
    assert_int_equal(du(1ull << 63, 3u), (1ull << 63) / 3u);
    assert_int_equal(du(0u, 7u), 0u);
    assert_int_equal(ds(INT64_MIN, 1), INT64_MIN);
    assert_int_equal(ds(INT64_MIN, 2), INT64_MIN / 2);
    assert_int_equal(ds(INT64_MAX, -1), -INT64_MAX);
    assert_int_equal(ds(-7, 2), -3); /* toward zero, as C */
    assert_int_equal(ds(7, -2), -3);
    assert_int_equal(ds(-7, -2), 3);
    /* Every pair of values next to the digit and word boundaries of the long division. */
    uint64_t edge[36];
    unsigned ne = 0;
    for (unsigned bit = 1; bit < 64u; bit += bit < 16u ? 15u : 16u) { /* 1, 16, 32, 48 */
        for (int k = -1; k <= 1; k++) {
            edge[ne++] = ((uint64_t)1 << bit) + (uint64_t)(int64_t)k;
            edge[ne++] = ((uint64_t)1 << (bit + 15u)) + (uint64_t)(int64_t)k;
        }
    }
    edge[ne++] = UINT64_MAX;
    edge[ne++] = UINT64_MAX - 1u;
    edge[ne++] = 0xFFFFFFFF00000000ull;
    edge[ne++] = 0x80000000FFFFFFFFull;
    for (unsigned i = 0; i < ne; i++) {
        for (unsigned k = 0; k < ne; k++) {
            assert_int_equal(du(edge[i], edge[k]), edge[i] / edge[k]);
        }
    }
    test_rng_t rng = {12u};
    for (int i = 0; i < 200000; i++) {
        uint64_t n = test_rng_u64(&rng) >> (test_rng_u64(&rng) % 64u);
        uint64_t d = test_rng_u64(&rng) >> (test_rng_u64(&rng) % 64u);
        if (d == 0u) {
            continue;
        }
        assert_int_equal(du(n, d), n / d);
        int64_t sn = (int64_t)(n >> 1) * ((i & 1) ? -1 : 1);
        int64_t sd = (int64_t)((d >> 1) | 1u) * ((i & 2) ? -1 : 1);
        assert_int_equal(ds(sn, sd), sn / sd);
    }
}

static uint64_t div_u64(uint64_t n, uint64_t d)
{
    return fix_div_u64(n, d);
}

static int64_t div_s64(int64_t n, int64_t d)
{
    return fix_div_s64(n, d);
}

/* The long division the MCU and the 32-bit build use, on every build. */
static void test_div_64_soft_matches_c(void **state)
{
    (void)state;
    check_div_64(fix_div_u64_soft, fix_div_s64_soft);
}

/* The division the core calls: C's '/' itself on a 64-bit host, the long division else. */
static void test_div_64_matches_c(void **state)
{
    (void)state;
    check_div_64(div_u64, div_s64);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sin_cos_error_bound),
        cmocka_unit_test(test_sin_cos_exact_at_right_angles),
        cmocka_unit_test(test_sin_symmetry),
        cmocka_unit_test(test_angle_wraparound),
        cmocka_unit_test(test_saturation_at_limits),
        cmocka_unit_test(test_mul_q30_i64_matches_wide_product),
        cmocka_unit_test(test_muldiv_u64),
        cmocka_unit_test(test_div_64_soft_matches_c),
        cmocka_unit_test(test_div_64_matches_c),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
