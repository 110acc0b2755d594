/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The interfaces between the files of the STM32F4 port (not part of the HAL contract):
 * clocks, pins, the time base and tick, the watchdog, the UART pump. Start-up and faults
 * are hal/cortex_m's (cm_startup.h).
 *
 * Which files an image links decides what it is: the robot image links them all with
 * main.c; the self-test image links the start-up, clock, tick, watchdog and critical
 * section with the replay HAL (hal/cortex_m/selftest) instead of the time base, wheel,
 * sonar, bump, UART and storage drivers.
 */
#ifndef STM32F4_PORT_H
#define STM32F4_PORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cm_startup.h"
#include "stm32f4_irq.h"
#include "stm32f4_regs.h"

/** A function that runs at start-up (or on the way down), never in a tick: built for size and
 *  away from the tick's code (GCC's cold). The core's SLAM_START_UP says the same. */
#define STM32_START_UP __attribute__((cold))

/* ---- clocks (clock.c) ---------------------------------------------------------------- */

typedef enum {
    STM32_CLOCK_HSE_PLL = 0, /**< BOARD_SYSCLK_HZ from the crystal: the normal case */
    STM32_CLOCK_HSI_PLL,     /**< the same from the internal RC: the crystal did not start */
    STM32_CLOCK_HSI,         /**< 16 MHz internal RC: the PLL did not lock (QEMU) */
} stm32_clock_source_t;

/** The clock tree as stm32_clock_init() left it. */
typedef struct {
    stm32_clock_source_t source;
    uint32_t sysclk_hz;   /**< core and AHB */
    uint32_t pclk1_hz;    /**< APB1 peripherals */
    uint32_t pclk2_hz;    /**< APB2 peripherals (USART1) */
    uint32_t tim_apb1_hz; /**< TIM2-7, 12-14 */
    uint32_t tim_apb2_hz; /**< TIM1, 8-11 */
    bool hse_timeout;     /**< HSERDY never came */
    bool pll_timeout;     /**< PLLRDY never came */
    bool flash_refused;   /**< the flash wait states did not read back; stayed slow */
} stm32_clocks_t;

extern stm32_clocks_t stm32_clocks;

/**
 * HSE + PLL to BOARD_SYSCLK_HZ; falls back to HSI + PLL, then to HSI alone. Every wait on a
 * ready bit has a timeout (QEMU does not emulate them). Call once, first thing.
 */
void stm32_clock_init(void);

/** A short name of the clock source for the banner ("HSE+PLL"...). */
const char *stm32_clock_name(void);

/** Turn on the bus clock of a peripheral given by its base address; 0 or -1 if unknown. */
int stm32_periph_enable(uint32_t base);

/** The input clock of a timer given by its base address, Hz. */
uint32_t stm32_timer_clock_hz(uint32_t tim_base);

/** RCC_CSR's reset flags as they were at start-up (the flags are then cleared). */
uint32_t stm32_reset_flags(void);

/** The most telling reset cause for the banner ("watchdog", "power-on", ...). */
const char *stm32_reset_name(uint32_t flags);

/* ---- pins (gpio.c) --------------------------------------------------------------------- */

enum { STM32_PIN_IN = 0, STM32_PIN_OUT = 1, STM32_PIN_AF = 2, STM32_PIN_ANALOG = 3 };
enum { STM32_PIN_NOPULL = 0, STM32_PIN_PULLUP = 1, STM32_PIN_PULLDOWN = 2 };
enum { STM32_PIN_PUSHPULL = 0, STM32_PIN_OPENDRAIN = 1 };

/** One row of the board's pin table. */
typedef struct {
    uint8_t port;  /**< 0 = A, 1 = B, ... */
    uint8_t pin;   /**< 0..15 */
    uint8_t mode;  /**< STM32_PIN_IN/OUT/AF/ANALOG */
    uint8_t af;    /**< alternate function 0..15 (mode AF) */
    uint8_t pull;  /**< STM32_PIN_NOPULL/PULLUP/PULLDOWN */
    uint8_t otype; /**< STM32_PIN_PUSHPULL/OPENDRAIN */
    uint8_t speed; /**< 0 low .. 3 very high */
} stm32_pin_t;

/** Enable the ports' clocks and configure every pin of a table (outputs start low). */
void stm32_gpio_setup(const stm32_pin_t *pins, size_t n);

/** Set (level true) or clear a pin; one atomic BSRR write. ISR-safe. */
static inline void stm32_gpio_write(uint8_t port, uint8_t pin, bool level)
{
    STM32_GPIO(port)->BSRR = level ? (1u << pin) : (1u << (pin + 16u));
}

/* ---- time base and tick (time.c, tick.c) -------------------------------------------- */

/** Start the free-running 1 MHz time base behind hal_time_us(). */
void stm32_time_init(void);

/** Stop the tick (the self-test, before it reports). */
void stm32_tick_stop(void);

/* ---- watchdog (watchdog.c) ------------------------------------------------------------ */

/** The watchdog timeout while the robot runs, ms (LSI at 32 kHz nominal, ±50 %). */
#define STM32_WATCHDOG_MS 250u
/** The timeout while a flash sector is erased: RM0090 gives 2 s at most for 128 KiB. */
#define STM32_WATCHDOG_ERASE_MS 4000u

/** Start the independent watchdog; it cannot be stopped again. Frozen while halted in a debugger.
 */
void stm32_watchdog_start(uint32_t timeout_ms);

/** Change the timeout of a running watchdog and reload it. */
void stm32_watchdog_set_timeout(uint32_t timeout_ms);

/* ---- telemetry UART (uart.c) ------------------------------------------------------------ */

/** Bring up the UART with its rings and interrupt. */
void stm32_uart_init(void);

/**
 * Move queued bytes to the transmitter from the main loop. The TXE interrupt does this
 * on silicon; QEMU 7.2 never raises it, so the main loop calls this too. Not ISR-safe.
 */
void stm32_uart_pump(void);

/** Write a string by polling, for fault reports only (interrupts may be off). */
void stm32_uart_write_blocking(const char *s);

/* ---- wheels, servos and sonars, bump switches (wheels.c, sonar.c, bump.c) -------------- */

/** Each set up with its outputs off, servos and sonars from the board's instance rows.
 *  wheels.c also defines cm_safe_outputs(), which a fault calls: PWM 0, direction pins low,
 *  driver in standby. */
void stm32_wheels_init(void);
void stm32_sonar_init(void);
void stm32_bump_init(void);

#endif /* STM32F4_PORT_H */
