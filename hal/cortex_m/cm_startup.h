/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Start-up and faults of every Cortex-M image (startup.c): the core's exception handlers,
 * what a fault leaves behind, and the two hooks a port gives the fault path.
 *
 * startup.c builds the vector table from the core's exceptions below and the chip's
 * interrupts, which the chip folder lists in its `cm_chip.h`, in vector order (position n
 * is IRQ n, exception 16 + n; X(name) stands for name_IRQHandler):
 *
 *     #define CM_CHIP_IRQS(X) X(WWDG) X(PVD) X(TAMP_STAMP) ...
 *
 * Every handler is weak: a driver defines the one it needs (void USART1_IRQHandler(void),
 * void SysTick_Handler(void)) and every other vector lands in one default handler, which
 * treats it as a fault: outputs safe (cm_safe_outputs()), the port's report
 * (cm_fault_hook()), then a wait for the watchdog.
 */
#ifndef CM_STARTUP_H
#define CM_STARTUP_H

#include <stdint.h>

/* System exceptions 2..15 that have a handler (the others are reserved). */
#define CM_EXCEPTIONS(X)                                                                           \
    X(NMI_Handler)                                                                                 \
    X(HardFault_Handler)                                                                           \
    X(MemManage_Handler)                                                                           \
    X(BusFault_Handler)                                                                            \
    X(UsageFault_Handler)                                                                          \
    X(SVC_Handler)                                                                                 \
    X(DebugMon_Handler)                                                                            \
    X(PendSV_Handler)                                                                              \
    X(SysTick_Handler)

void Reset_Handler(void);
#define CM_HANDLER_PROTO_(name) void name(void);
CM_EXCEPTIONS(CM_HANDLER_PROTO_)
#undef CM_HANDLER_PROTO_

/** What a fault left behind, for a report. */
typedef struct cm_fault {
    uint32_t exception; /**< IPSR: 3 HardFault, 4 MemManage, 5 BusFault, 6 UsageFault, 16+n IRQ n */
    uint32_t pc;        /**< stacked PC: the faulting instruction (0 for a panic) */
    uint32_t lr;        /**< stacked LR */
    uint32_t cfsr;      /**< SCB->CFSR */
    uint32_t hfsr;      /**< SCB->HFSR */
    uint32_t bfar;      /**< SCB->BFAR */
    const char *why;    /**< a panic's reason, or NULL */
} cm_fault_t;

/**
 * Put the outputs in a safe state (motors off), first thing after a fault, with interrupts
 * off. Weak: an image without motor drivers (the self-test) links without one.
 */
void cm_safe_outputs(void);

/**
 * Called once the outputs are safe, with interrupts off; weak. The robot image prints a
 * report on its UART, the self-test exits QEMU. When it returns the MCU waits for the
 * watchdog.
 */
void cm_fault_hook(const cm_fault_t *f);

/** A broken invariant: safe outputs, report, wait for the watchdog. */
_Noreturn void cm_panic(const char *why);

#endif /* CM_STARTUP_H */
