/* SPDX-License-Identifier: MIT */
/* hal_init() for the whole board: clocks, pins and every driver in a safe state. */
#include "board.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

STM32_START_UP int hal_init(void)
{
    static const stm32_pin_t pins[] = BOARD_PINS;
    stm32_clock_init();
    stm32_gpio_setup(pins, sizeof pins / sizeof pins[0]);
    stm32_time_init();
    stm32_wheels_init(); /* motors off, driver enabled */
    stm32_sonar_init();  /* no servo pulse until the firmware commands one */
    stm32_bump_init();
    stm32_uart_init();
    /* A slow clock is not an error: the banner reports it (stm32_clocks). */
    return HAL_OK;
}
