/* SPDX-License-Identifier: MIT */
/* The bump switches of the board's table (BOARD_BUMPS): inputs with the pull-up on, low while
 * pressed. */
#include "board.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

#define COUNT_ROW(...) +1
enum { BUMPS = 0 BOARD_BUMPS(COUNT_ROW) };
_Static_assert(BUMPS <= 255, "switches are numbered by a uint8_t");

/* Designated by index, so a row numbered twice or past the count fails the build; the last
 * entry only keeps the array from being empty on a board without switches. */
#define BUMP_ROW(i, port, pin)                                                                     \
    [i] = {port, pin, STM32_PIN_IN, 0, STM32_PIN_PULLUP, STM32_PIN_PUSHPULL, 0},
static const stm32_pin_t bumps[BUMPS + 1] = {BOARD_BUMPS(BUMP_ROW)[BUMPS] = {0}};

STM32_START_UP void stm32_bump_init(void)
{
    stm32_gpio_setup(bumps, BUMPS);
}

uint8_t hal_bump_count(void)
{
    return BUMPS;
}

int hal_bump_read(uint8_t bump, bool *pressed)
{
    if (BUMPS == 0) {
        return HAL_ENOSYS;
    }
    if (bump >= hal_bump_count() || pressed == NULL) { /* not BUMPS: 0 would be a warning */
        return HAL_EINVAL;
    }
    const stm32_pin_t *p = &bumps[bump];
    *pressed = (STM32_GPIO(p->port)->IDR & (1u << p->pin)) == 0u; /* closed to ground */
    return HAL_OK;
}
