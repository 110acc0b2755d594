/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The 82 interrupts of the STM32F405/407 (RM0090 Table 61), as one list from which the
 * vector table, the handler prototypes and the IRQ numbers are made.
 *
 * The vector table is hal/cortex_m's (cm_chip.h hands it this list): every handler is weak,
 * a driver defines the one it needs (void USART1_IRQHandler(void)) and every other vector
 * lands in the default handler, which treats it as a fault.
 */
#ifndef STM32F4_IRQ_H
#define STM32F4_IRQ_H

/* Interrupts in vector order: position n is IRQ n, exception 16 + n. */
/* clang-format off */
#define STM32_IRQS(X)                                                                           \
    X(WWDG) X(PVD) X(TAMP_STAMP) X(RTC_WKUP) X(FLASH) X(RCC) X(EXTI0) X(EXTI1) X(EXTI2)        \
    X(EXTI3) X(EXTI4) X(DMA1_Stream0) X(DMA1_Stream1) X(DMA1_Stream2) X(DMA1_Stream3)          \
    X(DMA1_Stream4) X(DMA1_Stream5) X(DMA1_Stream6) X(ADC) X(CAN1_TX) X(CAN1_RX0)              \
    X(CAN1_RX1) X(CAN1_SCE) X(EXTI9_5) X(TIM1_BRK_TIM9) X(TIM1_UP_TIM10)                       \
    X(TIM1_TRG_COM_TIM11) X(TIM1_CC) X(TIM2) X(TIM3) X(TIM4) X(I2C1_EV) X(I2C1_ER)             \
    X(I2C2_EV) X(I2C2_ER) X(SPI1) X(SPI2) X(USART1) X(USART2) X(USART3) X(EXTI15_10)           \
    X(RTC_Alarm) X(OTG_FS_WKUP) X(TIM8_BRK_TIM12) X(TIM8_UP_TIM13) X(TIM8_TRG_COM_TIM14)       \
    X(TIM8_CC) X(DMA1_Stream7) X(FSMC) X(SDIO) X(TIM5) X(SPI3) X(UART4) X(UART5)               \
    X(TIM6_DAC) X(TIM7) X(DMA2_Stream0) X(DMA2_Stream1) X(DMA2_Stream2) X(DMA2_Stream3)        \
    X(DMA2_Stream4) X(ETH) X(ETH_WKUP) X(CAN2_TX) X(CAN2_RX0) X(CAN2_RX1) X(CAN2_SCE)          \
    X(OTG_FS) X(DMA2_Stream5) X(DMA2_Stream6) X(DMA2_Stream7) X(USART6) X(I2C3_EV)             \
    X(I2C3_ER) X(OTG_HS_EP1_OUT) X(OTG_HS_EP1_IN) X(OTG_HS_WKUP) X(OTG_HS) X(DCMI) X(CRYP)     \
    X(HASH_RNG) X(FPU)
/* clang-format on */

/** IRQ numbers: STM32_IRQ_USART1 == 37 and so on. */
#define STM32_IRQ_ENUM_(name) STM32_IRQ_##name,
typedef enum { STM32_IRQS(STM32_IRQ_ENUM_) STM32_IRQ_COUNT } stm32_irq_t;
#undef STM32_IRQ_ENUM_
_Static_assert(STM32_IRQ_COUNT == 82, "the STM32F405 has 82 interrupts");
_Static_assert(STM32_IRQ_TIM5 == 50 && STM32_IRQ_USART1 == 37 && STM32_IRQ_TIM2 == 28,
               "IRQ numbers follow RM0090 Table 61");

#define STM32_IRQ_PROTO_(name) void name##_IRQHandler(void);
STM32_IRQS(STM32_IRQ_PROTO_)
#undef STM32_IRQ_PROTO_

#endif /* STM32F4_IRQ_H */
