/* SPDX-License-Identifier: MIT */
/* The independent watchdog (IWDG) on the ~32 kHz LSI: start, retime, feed. */
#include "hal/hal.h"
#include "stm32f4_port.h"

#define LSI_HZ 32000u /* nominal; RM0090 allows 17-47 kHz, so timeouts are ±50 % */
#define PR_MAX 6u     /* divider 4 << 6 = 256 */

/* PVU/RVU clear within a few LSI periods (about 200 µs); this is far more at 168 MHz and
 * keeps a dead LSI (or QEMU, which has no IWDG) from hanging the caller. */
#define IWDG_WAIT_LOOPS 100000u

static void iwdg_wait_updates(void)
{
    for (uint32_t n = 0; n < IWDG_WAIT_LOOPS; n++) {
        if ((STM32_IWDG->SR & (STM32_IWDG_SR_PVU | STM32_IWDG_SR_RVU)) == 0u) {
            return;
        }
    }
}

/* Prescaler and reload for a timeout: the finest divider whose 12-bit reload reaches it. */
static void iwdg_program(uint32_t timeout_ms)
{
    uint32_t pr = 0u;
    uint32_t ticks = timeout_ms * (LSI_HZ / 1000u);
    while (pr < PR_MAX && ticks / (4u << pr) > STM32_IWDG_RLR_MAX) {
        pr++;
    }
    uint32_t reload = ticks / (4u << pr);
    if (reload > STM32_IWDG_RLR_MAX) {
        reload = STM32_IWDG_RLR_MAX;
    } else if (reload == 0u) {
        reload = 1u;
    }
    iwdg_wait_updates(); /* PR and RLR refuse writes while an update is pending */
    STM32_IWDG->KR = STM32_IWDG_KR_UNLOCK;
    STM32_IWDG->PR = pr;
    STM32_IWDG->RLR = reload;
    iwdg_wait_updates(); /* the reload below must load the new value */
    STM32_IWDG->KR = STM32_IWDG_KR_RELOAD;
}

void stm32_watchdog_start(uint32_t timeout_ms)
{
    /* Stop counting while a debugger holds the core (make debug), or every breakpoint resets. */
    STM32_DBGMCU->APB1_FZ |= STM32_DBGMCU_APB1_FZ_IWDG_STOP;
    STM32_IWDG->KR = STM32_IWDG_KR_START; /* also starts the LSI */
    iwdg_program(timeout_ms);
}

void stm32_watchdog_set_timeout(uint32_t timeout_ms)
{
    iwdg_program(timeout_ms);
}

void hal_watchdog_kick(void)
{
    STM32_IWDG->KR = STM32_IWDG_KR_RELOAD;
}
