/* SPDX-License-Identifier: MIT */
/* hal_init() for the whole board, and the critical section of the HAL contract. */
#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

int hal_init(void)
{
    static const stm32_pin_t pins[] = BOARD_PINS;
    stm32_clock_init();
    stm32_gpio_setup(pins, sizeof pins / sizeof pins[0]);
    stm32_time_init();
    stm32_wheels_init(); /* motors off, driver enabled */
    stm32_sonar_init();  /* no servo pulse until the firmware commands one */
    stm32_uart_init();
    /* A slow clock is not an error: the banner reports it (stm32_clocks). */
    return HAL_OK;
}

hal_irq_state_t hal_critical_enter(void)
{
    return cm_atomic_begin();
}

void hal_critical_exit(hal_irq_state_t state)
{
    cm_atomic_end(&state);
}
