/* SPDX-License-Identifier: MIT */
/* Start-up of a Cortex-M image: vector table with weak default handlers, RAM init, faults. */
#include <stddef.h>
#include <string.h>

#include "cm_chip.h"
#include "cm_startup.h"
#include "cortex_m.h"
#include "text.h"

/* From the linker script (sections.ld). */
extern uint32_t _sidata[]; /* .data's image in flash */
extern uint32_t _sdata[];
extern uint32_t _edata[];
extern uint32_t _sbss[];
extern uint32_t _ebss[];
extern uint32_t _estack[]; /* the top of the main stack */

int main(void);

/* A vector without a handler is a bug: report it as a fault. */
void cm_default_handler(void);

#define CM_WEAK_ALIAS_(name) void name(void) __attribute__((weak, alias("cm_default_handler")));
CM_EXCEPTIONS(CM_WEAK_ALIAS_)
#undef CM_WEAK_ALIAS_
#define CM_WEAK_IRQ_(name)                                                                         \
    void name##_IRQHandler(void) __attribute__((weak, alias("cm_default_handler")));
CM_CHIP_IRQS(CM_WEAK_IRQ_)
#undef CM_WEAK_IRQ_

typedef void (*cm_vector_t)(void);

/* The table the core reads at reset: initial stack pointer, then the handlers. */
#define CM_IRQ_ONE_(name) +1
#define CM_IRQ_VECTOR_(name) name##_IRQHandler,
__attribute__((section(".isr_vector"),
               used)) static const cm_vector_t vector_table[16 CM_CHIP_IRQS(CM_IRQ_ONE_)] = {
    (cm_vector_t)(uintptr_t)_estack,
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    MemManage_Handler,
    BusFault_Handler,
    UsageFault_Handler,
    0,
    0,
    0,
    0,
    SVC_Handler,
    DebugMon_Handler,
    0,
    PendSV_Handler,
    SysTick_Handler,
    CM_CHIP_IRQS(CM_IRQ_VECTOR_)};
#undef CM_IRQ_VECTOR_
#undef CM_IRQ_ONE_

void Reset_Handler(void)
{
    /* The loops are written out: nothing from the C library may run before RAM is set. */
    for (uint32_t *src = _sidata, *dst = _sdata; dst < _edata;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = _sbss; dst < _ebss;) {
        *dst++ = 0u;
    }
    /* A boot loader may have left VTOR elsewhere. The FPU stays off: the image is fixed
     * point and an FPU instruction would fault (UsageFault, NOCP) instead of passing. */
    CM_SCB->VTOR = (uint32_t)(uintptr_t)vector_table;
    CM_SCB->CCR |= CM_SCB_CCR_DIV_0_TRP;
    CM_SCB->SHCSR |= CM_SCB_SHCSR_FAULTS_EN;
    cm_dsb();
    cm_isb();
    (void)main();
    cm_panic("main returned");
}

/* ---- the C library's two copies -------------------------------------------------------- */

/* Ours instead of newlib-nano's, which are unrolled for speed (470 bytes of flash). Only
 * start-up and the background loop copy or clear memory (the tick never does: `make bench`
 * lists no such call on its path), where a byte at a time costs nothing that matters. This
 * file is built with -fno-tree-loop-distribute-patterns, so the loops stay loops. */
void *memcpy(void *restrict dst, const void *restrict src, size_t n)
{
    unsigned char *d = dst;
    const unsigned char *s = src;
    while (n-- != 0u) {
        *d++ = *s++;
    }
    return dst;
}

void *memset(void *dst, int c, size_t n)
{
    unsigned char *d = dst;
    while (n-- != 0u) {
        *d++ = (unsigned char)c;
    }
    return dst;
}

/* ---- faults ------------------------------------------------------------------------- */

__attribute__((weak)) void cm_safe_outputs(void)
{
}

__attribute__((weak)) void cm_fault_hook(const cm_fault_t *f)
{
    (void)f;
}

static _Noreturn void fault_stop(cm_fault_t *f)
{
    cm_irq_disable();
    f->cfsr = CM_SCB->CFSR;
    f->hfsr = CM_SCB->HFSR;
    f->bfar = CM_SCB->BFAR;
    cm_safe_outputs();
    cm_fault_hook(f);
    /* The watchdog, when it runs, restarts the robot; the motors stay off until then. */
    for (;;) {
        cm_wfi();
    }
}

/* Called by the fault entry below with the stacked exception frame (r0-r3, r12, lr, pc, psr). */
_Noreturn void cm_fault_report(const uint32_t *frame);
_Noreturn void cm_fault_report(const uint32_t *frame)
{
    cm_fault_t f = {.exception = cm_ipsr() & 0x1FFu, .lr = frame[5], .pc = frame[6]};
    fault_stop(&f);
}

/* Every fault and unexpected interrupt: pass the frame of whichever stack was in use. */
__attribute__((naked)) void cm_default_handler(void)
{
    __asm__ volatile("tst lr, #4\n"
                     "ite eq\n"
                     "mrseq r0, msp\n"
                     "mrsne r0, psp\n"
                     "b cm_fault_report\n");
}

_Noreturn void cm_panic(const char *why)
{
    cm_fault_t f = {.exception = cm_ipsr() & 0x1FFu, .why = why};
    fault_stop(&f);
}

void text_fault(text_line_t *l, const struct cm_fault *f)
{
    text_str(l, "FAULT exception ");
    text_u32(l, f->exception);
    if (f->why != NULL) {
        text_str(l, ": ");
        text_str(l, f->why);
    }
    text_str(l, " pc 0x");
    text_hex(l, f->pc, 8u);
    text_str(l, " lr 0x");
    text_hex(l, f->lr, 8u);
    text_str(l, " cfsr 0x");
    text_hex(l, f->cfsr, 8u);
    text_str(l, " hfsr 0x");
    text_hex(l, f->hfsr, 8u);
    text_str(l, " bfar 0x");
    text_hex(l, f->bfar, 8u);
}
