/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Fixed-point arithmetic of the core: Q-format types, saturating operations,
 * binary angles and a table sine/cosine.
 *
 * Formats: `qM_N_t` holds a signed value with N fraction bits (value = raw / 2^N).
 * Angles are binary angles (`bam32_t`): a full turn is 2^32, so angle arithmetic wraps
 * for free in unsigned 32-bit arithmetic; 0 is the +x axis, angles grow counter-clockwise.
 * One binary angle unit is 2π/2^32 ≈ 1.46e-9 rad.
 *
 * Right shifts of negative values are arithmetic (GCC and every compiler the project
 * builds with guarantee it). Nothing here uses floating point.
 */
#ifndef SLAM_FIXED_H
#define SLAM_FIXED_H

#include <stdint.h>

typedef int32_t q16_16_t; /**< Q16.16: range ±32768, resolution 1.5e-5 */
typedef int32_t q1_30_t;  /**< Q1.30: range [-2, 2), resolution 9.3e-10 */
typedef int64_t q48_16_t; /**< Q48.16: a long accumulator with 16 fraction bits */
typedef uint32_t bam32_t; /**< binary angle: 2^32 = one full turn */

#define FIX_Q16_ONE ((q16_16_t)1 << 16) /**< 1.0 in Q16.16 */
#define FIX_Q30_ONE ((q1_30_t)1 << 30)  /**< 1.0 in Q1.30 */

#define FIX_BAM_QUARTER 0x40000000u /**< 90 degrees */
#define FIX_BAM_HALF 0x80000000u    /**< 180 degrees */

/** Maximum absolute error of fix_sin()/fix_cos() against the exact value, in Q1.30
 *  units (5e-6 ≈ 5369 units); the test of the fixed module asserts it. */
#define FIX_SIN_MAX_ERR_Q30 5369

/** Clamp a 64-bit value into the int32_t range. */
static inline int32_t fix_sat_i32(int64_t v)
{
    if (v > INT32_MAX) {
        return INT32_MAX;
    }
    if (v < INT32_MIN) {
        return INT32_MIN;
    }
    return (int32_t)v;
}

/** v >> shift, rounded to nearest (halves round up); shift in 1..62. */
static inline int64_t fix_round_shift(int64_t v, unsigned shift)
{
    return (v + ((int64_t)1 << (shift - 1u))) >> shift;
}

/** v · f for a Q1.30 factor f, rounded to nearest and saturated at the int32_t limits. */
static inline int32_t fix_mul_q30(int32_t v, q1_30_t f)
{
    return fix_sat_i32(fix_round_shift((int64_t)v * f, 30u));
}

/**
 * v · f for a 64-bit v with |v| < 2^47 and a Q1.30 factor |f| <= 1.0, rounded; the
 * product is formed in two halves so it never overflows. ISR-safe, O(1).
 */
static inline int64_t fix_mul_q30_i64(int64_t v, q1_30_t f)
{
    int64_t hi = (v >> 15) * f;             /* |hi| < 2^63 */
    int64_t lo = (v & 0x7FFF) * (int64_t)f; /* |lo| < 2^46 */
    return fix_round_shift(hi + fix_round_shift(lo, 15u), 15u);
}

/** The signed difference a - b of two binary angles, wrapped into [-2^31, 2^31). */
static inline int32_t fix_bam_diff(bam32_t a, bam32_t b)
{
    uint32_t d = a - b;
    return (d & 0x80000000u) ? -(int32_t)(~d) - 1 : (int32_t)d;
}

/**
 * Sine of a binary angle, from a 257-entry quarter-wave table with linear interpolation.
 * @param a  angle (2^32 = full turn)
 * @return   sin(a) in Q1.30, within FIX_SIN_MAX_ERR_Q30 of the exact value;
 *           exactly 0 and ±1.0 at multiples of 90°. ISR-safe, O(1).
 */
q1_30_t fix_sin(bam32_t a);

/** Cosine of a binary angle; see fix_sin(). */
q1_30_t fix_cos(bam32_t a);

/**
 * Binary angle from millidegrees, rounded to the nearest unit.
 * @param mdeg  angle in millidegrees, any value (wraps modulo 360°)
 * Uses a 64-bit division loop: call it at initialisation, not in the tick.
 */
bam32_t fix_bam_from_mdeg(int32_t mdeg);

/**
 * round(a · b / c) with a 128-bit intermediate product, for exact gains at
 * initialisation (about 64 loop iterations: not for the tick).
 * @param c  divisor, > 0
 * @return   the rounded quotient, or UINT64_MAX when it does not fit in 64 bits
 */
uint64_t fix_muldiv_u64(uint64_t a, uint64_t b, uint64_t c);

/**
 * n / d truncated toward zero, as C's '/' on uint64_t (d != 0): long division on 32-bit
 * hardware divisions, a few dozen instructions. Ours because the C library's general 64-bit
 * division takes 0.9 KiB of flash. Built everywhere, so a test can hold it against '/'.
 */
uint64_t fix_div_u64_soft(uint64_t n, uint64_t d);

/** n / d truncated toward zero, as C's '/' on int64_t (d != 0, not INT64_MIN / -1), by
 *  fix_div_u64_soft(). */
int64_t fix_div_s64_soft(int64_t n, int64_t d);

/*
 * Where the processor divides 64-bit numbers itself (a 64-bit host: the simulator, a 64-bit
 * Linux robot), fix_div_u64() and fix_div_s64() are C's '/': the same integers, a tenth of
 * the instructions. A 32-bit build (the MCU, -m32) takes the long division above. A build
 * may set FIX_DIV64_NATIVE to 0 or 1 itself.
 */
#ifndef FIX_DIV64_NATIVE
#if UINTPTR_MAX > 0xFFFFFFFFu
#define FIX_DIV64_NATIVE 1
#else
#define FIX_DIV64_NATIVE 0
#endif
#endif

/** n / d truncated toward zero, as C's '/' on uint64_t (d != 0). */
static inline uint64_t fix_div_u64(uint64_t n, uint64_t d)
{
#if FIX_DIV64_NATIVE
    return n / d;
#else
    return fix_div_u64_soft(n, d);
#endif
}

/** n / d truncated toward zero, as C's '/' on int64_t (d != 0, not INT64_MIN / -1). */
static inline int64_t fix_div_s64(int64_t n, int64_t d)
{
#if FIX_DIV64_NATIVE
    return n / d;
#else
    return fix_div_s64_soft(n, d);
#endif
}

/** Millidegrees of a binary angle, rounded, in [-180000, 180000]. */
int32_t fix_bam_to_mdeg(bam32_t a);

/** A frame of the robot in the world: an origin (µm) and a heading, by its cosine and sine. */
typedef struct {
    int32_t x_um, y_um; /**< the origin, world */
    q1_30_t cos, sin;   /**< of the heading */
} fix_frame_t;

/**
 * A world point in a frame: how far ahead of the origin it lies (returned) and how far to
 * the left (*left_um), µm. The one world-to-robot conversion of the core (exploration's
 * memory and corridor, localization's obstacle ahead). The differences are taken modulo
 * 2^32, which is exact for points within 2 km of the origin, and the 32 x 32-bit products
 * (one SMULL each on a Cortex-M4) fit 64 bits. ISR-safe.
 */
static inline int32_t fix_frame_point(const fix_frame_t *f, int32_t x_um, int32_t y_um,
                                      int32_t *left_um)
{
    int32_t dx = (int32_t)((uint32_t)x_um - (uint32_t)f->x_um);
    int32_t dy = (int32_t)((uint32_t)y_um - (uint32_t)f->y_um);
    *left_um = (int32_t)(((int64_t)dy * f->cos - (int64_t)dx * f->sin) >> 30);
    return (int32_t)(((int64_t)dx * f->cos + (int64_t)dy * f->sin) >> 30);
}

#endif /* SLAM_FIXED_H */
