/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The board table of the WeAct "Black Pill" STM32F411CEU6 (512 KiB flash, 128 KiB SRAM,
 * a 25 MHz crystal): every pin, timer and channel the port uses, in one place.
 *
 * The F411 has no TIM8, no TIM6/7 and no port C beyond PC13-15 in this package, so the
 * table differs from the F405's: TIM3 and TIM4 (16-bit, encoder mode) count the wheels;
 * TIM9 makes the 20 kHz motor PWM on two channels; TIM10 the 50 Hz servo pulse; TIM1 in
 * one-pulse mode the sonar trigger; TIM2 (32-bit) measures the echo in PWM-input mode;
 * TIM5 (32-bit) is the free-running microsecond clock. USART1 is on PA9/PA10, the pins
 * the chip's own serial boot loader listens on. The tick is SysTick.
 *
 * Pins left alone: PA11/PA12 (the USB-C connector), PA13/PA14 (SWD), PC13 (the blue LED),
 * PC14/PC15 (the 32 kHz crystal), PA0 (the KEY button), PB2 (BOOT1).
 *
 * Wiring (also in hal/stm32f4/README.md):
 *
 *   function                 pin          peripheral      note
 *   left encoder A, B        PA6, PA7     TIM3 CH1, CH2   pull-ups on
 *   right encoder A, B       PB6, PB7     TIM4 CH1, CH2   pull-ups on; counts inverted
 *   left motor PWM           PA2          TIM9 CH1        TB6612 PWMA / L298N ENA
 *   right motor PWM          PA3          TIM9 CH2        TB6612 PWMB / L298N ENB
 *   left motor IN1, IN2      PB12, PB13   GPIO            direction
 *   right motor IN1, IN2     PB14, PB15   GPIO            direction; inverted
 *   motor driver standby     PB10         GPIO            high = enabled (TB6612 STBY)
 *   servo signal             PB8          TIM10 CH1       SG90, 50 Hz
 *   sonar trigger            PA8          TIM1 CH1        HC-SR04 TRIG, 12 µs pulse
 *   sonar echo               PA5          TIM2 CH1        HC-SR04 ECHO (5 V: use a divider)
 *   telemetry TX, RX         PA9, PA10    USART1          115200 8N1, 3.3 V levels
 */
#ifndef STM32F4_BOARD_BLACKPILL_F411_H
#define STM32F4_BOARD_BLACKPILL_F411_H

#include "stm32f4_port.h"

#define BOARD_NAME "blackpill-f411"

/* ---- chip and clocks --------------------------------------------------------------------- */

/** The linker script of the chip (hal/stm32f4/): 512 KiB flash, 128 KiB SRAM. */
#define BOARD_LINKER_SCRIPT "stm32f411ce.ld"

/** The 25 MHz crystal, divided by 25 to the PLL's 1 MHz input (16 MHz HSI by 16). */
#define BOARD_HSE_HZ 25000000u
#define BOARD_PLL_IN_HZ 1000000u
/** 96 MHz: a VCO of 192 MHz gives USB its 48 MHz should it be used; 100 MHz would not.
 *  APB1 at 48 MHz (its maximum is 50), APB2 undivided (RM0383 §6.2). */
#define BOARD_SYSCLK_HZ 96000000u
#define BOARD_APB1_DIV 2u
#define BOARD_APB2_DIV 1u
#define BOARD_SYSCLK_MAX_HZ 100000000u
#define BOARD_APB1_MAX_HZ 50000000u
#define BOARD_APB2_MAX_HZ 100000000u
/** Regulator scale 1: the reset value (scale 2) allows only 84 MHz. */
#define BOARD_PWR_VOS STM32_PWR_CR_VOS_F411_SCALE1

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

/** Every pin the port drives or reads but those of the instance tables below (servos,
 *  sonars, bump switches), which their drivers configure from their rows. */
#define BOARD_PINS                                                                                 \
    {                                                                                              \
        /* port, pin, mode, alternate function, pull, output type, speed */                        \
        {                                                                                          \
            BOARD_PORT_A,       6, STM32_PIN_AF, 2, STM32_PIN_PULLUP,                              \
            STM32_PIN_PUSHPULL, 0}, /* TIM3_CH1 */                                                 \
            {BOARD_PORT_A,       7, STM32_PIN_AF, 2, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM3_CH2 */                                                \
            {BOARD_PORT_B,       6, STM32_PIN_AF, 2, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM4_CH1 */                                                \
            {BOARD_PORT_B,       7, STM32_PIN_AF, 2, STM32_PIN_PULLUP,                             \
             STM32_PIN_PUSHPULL, 0}, /* TIM4_CH2 */                                                \
            {BOARD_PORT_A,       2, STM32_PIN_AF, 3, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* TIM9_CH1 */                                                \
            {BOARD_PORT_A,       3, STM32_PIN_AF, 3, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* TIM9_CH2 */                                                \
            {BOARD_PORT_B,       12, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                           \
             STM32_PIN_PUSHPULL, 0}, /* IN1 L */                                                   \
            {BOARD_PORT_B,       13, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                           \
             STM32_PIN_PUSHPULL, 0}, /* IN2 L */                                                   \
            {BOARD_PORT_B,       14, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                           \
             STM32_PIN_PUSHPULL, 0}, /* IN1 R */                                                   \
            {BOARD_PORT_B,       15, STM32_PIN_OUT, 0, STM32_PIN_NOPULL,                           \
             STM32_PIN_PUSHPULL, 0}, /* IN2 R */                                                   \
            {BOARD_PORT_B,       10, STM32_PIN_OUT, 0, STM32_PIN_PULLDOWN,                         \
             STM32_PIN_PUSHPULL, 0}, /* STBY */                                                    \
            {BOARD_PORT_A,       9, STM32_PIN_AF, 7, STM32_PIN_NOPULL,                             \
             STM32_PIN_PUSHPULL, 1}, /* USART1_TX */                                               \
            {BOARD_PORT_A,       10, STM32_PIN_AF, 7, STM32_PIN_PULLUP,                            \
             STM32_PIN_PUSHPULL, 0}, /* USART1_RX */                                               \
    }

/* ---- wheels ------------------------------------------------------------------------------ */

#define BOARD_ENC_LEFT_TIM STM32_TIM3_BASE
#define BOARD_ENC_LEFT_INVERT 0
#define BOARD_ENC_RIGHT_TIM STM32_TIM4_BASE
#define BOARD_ENC_RIGHT_INVERT 1 /* the right wheel turns the other way round its axle */
/** Input filter IC1F/IC2F of the encoder inputs: fDTS/4, 6 samples (about 250 ns). */
#define BOARD_ENC_FILTER 6u

#define BOARD_MOTOR_TIM STM32_TIM9_BASE
#define BOARD_MOTOR_PWM_HZ 20000u /* above hearing */
#define BOARD_MOTOR_LEFT_CH 1u
#define BOARD_MOTOR_RIGHT_CH 2u
#define BOARD_MOTOR_DIR_PORT BOARD_PORT_B /* the four direction pins share one port */
#define BOARD_MOTOR_LEFT_IN1 12u
#define BOARD_MOTOR_LEFT_IN2 13u
#define BOARD_MOTOR_LEFT_INVERT 0
#define BOARD_MOTOR_RIGHT_IN1 14u
#define BOARD_MOTOR_RIGHT_IN2 15u
#define BOARD_MOTOR_RIGHT_INVERT 1
#define BOARD_MOTOR_STBY_PORT BOARD_PORT_B
#define BOARD_MOTOR_STBY_PIN 10u

/* ---- servos, sonars and bump switches: one row per instance -------------------------------- */

/* The rows' fields are board_generic_f405.h's. The trigger timer needs one-pulse mode: on
 * the F411 TIM1-5 or 9. */
#define BOARD_SERVOS(X) X(0, BOARD_PORT_B, 8, 3, TIM10, 1) /* PB8 TIM10_CH1 */

#define BOARD_SONARS(X)                                                                            \
    X(0, BOARD_PORT_A, 8, 1, TIM1, 1, BOARD_PORT_A, 5, 1, TIM2, 1, TIM2) /* PA8, PA5 */

/* None wired. */
#define BOARD_BUMPS(X)

#define BOARD_TRIG_PULSE_US 12u /* HC-SR04 wants at least 10 µs */

/* ---- time, telemetry, storage ------------------------------------------------------------ */

#define BOARD_TIME_TIM STM32_TIM5_BASE /* 32-bit, free-running at 1 MHz */

#define BOARD_UART STM32_USART1_BASE
#define BOARD_UART_IRQ STM32_IRQ_USART1
#define BOARD_UART_IRQHandler USART1_IRQHandler
#define BOARD_UART_BAUD 115200u

/** Map storage: the last two 128 KiB sectors (6 and 7 of the F411's eight, RM0383
 *  Table 5); the linker script keeps code below them. */
#define BOARD_STORAGE_SECTOR0 6u
#define BOARD_STORAGE_ADDR0 0x08040000u
#define BOARD_STORAGE_SECTOR1 7u
#define BOARD_STORAGE_ADDR1 0x08060000u
#define BOARD_STORAGE_BYTES (128u * 1024u)
/** Program 32 bits at a time: needs a 2.7-3.6 V supply (the board's regulator gives 3.3 V). */
#define BOARD_FLASH_PSIZE STM32_FLASH_CR_PSIZE_X32
/** Flash wait states at 96 MHz and 2.7-3.6 V: 3 (RM0383 Table 6: 90-100 MHz). */
#define BOARD_FLASH_WAIT_STATES 3u

/* ---- interrupt priorities (0x00 highest .. 0xF0) ------------------------------------------ */

#define BOARD_PRIO_ECHO 0x40u /* the sonars' captures: short, must not wait for the tick */
#define BOARD_PRIO_TICK 0x80u
#define BOARD_PRIO_UART 0xC0u /* telemetry waits for the tick */

#endif /* STM32F4_BOARD_BLACKPILL_F411_H */
