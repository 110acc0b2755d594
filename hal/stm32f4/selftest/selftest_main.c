/* SPDX-License-Identifier: MIT */
/* The self-test image: the recorded scenario on the 10 ms SysTick tick, report by semihosting. */
#include "cortex_m.h"
#include "hal/hal.h"
#include "selftest.h"
#include "semihost.h"
#include "stm32f4_port.h"
#include "text.h"

/* The instruction counter: TIM2 free-running at the timer clock. Under QEMU with
 * -icount shift=0 the timers count at 1 GHz of virtual time, one count per instruction. */
#define COUNTER_TIM STM32_TIM2_BASE
#define COSTS_MAX 16384u

static robot_t robot;
static selftest_t st;
static uint16_t costs[COSTS_MAX];

uint32_t selftest_counter(void)
{
    return STM32_TIM(COUNTER_TIM)->CNT;
}

void selftest_print(const char *s)
{
    hal_watchdog_kick(); /* the report is long; on silicon the watchdog is running */
    semihost_write0(s);
}

void stm32_fault_hook(const stm32_fault_t *f)
{
    text_line_t l;
    text_clear(&l);
    text_str(&l, "selftest: ");
    text_fault(&l, f);
    text_str(&l, "\n");
    semihost_write0(l.buf);
    semihost_exit(3u);
}

int main(void)
{
    stm32_clock_init();
    stm32_tim_t *tim = STM32_TIM(COUNTER_TIM);
    (void)stm32_periph_enable(COUNTER_TIM);
    tim->PSC = 0u;
    tim->ARR = 0xFFFFFFFFu;
    tim->EGR = STM32_TIM_EGR_UG;
    tim->CR1 = STM32_TIM_CR1_CEN;

    if (selftest_begin(&st, &robot, costs, COSTS_MAX) != 0) {
        selftest_report(&st, false);
        semihost_exit(2u);
    }
    if (hal_tick_start(selftest_step, &st) != HAL_OK) {
        stm32_panic("the tick did not start");
    }
    while (!selftest_done(&st)) {
        cm_wfi();
        selftest_idle(&st);
    }
    stm32_tick_stop();
    selftest_report(&st, true);
    selftest_reading_costs(&st);

    text_line_t l;
    text_clear(&l);
    text_str(&l, "overruns ");
    text_u32(&l, hal_tick_overruns());
    text_str(&l, "\nclock ");
    text_str(&l, stm32_clock_name());
    text_str(&l, "\n");
    semihost_write0(l.buf);
    semihost_exit(selftest_passed(&st) ? 0u : 1u);
}
