/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The board table of a generic STM32F405RG robot board: every pin, timer and channel the
 * port uses, in one place. A new board copies this file to board_<name>.h, edits the
 * table and builds with -DSTM32F4_BOARD=<name>.
 *
 * Timer choices: TIM1/TIM8 (16-bit, encoder mode) count the wheels; TIM3 makes the 20 kHz
 * motor PWM; TIM10 the 50 Hz servo pulse at 1 µs resolution; TIM9 in one-pulse mode the
 * 10 µs sonar trigger, so no code waits for it; TIM5 (32-bit) measures the echo width in
 * PWM-input mode, so the capture interrupt only posts a finished number; TIM2 (32-bit)
 * is the free-running microsecond clock. The tick is SysTick.
 *
 * Wiring (also in the README):
 *
 *   function                 pin        peripheral      note
 *   left encoder A, B        PA8, PA9   TIM1 CH1, CH2   pull-ups on
 *   right encoder A, B       PC6, PC7   TIM8 CH1, CH2   pull-ups on; counts inverted
 *   left motor PWM           PB0        TIM3 CH3        TB6612 PWMA / L298N ENA
 *   right motor PWM          PB1        TIM3 CH4        TB6612 PWMB / L298N ENB
 *   left motor IN1, IN2      PC0, PC1   GPIO            direction
 *   right motor IN1, IN2     PC2, PC3   GPIO            direction; inverted
 *   motor driver standby     PC4        GPIO            high = enabled (TB6612 STBY)
 *   servo signal             PB8        TIM10 CH1       SG90, 50 Hz
 *   sonar trigger            PA2        TIM9 CH1        HC-SR04 TRIG, 12 µs pulse
 *   sonar echo               PA0        TIM5 CH1        HC-SR04 ECHO (5 V: use a divider)
 *   telemetry TX, RX         PB6, PB7   USART1          115200 8N1, 3.3 V levels
 */
#ifndef STM32F4_BOARD_GENERIC_F405_H
#define STM32F4_BOARD_GENERIC_F405_H

#include "stm32f4_port.h"

#define BOARD_NAME "generic-f405"

/* ---- chip and clocks --------------------------------------------------------------------- */

/** The linker script of the chip (hal/stm32f4/): 1 MiB flash, 128 KiB SRAM. */
#define BOARD_LINKER_SCRIPT "stm32f405rg.ld"

/** The crystal, and the PLL's input divided down from it (1..2 MHz, dividing 16 MHz too). */
#define BOARD_HSE_HZ 8000000u
#define BOARD_PLL_IN_HZ 2000000u
/** 168 MHz; APB1 at 42 MHz and APB2 at 84 MHz, their maxima (RM0090 §6.2). */
#define BOARD_SYSCLK_HZ 168000000u
#define BOARD_APB1_DIV 4u
#define BOARD_APB2_DIV 2u
#define BOARD_SYSCLK_MAX_HZ 168000000u
#define BOARD_APB1_MAX_HZ 42000000u
#define BOARD_APB2_MAX_HZ 84000000u
/** Regulator scale 1, needed above 144 MHz. */
#define BOARD_PWR_VOS STM32_PWR_CR_VOS_F405_SCALE1

/* ---- map ------------------------------------------------------------------------------- */

/** The grid this board holds, A x B cells (12 m x 12 m at the default 50 mm): OM and TM take
 *  2·A·B = 115 200 bytes of the 128 KiB SRAM, leaving 15.5 KiB for the robot's other state
 *  and the stack (`make bench` gives the RAM used against 2·A·B + 8 KiB). A record
 *  (header, OM, TM) must fit one storage slot (storage.c checks at build time). The build
 *  reads both numbers from these lines: keep them plain decimal. */
#define BOARD_GRID_A 240u
#define BOARD_GRID_B 240u

/* ---- pins ----------------------------------------------------------------------------- */

#define BOARD_PORT_A 0u
#define BOARD_PORT_B 1u
#define BOARD_PORT_C 2u

/** Every pin the port drives or reads but those of the instance tables below (servos,
 *  sonars, bump switches), which their drivers configure from their rows. */
#define BOARD_PINS                                                                                 \
    {                                                                                              \
        /* port, pin, mode, alternate function, pull, output type, speed */                        \
        {                                                                                          \
            BOARD_PORT_A,       8, STM32_PIN_AF, 1, STM32_PIN_PULLUP,                              \
            STM32_PIN_PUSHPULL, 0}, /* TIM1_CH1 */                                                 \
            {BOARD_PORT_A,       9, STM32_PIN_AF, 1, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM1_CH2 */                                                \
            {BOARD_PORT_C,       6, STM32_PIN_AF, 3, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM8_CH1 */                                                \
            {BOARD_PORT_C,       7, STM32_PIN_AF, 3, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM8_CH2 */                                                \
            {BOARD_PORT_B,       0, STM32_PIN_AF, 2, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* TIM3_CH3 */                                                \
            {BOARD_PORT_B,       1, STM32_PIN_AF, 2, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* TIM3_CH4 */                                                \
            {BOARD_PORT_C,       0, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                            \
             STM32_PIN_PUSHPULL, 0}, /* IN1 L */                                                   \
            {BOARD_PORT_C,       1, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                            \
             STM32_PIN_PUSHPULL, 0}, /* IN2 L */                                                   \
            {BOARD_PORT_C,       2, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                            \
             STM32_PIN_PUSHPULL, 0}, /* IN1 R */                                                   \
            {BOARD_PORT_C,       3, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                            \
             STM32_PIN_PUSHPULL, 0}, /* IN2 R */                                                   \
            {BOARD_PORT_C,       4, STM32_PIN_OUT, 0, STM32_PIN_PULLDOWN,                          \
             STM32_PIN_PUSHPULL, 0}, /* STBY */                                                    \
            {BOARD_PORT_B,       6, STM32_PIN_AF, 7, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* USART1_TX */                                               \
            {BOARD_PORT_B,       7, STM32_PIN_AF, 7, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* USART1_RX */                                               \
    }

/* ---- wheels ------------------------------------------------------------------------------ */

#define BOARD_ENC_LEFT_TIM STM32_TIM1_BASE
#define BOARD_ENC_LEFT_INVERT 0
#define BOARD_ENC_RIGHT_TIM STM32_TIM8_BASE
#define BOARD_ENC_RIGHT_INVERT 1 /* the right wheel turns the other way round its axle */
/** Input filter IC1F/IC2F of the encoder inputs: fDTS/4, 6 samples (about 140 ns). */
#define BOARD_ENC_FILTER 6u

#define BOARD_MOTOR_TIM STM32_TIM3_BASE
#define BOARD_MOTOR_PWM_HZ 20000u /* above hearing */
#define BOARD_MOTOR_LEFT_CH 3u
#define BOARD_MOTOR_RIGHT_CH 4u
#define BOARD_MOTOR_DIR_PORT BOARD_PORT_C /* the four direction pins share one port */
#define BOARD_MOTOR_LEFT_IN1 0u
#define BOARD_MOTOR_LEFT_IN2 1u
#define BOARD_MOTOR_LEFT_INVERT 0
#define BOARD_MOTOR_RIGHT_IN1 2u
#define BOARD_MOTOR_RIGHT_IN2 3u
#define BOARD_MOTOR_RIGHT_INVERT 1
#define BOARD_MOTOR_STBY_PORT BOARD_PORT_C
#define BOARD_MOTOR_STBY_PIN 4u

/* ---- servos, sonars and bump switches: one row per instance -------------------------------- */

/*
 * hal.h addresses servos and sonars by instance, and each instance is one row here: row 0
 * is the paper's (the sweep servo, the swept sonar); a board adds a sensor by adding a row
 * numbered 1, 2, ... (firmware/README.md, "Adding a sonar instance"). Rows are numbered from
 * 0 without a gap; a duplicate or a gap fails the build. Pins are set up from the rows.
 *
 * Servo: a 50 Hz PWM output at 1 µs a count, on a channel of a timer of its own.
 *   X(index, pin port, pin, AF, timer, channel)
 * Sonar (HC-SR04): a trigger timer in one-pulse mode (on the F405 TIM1-5, 8, 9 or 12), and
 * an echo timer in PWM-input mode whose CH1 or CH2 pin takes the echo, the other channel
 * capturing the width; 32-bit (TIM2, TIM5) or 16-bit (an echo is shorter than 65 ms), each
 * with an interrupt no other driver uses (IRQ: its name in stm32f4_irq.h).
 *   X(index, trigger port, pin, AF, timer, channel, echo port, pin, AF, timer, channel, IRQ)
 * Bump switch: a GPIO input with the pull-up on, closed to ground when pressed.
 *   X(index, port, pin)
 */
#define BOARD_SERVOS(X) X(0, BOARD_PORT_B, 8, 3, TIM10, 1) /* PB8 TIM10_CH1 */

#define BOARD_SONARS(X)                                                                            \
    X(0, BOARD_PORT_A, 2, 3, TIM9, 1, BOARD_PORT_A, 0, 2, TIM5, 1, TIM5) /* PA2, PA0 */

/* None wired. Two on PC8 and PC9 would be X(0, BOARD_PORT_C, 8) X(1, BOARD_PORT_C, 9). */
#define BOARD_BUMPS(X)

#define BOARD_TRIG_PULSE_US 12u /* HC-SR04 wants at least 10 µs */

/* ---- time, telemetry, storage ------------------------------------------------------------ */

#define BOARD_TIME_TIM STM32_TIM2_BASE /* 32-bit, free-running at 1 MHz */

#define BOARD_UART STM32_USART1_BASE
#define BOARD_UART_IRQ STM32_IRQ_USART1
#define BOARD_UART_IRQHandler USART1_IRQHandler
#define BOARD_UART_BAUD 115200u

/** Map storage: the last two 128 KiB sectors; the linker script keeps code below them. */
#define BOARD_STORAGE_SECTOR0 10u
#define BOARD_STORAGE_ADDR0 0x080C0000u
#define BOARD_STORAGE_SECTOR1 11u
#define BOARD_STORAGE_ADDR1 0x080E0000u
#define BOARD_STORAGE_BYTES (128u * 1024u)
/** Program 32 bits at a time: needs a 2.7-3.6 V supply (RM0090 Table 6). */
#define BOARD_FLASH_PSIZE STM32_FLASH_CR_PSIZE_X32
/** Flash wait states at 168 MHz and 2.7-3.6 V (RM0090 Table 10). */
#define BOARD_FLASH_WAIT_STATES 5u

/* ---- interrupt priorities (0x00 highest .. 0xF0) ------------------------------------------ */

#define BOARD_PRIO_ECHO 0x40u /* the sonars' captures: short, must not wait for the tick */
#define BOARD_PRIO_TICK 0x80u
#define BOARD_PRIO_UART 0xC0u /* telemetry waits for the tick */

#endif /* STM32F4_BOARD_GENERIC_F405_H */
