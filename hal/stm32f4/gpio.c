/* SPDX-License-Identifier: MIT */
/* Pin set-up from the board table: mode, alternate function, pull, output type, speed. */
#include "stm32f4_port.h"

void stm32_gpio_setup(const stm32_pin_t *pins, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const stm32_pin_t *p = &pins[i];
        stm32_gpio_t *gpio = STM32_GPIO(p->port);
        (void)stm32_periph_enable(STM32_GPIOA_BASE + STM32_GPIO_STRIDE * p->port);
        uint32_t two = 2u * p->pin;
        uint32_t four = 4u * (p->pin % 8u);
        /* Level and function first, so an output never drives before it is meant to. */
        gpio->BSRR = 1u << (p->pin + 16u);
        gpio->AFR[p->pin / 8u] =
            (gpio->AFR[p->pin / 8u] & ~(0xFu << four)) | ((uint32_t)p->af << four);
        gpio->OTYPER = (gpio->OTYPER & ~(1u << p->pin)) | ((uint32_t)p->otype << p->pin);
        gpio->OSPEEDR = (gpio->OSPEEDR & ~(3u << two)) | ((uint32_t)p->speed << two);
        gpio->PUPDR = (gpio->PUPDR & ~(3u << two)) | ((uint32_t)p->pull << two);
        gpio->MODER = (gpio->MODER & ~(3u << two)) | ((uint32_t)p->mode << two);
    }
}
