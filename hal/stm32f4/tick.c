/* SPDX-License-Identifier: MIT */
/* The 10 ms tick from SysTick and its overrun count. */
#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

static hal_tick_fn tick_fn;
static void *tick_ctx;
static uint32_t tick_late_limit; /* SysTick counts after the reload that still count as on time */
static volatile uint32_t tick_overruns;

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    if (fn == NULL) {
        return HAL_EINVAL;
    }
    if (tick_fn != NULL) {
        return HAL_EBUSY;
    }
    uint32_t load = stm32_clocks.sysclk_hz / (1000000u / HAL_TICK_PERIOD_US) - 1u;
    if (load > CM_SYSTICK_LOAD_MAX) {
        return HAL_EINVAL; /* no clock set up yet (0 Hz), or one above 1.6 GHz */
    }
    tick_fn = fn;
    tick_ctx = ctx;
    /* A tick that starts more than a tenth of the period late counts as an overrun. */
    tick_late_limit = load / 10u;
    CM_SCB->SHPR[CM_SHPR_SYSTICK] = BOARD_PRIO_TICK;
    CM_SYSTICK->LOAD = load;
    CM_SYSTICK->VAL = 0u;
    CM_SYSTICK->CTRL =
        CM_SYSTICK_CTRL_CLKSOURCE_CPU | CM_SYSTICK_CTRL_TICKINT | CM_SYSTICK_CTRL_ENABLE;
    /* The tick is what the watchdog guards: robot_idle() feeds it while ticks go on. */
    stm32_watchdog_start(STM32_WATCHDOG_MS);
    return HAL_OK;
}

void stm32_tick_stop(void)
{
    CM_SYSTICK->CTRL = 0u;
    CM_SCB->ICSR = CM_SCB_ICSR_PENDSTCLR; /* forget a tick that is already pending */
    tick_fn = NULL;
}

uint32_t hal_tick_overruns(void)
{
    return tick_overruns;
}

void SysTick_Handler(void)
{
    /* SysTick counts ..., 1, 0, LOAD, LOAD - 1, ... and interrupts on reaching 0, so 0
     * is the first count of the new period (QEMU takes the interrupt before the reload);
     * any other value v is LOAD - v + 1 counts into it. */
    uint32_t val = CM_SYSTICK->VAL;
    uint32_t elapsed = val == 0u ? 0u : CM_SYSTICK->LOAD - val + 1u;
    bool late = elapsed > tick_late_limit;
    tick_fn(tick_ctx);
    /* Still running when the next period began: the tick overran. */
    if (late || (CM_SCB->ICSR & CM_SCB_ICSR_PENDSTSET) != 0u) {
        tick_overruns++;
    }
}
