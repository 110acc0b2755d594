/* SPDX-License-Identifier: MIT */
/* Late, overrun and missed ticks of a periodic timer, from injected timestamps. */
#include "lhal/tickstat.h"

void tickstat_init(tickstat_t *t, uint64_t period_ns, uint64_t late_ns, uint64_t first_due_ns)
{
    *t = (tickstat_t){0};
    t->period_ns = period_ns;
    t->late_ns = late_ns;
    /* The first wake-up adds one period per expiry, so start one period early. */
    t->due_ns = first_due_ns - period_ns;
}

static uint32_t tickstat_add_sat(uint32_t a, uint64_t b)
{
    uint64_t s = (uint64_t)a + b;
    return s > UINT32_MAX ? UINT32_MAX : (uint32_t)s;
}

void tickstat_wake(tickstat_t *t, uint64_t expirations, uint64_t now_ns)
{
    if (expirations == 0u) {
        expirations = 1u;
    }
    t->missed = tickstat_add_sat(t->missed, expirations - 1u);
    t->due_ns += expirations * t->period_ns;
    uint64_t latency = now_ns > t->due_ns ? now_ns - t->due_ns : 0u;
    if (latency > t->max_latency_ns) {
        t->max_latency_ns = latency;
    }
    if (latency > t->late_ns) {
        t->late = tickstat_add_sat(t->late, 1u);
    }
    t->ticks++;
}

void tickstat_done(tickstat_t *t, uint64_t start_ns, uint64_t end_ns)
{
    uint64_t run = end_ns > start_ns ? end_ns - start_ns : 0u;
    if (run > t->max_run_ns) {
        t->max_run_ns = run;
    }
    if (end_ns > t->due_ns + t->period_ns) {
        t->overruns = tickstat_add_sat(t->overruns, 1u);
    }
}

uint32_t tickstat_faults(const tickstat_t *t)
{
    return tickstat_add_sat(tickstat_add_sat(t->late, t->overruns), t->missed);
}
