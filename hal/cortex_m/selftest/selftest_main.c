/* SPDX-License-Identifier: MIT */
/* The self-test image: the recorded scenario on the chip's 10 ms tick, report by semihosting. */
#include "cm_startup.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "selftest.h"
#include "selftest_port.h"
#include "semihost.h"
#include "text.h"

/* tools/slamtools/cortex_m/unicorn_run.py calls into the image with these two by name. */
static robot_t robot;
static selftest_t st;

/* Each tick's cost is kept in the RAM the image leaves free, between the end of .bss and
 * the end of RAM (cm_sections.ld): with a board's largest map that holds the first few
 * thousand ticks, not the whole scenario; the report's sum and worst cover every tick. */
extern uint32_t _ebss[];
extern uint32_t _eram[];

void selftest_print(const char *s)
{
    hal_watchdog_kick(); /* the report is long; on silicon the watchdog is running */
    semihost_write0(s);
}

void cm_fault_hook(const cm_fault_t *f)
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
    selftest_port_init();

    uint32_t costs_max = (uint32_t)((uintptr_t)_eram - (uintptr_t)_ebss) / sizeof(uint16_t);
    if (selftest_begin(&st, &robot, (uint16_t *)(void *)_ebss, costs_max) != 0) {
        selftest_report(&st, false);
        semihost_exit(2u);
    }
    if (hal_tick_start(selftest_step, &st) != HAL_OK) {
        cm_panic("the tick did not start");
    }
    while (!selftest_done(&st)) {
        cm_wfi();
        selftest_idle(&st);
    }
    selftest_port_stop();
    selftest_report(&st, true);
    selftest_reading_costs(&st);

    text_line_t l;
    text_clear(&l);
    text_str(&l, "overruns ");
    text_u32(&l, hal_tick_overruns());
    text_str(&l, "\nclock ");
    text_str(&l, selftest_port_clock_name());
    text_str(&l, "\n");
    semihost_write0(l.buf);
    semihost_exit(selftest_passed(&st) ? 0u : 1u);
}
