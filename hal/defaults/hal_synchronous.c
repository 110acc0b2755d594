/* SPDX-License-Identifier: MIT */
/*
 * The HAL's system calls for a program that runs the tick itself, in one thread: the
 * bench's scripted drive and the host half of the self-test call robot_tick() and
 * robot_idle() in turn. Nothing can interrupt anything there, so the critical section
 * masks nothing, a tick never overruns, and there is no watchdog to feed.
 *
 * Never for a backend whose tick is an interrupt or a thread: there these calls are what
 * keeps the tick and the background loop apart, so they are strong definitions in a
 * library of their own, which only such programs link, not weak defaults.
 */
#include "hal/hal.h"

hal_irq_state_t hal_critical_enter(void)
{
    return 0u;
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
}

uint32_t hal_tick_overruns(void)
{
    return 0u;
}

void hal_watchdog_kick(void)
{
}
