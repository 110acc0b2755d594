/* SPDX-License-Identifier: MIT */
/* A small deterministic random generator for tests (splitmix64); state is passed in. */
#ifndef SLAM_TEST_RNG_H
#define SLAM_TEST_RNG_H

#include <stdint.h>

typedef struct {
    uint64_t s;
} test_rng_t;

static inline uint64_t test_rng_u64(test_rng_t *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/** Uniform integer in [lo, hi]. */
static inline int32_t test_rng_range(test_rng_t *r, int32_t lo, int32_t hi)
{
    uint64_t span = (uint64_t)((int64_t)hi - lo) + 1u;
    return (int32_t)(lo + (int64_t)(test_rng_u64(r) % span));
}

/** Uniform double in [0, 1). */
static inline double test_rng_unit(test_rng_t *r)
{
    return (double)(test_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

#endif /* SLAM_TEST_RNG_H */
