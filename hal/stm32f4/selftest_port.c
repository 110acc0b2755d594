/* SPDX-License-Identifier: MIT */
/* The STM32F4's part of the self-test image (hal/cortex_m/selftest): clocks, TIM2 as counter. */
#include "selftest.h"
#include "selftest_port.h"
#include "stm32f4_port.h"

/* The instruction counter: TIM2 free-running at the timer clock. Under QEMU with
 * -icount shift=0 the timers count at 1 GHz of virtual time, one count per instruction. */
#define COUNTER_TIM STM32_TIM2_BASE

uint32_t selftest_counter(void)
{
    return STM32_TIM(COUNTER_TIM)->CNT;
}

void selftest_port_init(void)
{
    stm32_clock_init();
    stm32_tim_t *tim = STM32_TIM(COUNTER_TIM);
    (void)stm32_periph_enable(COUNTER_TIM);
    tim->PSC = 0u;
    tim->ARR = 0xFFFFFFFFu;
    tim->EGR = STM32_TIM_EGR_UG;
    tim->CR1 = STM32_TIM_CR1_CEN;
}

void selftest_port_stop(void)
{
    stm32_tick_stop();
}

const char *selftest_port_clock_name(void)
{
    return stm32_clock_name();
}
