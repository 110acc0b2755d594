/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A test board table: the generic F405 board with a second, side-looking sonar and two bump
 * switches, so the drivers' instance tables are built and run with more than one row (the
 * shipped boards have one of each and no switches). Only the register-model test uses it.
 *
 * Added to board_generic_f405.h's pins and timers:
 *
 *   function                 pin        peripheral            note
 *   sonar 1 trigger          PB9        TIM4 CH4, one-pulse   HC-SR04 TRIG, 12 µs
 *   sonar 1 echo             PB15       TIM12 CH2, PWM input  16-bit; the width on CH1
 *   bump switch 0 (left)     PC8        GPIO input, pull-up   closes to ground
 *   bump switch 1 (right)    PC9        GPIO input, pull-up   closes to ground
 */
#ifndef STM32F4_BOARD_TEST_F405_SIDE_H
#define STM32F4_BOARD_TEST_F405_SIDE_H

#include "board_generic_f405.h"

#undef BOARD_NAME
#define BOARD_NAME "test-f405-side"

/* The build reads the linker script's name and the grid from this file's own lines. */
#undef BOARD_LINKER_SCRIPT
#define BOARD_LINKER_SCRIPT "stm32f405rg.ld"
#undef BOARD_GRID_A
#define BOARD_GRID_A 240u
#undef BOARD_GRID_B
#define BOARD_GRID_B 240u

#undef BOARD_SONARS
#define BOARD_SONARS(X)                                                                            \
    X(0, BOARD_PORT_A, 2, 3, TIM9, 1, BOARD_PORT_A, 0, 2, TIM5, 1, TIM5) /* PA2, PA0 */            \
    X(1, BOARD_PORT_B, 9, 2, TIM4, 4, BOARD_PORT_B, 15, 9, TIM12, 2, TIM8_BRK_TIM12)

#undef BOARD_BUMPS
#define BOARD_BUMPS(X) X(0, BOARD_PORT_C, 8) X(1, BOARD_PORT_C, 9)

#endif /* STM32F4_BOARD_TEST_F405_SIDE_H */
