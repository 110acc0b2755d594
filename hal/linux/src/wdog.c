/* SPDX-License-Identifier: MIT */
/* The watchdog's stall test on injected timestamps. */
#include "lhal/wdog.h"

static uint64_t wdog_age(uint64_t now_ns, uint64_t stamp_ns)
{
    return now_ns > stamp_ns ? now_ns - stamp_ns : 0u;
}

wdog_verdict_t wdog_check(const wdog_t *w, uint64_t now_ns, uint64_t last_tick_ns,
                          uint64_t last_kick_ns, uint64_t *age_ns)
{
    uint64_t tick_age = wdog_age(now_ns, last_tick_ns);
    *age_ns = tick_age;
    if (tick_age > w->tick_limit_ns) {
        return WDOG_TICK_STALL;
    }
    uint64_t kick_age = wdog_age(now_ns, last_kick_ns);
    if (w->idle_limit_ns != 0u && kick_age > w->idle_limit_ns) {
        *age_ns = kick_age;
        return WDOG_IDLE_STALL;
    }
    return WDOG_OK;
}
