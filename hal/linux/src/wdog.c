/* SPDX-License-Identifier: MIT */
/* The watchdog's stall test on injected timestamps. */
#include "lhal/wdog.h"

static uint64_t wdog_age(uint64_t now_ns, uint64_t stamp_ns)
{
    return now_ns > stamp_ns ? now_ns - stamp_ns : 0u;
}

wdog_verdict_t wdog_check(const wdog_t *w, uint64_t now_ns, const wdog_stamps_t *s,
                          uint64_t *age_ns)
{
    const struct {
        uint64_t stamp;
        uint64_t limit;
        wdog_verdict_t verdict;
    } order[] = {
        {s->tick_ns, w->tick_limit_ns, WDOG_TICK_STALL},
        {s->events_ns, w->tick_limit_ns, WDOG_EVENTS_STALL},
        {s->output_ns, w->tick_limit_ns, WDOG_OUTPUT_STALL},
        {s->kick_ns, w->idle_limit_ns, WDOG_IDLE_STALL},
    };
    *age_ns = wdog_age(now_ns, s->tick_ns);
    for (unsigned i = 0u; i < sizeof order / sizeof order[0]; i++) {
        uint64_t age = wdog_age(now_ns, order[i].stamp);
        if (order[i].limit != 0u && age > order[i].limit) {
            *age_ns = age;
            return order[i].verdict;
        }
    }
    return WDOG_OK;
}
