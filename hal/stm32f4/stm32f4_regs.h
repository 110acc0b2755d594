/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The STM32F405/407 peripheral registers this port uses, written from the reference
 * manual RM0090 (no vendor header): base addresses, register blocks and bit fields.
 *
 * Every block is a struct of `volatile uint32_t` at its base address; the offset of each
 * register is checked at compile time against the manual's register map, so a missing
 * reserved word cannot shift the registers behind it. Names are subsystem-prefixed:
 * STM32_<PERIPH>_<REG>_<FIELD>.
 */
#ifndef STM32F4_REGS_H
#define STM32F4_REGS_H

#include <stddef.h>
#include <stdint.h>

/* ---- memory map (RM0090 §2.3) ------------------------------------------------------ */

#define STM32_FLASH_MEM_BASE 0x08000000u /**< main flash, 1 MiB on the F405RG */
#define STM32_SRAM_BASE 0x20000000u      /**< SRAM1 (112 KiB) + SRAM2 (16 KiB) */

#define STM32_TIM2_BASE 0x40000000u
#define STM32_TIM3_BASE 0x40000400u
#define STM32_TIM4_BASE 0x40000800u
#define STM32_TIM5_BASE 0x40000C00u
#define STM32_TIM6_BASE 0x40001000u
#define STM32_TIM7_BASE 0x40001400u
#define STM32_TIM12_BASE 0x40001800u
#define STM32_TIM13_BASE 0x40001C00u
#define STM32_TIM14_BASE 0x40002000u
#define STM32_IWDG_BASE 0x40003000u
#define STM32_USART2_BASE 0x40004400u
#define STM32_USART3_BASE 0x40004800u
#define STM32_PWR_BASE 0x40007000u
#define STM32_TIM1_BASE 0x40010000u
#define STM32_TIM8_BASE 0x40010400u
#define STM32_USART1_BASE 0x40011000u
#define STM32_USART6_BASE 0x40011400u
#define STM32_TIM9_BASE 0x40014000u
#define STM32_TIM10_BASE 0x40014400u
#define STM32_TIM11_BASE 0x40014800u
#define STM32_GPIOA_BASE 0x40020000u /**< GPIOx at GPIOA + 0x400·x, A..I */
#define STM32_GPIO_STRIDE 0x400u
#define STM32_RCC_BASE 0x40023800u
#define STM32_FLASH_IF_BASE 0x40023C00u /**< the flash interface registers */
#define STM32_DBGMCU_BASE 0xE0042000u

/* ---- RCC: reset and clock control (RM0090 §7.3) ------------------------------------ */

typedef struct {
    volatile uint32_t CR;         /* 0x00 */
    volatile uint32_t PLLCFGR;    /* 0x04 */
    volatile uint32_t CFGR;       /* 0x08 */
    volatile uint32_t CIR;        /* 0x0C */
    volatile uint32_t AHB1RSTR;   /* 0x10 */
    volatile uint32_t AHB2RSTR;   /* 0x14 */
    volatile uint32_t AHB3RSTR;   /* 0x18 */
    uint32_t reserved0;           /* 0x1C */
    volatile uint32_t APB1RSTR;   /* 0x20 */
    volatile uint32_t APB2RSTR;   /* 0x24 */
    uint32_t reserved1[2];        /* 0x28 */
    volatile uint32_t AHB1ENR;    /* 0x30 */
    volatile uint32_t AHB2ENR;    /* 0x34 */
    volatile uint32_t AHB3ENR;    /* 0x38 */
    uint32_t reserved2;           /* 0x3C */
    volatile uint32_t APB1ENR;    /* 0x40 */
    volatile uint32_t APB2ENR;    /* 0x44 */
    uint32_t reserved3[2];        /* 0x48 */
    volatile uint32_t AHB1LPENR;  /* 0x50 */
    volatile uint32_t AHB2LPENR;  /* 0x54 */
    volatile uint32_t AHB3LPENR;  /* 0x58 */
    uint32_t reserved4;           /* 0x5C */
    volatile uint32_t APB1LPENR;  /* 0x60 */
    volatile uint32_t APB2LPENR;  /* 0x64 */
    uint32_t reserved5[2];        /* 0x68 */
    volatile uint32_t BDCR;       /* 0x70 */
    volatile uint32_t CSR;        /* 0x74 */
    uint32_t reserved6[2];        /* 0x78 */
    volatile uint32_t SSCGR;      /* 0x80 */
    volatile uint32_t PLLI2SCFGR; /* 0x84 */
} stm32_rcc_t;
_Static_assert(offsetof(stm32_rcc_t, PLLCFGR) == 0x04, "RCC_PLLCFGR");
_Static_assert(offsetof(stm32_rcc_t, APB1RSTR) == 0x20, "RCC_APB1RSTR");
_Static_assert(offsetof(stm32_rcc_t, AHB1ENR) == 0x30, "RCC_AHB1ENR");
_Static_assert(offsetof(stm32_rcc_t, APB1ENR) == 0x40, "RCC_APB1ENR");
_Static_assert(offsetof(stm32_rcc_t, APB2ENR) == 0x44, "RCC_APB2ENR");
_Static_assert(offsetof(stm32_rcc_t, AHB1LPENR) == 0x50, "RCC_AHB1LPENR");
_Static_assert(offsetof(stm32_rcc_t, BDCR) == 0x70, "RCC_BDCR");
_Static_assert(offsetof(stm32_rcc_t, CSR) == 0x74, "RCC_CSR");
_Static_assert(offsetof(stm32_rcc_t, PLLI2SCFGR) == 0x84, "RCC_PLLI2SCFGR");
#define STM32_RCC ((stm32_rcc_t *)STM32_RCC_BASE)

#define STM32_RCC_CR_HSION (1u << 0)
#define STM32_RCC_CR_HSIRDY (1u << 1)
#define STM32_RCC_CR_HSEON (1u << 16)
#define STM32_RCC_CR_HSERDY (1u << 17)
#define STM32_RCC_CR_HSEBYP (1u << 18)
#define STM32_RCC_CR_PLLON (1u << 24)
#define STM32_RCC_CR_PLLRDY (1u << 25)

#define STM32_RCC_PLLCFGR_M(m) ((uint32_t)(m) << 0)              /* 2..63 */
#define STM32_RCC_PLLCFGR_N(n) ((uint32_t)(n) << 6)              /* 50..432 */
#define STM32_RCC_PLLCFGR_P(p) ((uint32_t)((p) / 2u - 1u) << 16) /* 2, 4, 6, 8 */
#define STM32_RCC_PLLCFGR_SRC_HSE (1u << 22)
#define STM32_RCC_PLLCFGR_Q(q) ((uint32_t)(q) << 24) /* 2..15 */
/** Reserved bits (31:28, 23, 21:18, 15) keep their reset value; bit 29 resets to 1. */
#define STM32_RCC_PLLCFGR_RESERVED 0xF0BC8000u

#define STM32_RCC_CFGR_SW_MASK (3u << 0)
#define STM32_RCC_CFGR_SW_HSI (0u << 0)
#define STM32_RCC_CFGR_SW_HSE (1u << 0)
#define STM32_RCC_CFGR_SW_PLL (2u << 0)
#define STM32_RCC_CFGR_SWS_MASK (3u << 2)
#define STM32_RCC_CFGR_SWS_HSI (0u << 2)
#define STM32_RCC_CFGR_SWS_PLL (2u << 2)
#define STM32_RCC_CFGR_HPRE_DIV1 (0u << 4)
/** APB prescaler field of a divider 1, 2, 4, 8 or 16: 0, then 4 + log2(div) - 1. */
#define STM32_RCC_PPRE(div)                                                                        \
    ((div) == 1u ? 0u : (div) == 2u ? 4u : (div) == 4u ? 5u : (div) == 8u ? 6u : 7u)
#define STM32_RCC_CFGR_PPRE1(div) (STM32_RCC_PPRE(div) << 10)
#define STM32_RCC_CFGR_PPRE2(div) (STM32_RCC_PPRE(div) << 13)
#define STM32_RCC_CFGR_PRESCALERS_MASK ((0xFu << 4) | (7u << 10) | (7u << 13))

#define STM32_RCC_APB1ENR_PWREN (1u << 28)

#define STM32_RCC_CSR_LSION (1u << 0)
#define STM32_RCC_CSR_RMVF (1u << 24)
#define STM32_RCC_CSR_BORRSTF (1u << 25)
#define STM32_RCC_CSR_PINRSTF (1u << 26)
#define STM32_RCC_CSR_PORRSTF (1u << 27)
#define STM32_RCC_CSR_SFTRSTF (1u << 28)
#define STM32_RCC_CSR_IWDGRSTF (1u << 29)
#define STM32_RCC_CSR_WWDGRSTF (1u << 30)
#define STM32_RCC_CSR_LPWRRSTF (1u << 31)

/* ---- PWR (RM0090 §5.4) -------------------------------------------------------------- */

typedef struct {
    volatile uint32_t CR;  /* 0x00 */
    volatile uint32_t CSR; /* 0x04 */
} stm32_pwr_t;
#define STM32_PWR ((stm32_pwr_t *)STM32_PWR_BASE)
#define STM32_PWR_CR_VOS_F405_SCALE1 (1u << 14) /**< F405/407: scale 1, needed above 144 MHz */
#define STM32_PWR_CR_VOS_F411_SCALE1 (3u << 14) /**< F401/411: scale 1, needed above 84 MHz */

/* ---- flash interface (RM0090 §3.9) --------------------------------------------------- */

typedef struct {
    volatile uint32_t ACR;     /* 0x00 */
    volatile uint32_t KEYR;    /* 0x04 */
    volatile uint32_t OPTKEYR; /* 0x08 */
    volatile uint32_t SR;      /* 0x0C */
    volatile uint32_t CR;      /* 0x10 */
    volatile uint32_t OPTCR;   /* 0x14 */
} stm32_flash_t;
_Static_assert(offsetof(stm32_flash_t, SR) == 0x0C, "FLASH_SR");
_Static_assert(offsetof(stm32_flash_t, CR) == 0x10, "FLASH_CR");
#define STM32_FLASH ((stm32_flash_t *)STM32_FLASH_IF_BASE)

#define STM32_FLASH_ACR_LATENCY(ws) ((uint32_t)(ws) << 0)
#define STM32_FLASH_ACR_LATENCY_MASK (7u << 0)
#define STM32_FLASH_ACR_PRFTEN (1u << 8)
#define STM32_FLASH_ACR_ICEN (1u << 9)
#define STM32_FLASH_ACR_DCEN (1u << 10)
#define STM32_FLASH_ACR_ICRST (1u << 11)
#define STM32_FLASH_ACR_DCRST (1u << 12)

#define STM32_FLASH_KEY1 0x45670123u
#define STM32_FLASH_KEY2 0xCDEF89ABu

#define STM32_FLASH_SR_EOP (1u << 0)
#define STM32_FLASH_SR_OPERR (1u << 1)
#define STM32_FLASH_SR_WRPERR (1u << 4)
#define STM32_FLASH_SR_PGAERR (1u << 5)
#define STM32_FLASH_SR_PGPERR (1u << 6)
#define STM32_FLASH_SR_PGSERR (1u << 7)
#define STM32_FLASH_SR_BSY (1u << 16)
#define STM32_FLASH_SR_ERRORS                                                                      \
    (STM32_FLASH_SR_OPERR | STM32_FLASH_SR_WRPERR | STM32_FLASH_SR_PGAERR |                        \
     STM32_FLASH_SR_PGPERR | STM32_FLASH_SR_PGSERR)

#define STM32_FLASH_CR_PG (1u << 0)
#define STM32_FLASH_CR_SER (1u << 1)
#define STM32_FLASH_CR_SNB(n) ((uint32_t)(n) << 3) /* sector 0..11 */
#define STM32_FLASH_CR_PSIZE_X8 (0u << 8)
#define STM32_FLASH_CR_PSIZE_X32 (2u << 8)
#define STM32_FLASH_CR_STRT (1u << 16)
#define STM32_FLASH_CR_LOCK (1u << 31)

/* ---- GPIO (RM0090 §8.4) -------------------------------------------------------------- */

typedef struct {
    volatile uint32_t MODER;   /* 0x00 */
    volatile uint32_t OTYPER;  /* 0x04 */
    volatile uint32_t OSPEEDR; /* 0x08 */
    volatile uint32_t PUPDR;   /* 0x0C */
    volatile uint32_t IDR;     /* 0x10 */
    volatile uint32_t ODR;     /* 0x14 */
    volatile uint32_t BSRR;    /* 0x18 */
    volatile uint32_t LCKR;    /* 0x1C */
    volatile uint32_t AFR[2];  /* 0x20, 0x24 */
} stm32_gpio_t;
_Static_assert(offsetof(stm32_gpio_t, BSRR) == 0x18, "GPIO_BSRR");
_Static_assert(offsetof(stm32_gpio_t, AFR) == 0x20, "GPIO_AFRL");
/** GPIO port 0 = A, 1 = B, ... */
#define STM32_GPIO(port) ((stm32_gpio_t *)(STM32_GPIOA_BASE + STM32_GPIO_STRIDE * (uint32_t)(port)))

/* ---- timers: TIM1..TIM14 share one layout (RM0090 §17.4, §18.4, §19.4) ---------------- */

typedef struct {
    volatile uint32_t CR1;    /* 0x00 */
    volatile uint32_t CR2;    /* 0x04 */
    volatile uint32_t SMCR;   /* 0x08 */
    volatile uint32_t DIER;   /* 0x0C */
    volatile uint32_t SR;     /* 0x10 */
    volatile uint32_t EGR;    /* 0x14 */
    volatile uint32_t CCMR1;  /* 0x18 */
    volatile uint32_t CCMR2;  /* 0x1C */
    volatile uint32_t CCER;   /* 0x20 */
    volatile uint32_t CNT;    /* 0x24 */
    volatile uint32_t PSC;    /* 0x28 */
    volatile uint32_t ARR;    /* 0x2C */
    volatile uint32_t RCR;    /* 0x30, TIM1/TIM8 only */
    volatile uint32_t CCR[4]; /* 0x34..0x40: CCR1..CCR4 */
    volatile uint32_t BDTR;   /* 0x44, TIM1/TIM8 only */
    volatile uint32_t DCR;    /* 0x48 */
    volatile uint32_t DMAR;   /* 0x4C */
    volatile uint32_t OR;     /* 0x50 */
} stm32_tim_t;
_Static_assert(offsetof(stm32_tim_t, CCMR1) == 0x18, "TIM_CCMR1");
_Static_assert(offsetof(stm32_tim_t, CCER) == 0x20, "TIM_CCER");
_Static_assert(offsetof(stm32_tim_t, CNT) == 0x24, "TIM_CNT");
_Static_assert(offsetof(stm32_tim_t, ARR) == 0x2C, "TIM_ARR");
_Static_assert(offsetof(stm32_tim_t, CCR) == 0x34, "TIM_CCR1");
_Static_assert(offsetof(stm32_tim_t, BDTR) == 0x44, "TIM_BDTR");
_Static_assert(offsetof(stm32_tim_t, OR) == 0x50, "TIM_OR");
#define STM32_TIM(base) ((stm32_tim_t *)(base))

#define STM32_TIM_CR1_CEN (1u << 0)
#define STM32_TIM_CR1_URS (1u << 2)
#define STM32_TIM_CR1_OPM (1u << 3) /* not on TIM10/11/13/14 */
#define STM32_TIM_CR1_ARPE (1u << 7)

#define STM32_TIM_SMCR_SMS_ENCODER3 (3u << 0) /* count on TI1 and TI2 edges */
#define STM32_TIM_SMCR_SMS_RESET (4u << 0)    /* trigger input resets the counter */
#define STM32_TIM_SMCR_TS_TI1FP1 (5u << 4)
#define STM32_TIM_SMCR_TS_TI2FP2 (6u << 4)

#define STM32_TIM_DIER_CC2IE (1u << 2)
#define STM32_TIM_DIER_CCIE(ch) (1u << (ch)) /* channel 1..4 */

#define STM32_TIM_SR_UIF (1u << 0)
#define STM32_TIM_SR_CC1IF (1u << 1)
#define STM32_TIM_SR_CC2IF (1u << 2)
#define STM32_TIM_SR_CC1OF (1u << 9)
#define STM32_TIM_SR_CC2OF (1u << 10)
#define STM32_TIM_SR_CCIF(ch) (1u << (ch))        /* channel 1..4 */
#define STM32_TIM_SR_CCOF(ch) (1u << ((ch) + 8u)) /* channel 1..4 */

#define STM32_TIM_EGR_UG (1u << 0)

/* CCMRx: each 16-bit half configures one channel (odd channels low, even high). */
#define STM32_TIM_CCMR_CCS_OUT 0u      /* CCxS = 00: output */
#define STM32_TIM_CCMR_CCS_TI_SAME 1u  /* CCxS = 01: ICx on its own TIx */
#define STM32_TIM_CCMR_CCS_TI_OTHER 2u /* CCxS = 10: ICx on the neighbour's TI (IC2 on TI1) */
#define STM32_TIM_CCMR_OCPE (1u << 3)
#define STM32_TIM_CCMR_OCM_PWM1 (6u << 4)
#define STM32_TIM_CCMR_OCM_PWM2 (7u << 4)
#define STM32_TIM_CCMR_ICF(f) ((uint32_t)(f) << 4)
/** Place a channel's 8-bit CCMR setting: channel 1..4 into CCMR1/CCMR2's half. */
#define STM32_TIM_CCMR_CH(ch, bits) ((uint32_t)(bits) << (((ch)-1u) % 2u * 8u))

#define STM32_TIM_CCER_CCE(ch) (1u << (((ch)-1u) * 4u))
#define STM32_TIM_CCER_CCP(ch) (2u << (((ch)-1u) * 4u))
#define STM32_TIM_CCER_CCNP(ch) (8u << (((ch)-1u) * 4u))

#define STM32_TIM_BDTR_MOE (1u << 15)

/* ---- USART (RM0090 §30.6) ------------------------------------------------------------ */

typedef struct {
    volatile uint32_t SR;   /* 0x00 */
    volatile uint32_t DR;   /* 0x04 */
    volatile uint32_t BRR;  /* 0x08 */
    volatile uint32_t CR1;  /* 0x0C */
    volatile uint32_t CR2;  /* 0x10 */
    volatile uint32_t CR3;  /* 0x14 */
    volatile uint32_t GTPR; /* 0x18 */
} stm32_usart_t;
_Static_assert(offsetof(stm32_usart_t, CR1) == 0x0C, "USART_CR1");
#define STM32_USART(base) ((stm32_usart_t *)(base))

#define STM32_USART_SR_ORE (1u << 3)
#define STM32_USART_SR_RXNE (1u << 5)
#define STM32_USART_SR_TXE (1u << 7)
#define STM32_USART_CR1_RE (1u << 2)
#define STM32_USART_CR1_TE (1u << 3)
#define STM32_USART_CR1_RXNEIE (1u << 5)
#define STM32_USART_CR1_TXEIE (1u << 7)
#define STM32_USART_CR1_UE (1u << 13)

/* ---- IWDG (RM0090 §21.4) ------------------------------------------------------------- */

typedef struct {
    volatile uint32_t KR;  /* 0x00 */
    volatile uint32_t PR;  /* 0x04 */
    volatile uint32_t RLR; /* 0x08 */
    volatile uint32_t SR;  /* 0x0C */
} stm32_iwdg_t;
#define STM32_IWDG ((stm32_iwdg_t *)STM32_IWDG_BASE)
#define STM32_IWDG_KR_RELOAD 0xAAAAu
#define STM32_IWDG_KR_UNLOCK 0x5555u
#define STM32_IWDG_KR_START 0xCCCCu
#define STM32_IWDG_SR_PVU (1u << 0)
#define STM32_IWDG_SR_RVU (1u << 1)
#define STM32_IWDG_RLR_MAX 0xFFFu

/* ---- DBGMCU (RM0090 §38.16) ---------------------------------------------------------- */

typedef struct {
    volatile uint32_t IDCODE;  /* 0x00 */
    volatile uint32_t CR;      /* 0x04 */
    volatile uint32_t APB1_FZ; /* 0x08 */
    volatile uint32_t APB2_FZ; /* 0x0C */
} stm32_dbgmcu_t;
#define STM32_DBGMCU ((stm32_dbgmcu_t *)STM32_DBGMCU_BASE)
#define STM32_DBGMCU_APB1_FZ_IWDG_STOP (1u << 12)

#endif /* STM32F4_REGS_H */
