/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What hal/cortex_m asks of the chip (cm_startup.h): the STM32F405/407's interrupts, in
 * vector order, for the vector table.
 */
#ifndef CM_CHIP_H
#define CM_CHIP_H

#include "stm32f4_irq.h"

#define CM_CHIP_IRQS(X) STM32_IRQS(X)

#endif /* CM_CHIP_H */
