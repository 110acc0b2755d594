/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The ARMv7-M core (Cortex-M3, M4, M7) as every port of this project uses it: SysTick, NVIC
 * and SCB registers (ARMv7-M Architecture Reference Manual, B3), the few special
 * instructions, and an atomic block. Nothing here depends on the chip around the core.
 *
 * A chip implements only the top bits of a priority byte (the STM32F4 4 of them, the nRF52
 * 3) and ignores the others: with 4, a priority byte is 0x00 (highest) .. 0xF0.
 */
#ifndef CORTEX_M_H
#define CORTEX_M_H

#include <stddef.h>
#include <stdint.h>

/* ---- SysTick (B3.3) ------------------------------------------------------------------ */

typedef struct {
    volatile uint32_t CTRL;  /* 0xE000E010 */
    volatile uint32_t LOAD;  /* 0xE000E014 */
    volatile uint32_t VAL;   /* 0xE000E018 */
    volatile uint32_t CALIB; /* 0xE000E01C */
} cm_systick_t;
#define CM_SYSTICK ((cm_systick_t *)0xE000E010u)
#define CM_SYSTICK_CTRL_ENABLE (1u << 0)
#define CM_SYSTICK_CTRL_TICKINT (1u << 1)
#define CM_SYSTICK_CTRL_CLKSOURCE_CPU (1u << 2)
#define CM_SYSTICK_LOAD_MAX 0xFFFFFFu

/* ---- NVIC (B3.4) ------------------------------------------------------------------- */

typedef struct {
    volatile uint32_t ISER[8]; /* 0xE000E100 */
    uint32_t reserved0[24];
    volatile uint32_t ICER[8]; /* 0xE000E180 */
    uint32_t reserved1[24];
    volatile uint32_t ISPR[8]; /* 0xE000E200 */
    uint32_t reserved2[24];
    volatile uint32_t ICPR[8]; /* 0xE000E280 */
    uint32_t reserved3[24];
    volatile uint32_t IABR[8]; /* 0xE000E300 */
    uint32_t reserved4[56];
    volatile uint8_t IPR[240]; /* 0xE000E400 */
} cm_nvic_t;
_Static_assert(offsetof(cm_nvic_t, ICER) == 0x80, "NVIC_ICER");
_Static_assert(offsetof(cm_nvic_t, ICPR) == 0x180, "NVIC_ICPR");
_Static_assert(offsetof(cm_nvic_t, IPR) == 0x300, "NVIC_IPR");
#define CM_NVIC ((cm_nvic_t *)0xE000E100u)

/* ---- SCB (B3.2) -------------------------------------------------------------------- */

typedef struct {
    volatile uint32_t CPUID;   /* 0xE000ED00 */
    volatile uint32_t ICSR;    /* 0xE000ED04 */
    volatile uint32_t VTOR;    /* 0xE000ED08 */
    volatile uint32_t AIRCR;   /* 0xE000ED0C */
    volatile uint32_t SCR;     /* 0xE000ED10 */
    volatile uint32_t CCR;     /* 0xE000ED14 */
    volatile uint8_t SHPR[12]; /* 0xE000ED18: priorities of system handlers 4..15 */
    volatile uint32_t SHCSR;   /* 0xE000ED24 */
    volatile uint32_t CFSR;    /* 0xE000ED28 */
    volatile uint32_t HFSR;    /* 0xE000ED2C */
    volatile uint32_t DFSR;    /* 0xE000ED30 */
    volatile uint32_t MMFAR;   /* 0xE000ED34 */
    volatile uint32_t BFAR;    /* 0xE000ED38 */
} cm_scb_t;
_Static_assert(offsetof(cm_scb_t, SHPR) == 0x18, "SCB_SHPR1");
_Static_assert(offsetof(cm_scb_t, CFSR) == 0x28, "SCB_CFSR");
_Static_assert(offsetof(cm_scb_t, BFAR) == 0x38, "SCB_BFAR");
#define CM_SCB ((cm_scb_t *)0xE000ED00u)
#define CM_SCB_ICSR_PENDSTSET (1u << 26)
#define CM_SCB_ICSR_PENDSTCLR (1u << 25)
#define CM_SCB_AIRCR_VECTKEY (0x05FAu << 16)
#define CM_SCB_AIRCR_SYSRESETREQ (1u << 2)
#define CM_SCB_CCR_DIV_0_TRP (1u << 4)
#define CM_SCB_SHCSR_FAULTS_EN ((1u << 16) | (1u << 17) | (1u << 18)) /* Mem, Bus, Usage */
/** SHPR index of a system handler: exception number - 4 (SysTick is 15). */
#define CM_SHPR_SYSTICK 11u

/* ---- special instructions ----------------------------------------------------------- */

static inline uint32_t cm_primask(void)
{
    uint32_t v;
    __asm__ volatile("mrs %0, primask" : "=r"(v));
    return v;
}

static inline void cm_primask_set(uint32_t v)
{
    __asm__ volatile("msr primask, %0" : : "r"(v) : "memory");
}

static inline void cm_irq_disable(void)
{
    __asm__ volatile("cpsid i" : : : "memory");
}

/** The exception being handled: 0 in thread mode, 15 in SysTick, 16 + n in IRQ n. */
static inline uint32_t cm_ipsr(void)
{
    uint32_t v;
    __asm__ volatile("mrs %0, ipsr" : "=r"(v));
    return v;
}

static inline void cm_wfi(void)
{
    __asm__ volatile("wfi" : : : "memory");
}

static inline void cm_dsb(void)
{
    __asm__ volatile("dsb" : : : "memory");
}

static inline void cm_isb(void)
{
    __asm__ volatile("isb" : : : "memory");
}

/** Enable IRQ n at a priority byte (0x00 highest; the chip keeps only its top bits). */
static inline void cm_nvic_enable(uint32_t irq, uint8_t priority)
{
    CM_NVIC->IPR[irq] = priority;
    CM_NVIC->ICPR[irq / 32u] = 1u << (irq % 32u);
    CM_NVIC->ISER[irq / 32u] = 1u << (irq % 32u);
}

static inline void cm_nvic_disable(uint32_t irq)
{
    CM_NVIC->ICER[irq / 32u] = 1u << (irq % 32u);
    cm_dsb();
    cm_isb();
}

/* ---- atomic block -------------------------------------------------------------------- */

static inline uint32_t cm_atomic_begin(void)
{
    uint32_t saved = cm_primask();
    cm_irq_disable();
    return saved;
}

static inline void cm_atomic_end(const uint32_t *saved)
{
    cm_primask_set(*saved);
}

/**
 * Run the following statement or block with interrupts masked; the previous mask is
 * restored however the block is left (end, break, return, goto), so blocks nest:
 *
 *     CM_ATOMIC_BLOCK() {
 *         ... touch state shared with an interrupt ...
 *     }
 */
#define CM_ATOMIC_BLOCK()                                                                          \
    for (uint32_t cm_atomic_saved_ __attribute__((cleanup(cm_atomic_end))) = cm_atomic_begin(),    \
                                   cm_atomic_once_ = 1u;                                           \
         cm_atomic_once_ != 0u; cm_atomic_once_ = 0u)

#endif /* CORTEX_M_H */
