/* SPDX-License-Identifier: MIT */
/* The critical section of the HAL contract: PRIMASK saved, interrupts off, PRIMASK restored. */
#include "cortex_m.h"
#include "hal/hal.h"

hal_irq_state_t hal_critical_enter(void)
{
    return cm_atomic_begin();
}

void hal_critical_exit(hal_irq_state_t state)
{
    cm_atomic_end(&state);
}
