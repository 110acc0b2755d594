/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The world's random numbers: splitmix64 streams whose state the caller owns, so every
 * error source draws from its own stream and a run is a function of its seed. Private to
 * hal/host.
 */
#ifndef HOST_SIM_RNG_H
#define HOST_SIM_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct {
    uint64_t s;
} sim_rng_t;

static inline uint64_t sim_rng_u64(sim_rng_t *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/** Stream @p stream of a seed: streams of one seed, and seeds, do not overlap in practice. */
static inline void sim_rng_seed(sim_rng_t *r, uint64_t seed, uint64_t stream)
{
    sim_rng_t mix = {seed ^ (stream * 0xD1B54A32D192ED03ull)};
    r->s = sim_rng_u64(&mix);
}

/** Uniform in [0, 1). */
static inline double sim_rng_unit(sim_rng_t *r)
{
    return (double)(sim_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

/**
 * A standard normal deviate from two uniforms in [0, 1) (Box-Muller; one of the pair is
 * dropped, for simplicity). Taking the uniforms rather than the stream lets a caller draw
 * them always and pay for the logarithm only when the deviate is used.
 */
static inline double sim_rng_gauss_from(double u1, double u2)
{
    return sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586476925 * u2); /* 1-u1 > 0 */
}

/**
 * A cheap near-normal deviate for every tick: the sum of four 16-bit uniforms
 * (Irwin-Hall), centred and scaled to unit variance. Its tails stop at ±3.46σ.
 */
static inline double sim_rng_gauss4(sim_rng_t *r)
{
    uint64_t v = sim_rng_u64(r);
    uint32_t sum = (uint32_t)(v & 0xFFFFu) + (uint32_t)((v >> 16) & 0xFFFFu) +
                   (uint32_t)((v >> 32) & 0xFFFFu) + (uint32_t)(v >> 48);
    /* Each term is uniform on {0..65535}: mean 32767.5, variance (65536² - 1)/12. */
    return ((double)sum - 131070.0) * (1.7320508075688772 / 65536.0);
}

#endif /* HOST_SIM_RNG_H */
