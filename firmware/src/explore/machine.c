/* SPDX-License-Identifier: MIT */
/* The exploration's state machine: entering a state, and the random stream. */
#include "base.h"

void explore_enter(explore_t *e, explore_state_t s)
{
    e->machine.state = (uint8_t)s;
    e->machine.ticks = 0u;
    e->machine.readings = 0u;
}

/* xorshift32, seeded by the configuration. */
uint32_t explore_rng_below(explore_t *e, uint32_t n)
{
    uint32_t x = e->machine.rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    e->machine.rng = x;
    return x % n;
}
