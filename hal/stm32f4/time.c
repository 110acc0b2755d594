/* SPDX-License-Identifier: MIT */
/* The free-running 1 MHz time base behind hal_time_us(): a 32-bit timer. */
#include "board.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

STM32_START_UP void stm32_time_init(void)
{
    stm32_tim_t *tim = STM32_TIM(BOARD_TIME_TIM);
    (void)stm32_periph_enable(BOARD_TIME_TIM);
    tim->CR1 = 0u;
    tim->PSC = stm32_timer_clock_hz(BOARD_TIME_TIM) / 1000000u - 1u;
    tim->ARR = 0xFFFFFFFFu;
    tim->EGR = STM32_TIM_EGR_UG; /* load the prescaler now, not at the first wrap */
    tim->CR1 = STM32_TIM_CR1_CEN;
}

uint32_t hal_time_us(void)
{
    return STM32_TIM(BOARD_TIME_TIM)->CNT;
}
