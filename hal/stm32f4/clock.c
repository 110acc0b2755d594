/* SPDX-License-Identifier: MIT */
/* The clock tree: HSE + PLL to the board's speed, a timeout on every ready bit, HSI as the
 * fallback. */
#include "board.h"
#include "cortex_m.h"
#include "stm32f4_port.h"

/* The board table gives the crystal, the PLL's input, the speed and the bus dividers; the
 * PLL's factors follow, and every limit of the reference manuals is checked here. */
#define HSI_HZ 16000000u
#define PLL_IN_HZ BOARD_PLL_IN_HZ /* VCO input: 2 MHz keeps the jitter lowest (RM0090 §6.3.2) */
#define PLL_P 2u
#define PLL_N (BOARD_SYSCLK_HZ / PLL_IN_HZ * PLL_P)
#define PLL_VCO_HZ (PLL_IN_HZ * PLL_N)
#define PLL_Q (PLL_VCO_HZ / 48000000u) /* 48 MHz for USB/SDIO, should they be used */
#define SYSCLK_PLL_HZ (PLL_VCO_HZ / PLL_P)
#define PCLK1_HZ (SYSCLK_PLL_HZ / BOARD_APB1_DIV)
#define PCLK2_HZ (SYSCLK_PLL_HZ / BOARD_APB2_DIV)

#if PLL_IN_HZ < 1000000u || PLL_IN_HZ > 2000000u || BOARD_HSE_HZ % PLL_IN_HZ != 0u ||              \
    HSI_HZ % PLL_IN_HZ != 0u || BOARD_HSE_HZ / PLL_IN_HZ > 63u
#error "BOARD_PLL_IN_HZ must be 1 to 2 MHz and divide both the crystal and the 16 MHz HSI"
#endif
#if SYSCLK_PLL_HZ != BOARD_SYSCLK_HZ || PLL_N < 50u || PLL_N > 432u || PLL_VCO_HZ < 100000000u ||  \
    PLL_VCO_HZ > 432000000u || PLL_Q < 2u || PLL_Q > 15u
#error "BOARD_SYSCLK_HZ is not reachable with this PLL input (VCO 100..432 MHz, N 50..432)"
#endif
#if BOARD_SYSCLK_HZ > BOARD_SYSCLK_MAX_HZ || PCLK1_HZ > BOARD_APB1_MAX_HZ ||                       \
    PCLK2_HZ > BOARD_APB2_MAX_HZ
#error "a clock of the board table exceeds its chip's maximum"
#endif

/* How long to wait for a ready bit, in loops: about 60 ms at the 16 MHz of HSI, where a
 * crystal needs about 2 ms and the PLL 0.1 ms. A loop, because no timer runs yet; QEMU
 * never sets the ready bits, so it always takes the fallbacks after these loops. */
#define CLOCK_WAIT_LOOPS 200000u

stm32_clocks_t stm32_clocks;
static uint32_t reset_flags;

static bool wait_bits(volatile uint32_t *reg, uint32_t mask, uint32_t value)
{
    for (uint32_t n = 0; n < CLOCK_WAIT_LOOPS; n++) {
        if ((*reg & mask) == value) {
            return true;
        }
    }
    return false;
}

static void run_on_hsi(void)
{
    stm32_rcc_t *rcc = STM32_RCC;
    rcc->CFGR = (rcc->CFGR & ~(STM32_RCC_CFGR_SW_MASK | STM32_RCC_CFGR_PRESCALERS_MASK)) |
                STM32_RCC_CFGR_SW_HSI;
    (void)wait_bits(&rcc->CFGR, STM32_RCC_CFGR_SWS_MASK, STM32_RCC_CFGR_SWS_HSI);
    rcc->CR &= ~STM32_RCC_CR_PLLON;
    stm32_clocks.source = STM32_CLOCK_HSI;
    stm32_clocks.sysclk_hz = HSI_HZ;
    stm32_clocks.pclk1_hz = HSI_HZ;
    stm32_clocks.pclk2_hz = HSI_HZ;
    stm32_clocks.tim_apb1_hz = HSI_HZ;
    stm32_clocks.tim_apb2_hz = HSI_HZ;
}

void stm32_clock_init(void)
{
    stm32_rcc_t *rcc = STM32_RCC;
    reset_flags = rcc->CSR;
    rcc->CSR |= STM32_RCC_CSR_RMVF;
    stm32_clocks = (stm32_clocks_t){0};

    /* A known start, whatever a boot loader or debugger left: HSI selected, PLL off. */
    rcc->CR |= STM32_RCC_CR_HSION;
    (void)wait_bits(&rcc->CR, STM32_RCC_CR_HSIRDY, STM32_RCC_CR_HSIRDY);
    run_on_hsi();
    (void)wait_bits(&rcc->CR, STM32_RCC_CR_PLLRDY, 0u);

    /* The regulator's scale for this speed (F405: the reset value, set for certainty;
     * F411: its reset value is too low for more than 84 MHz). The PLL is still off, as
     * a change of scale requires. */
    rcc->APB1ENR |= STM32_RCC_APB1ENR_PWREN;
    (void)rcc->APB1ENR;
    STM32_PWR->CR |= BOARD_PWR_VOS;

    uint32_t pll;
    rcc->CR |= STM32_RCC_CR_HSEON;
    if (wait_bits(&rcc->CR, STM32_RCC_CR_HSERDY, STM32_RCC_CR_HSERDY)) {
        pll = STM32_RCC_PLLCFGR_M(BOARD_HSE_HZ / PLL_IN_HZ) | STM32_RCC_PLLCFGR_SRC_HSE;
        stm32_clocks.source = STM32_CLOCK_HSE_PLL;
    } else {
        rcc->CR &= ~STM32_RCC_CR_HSEON;
        stm32_clocks.hse_timeout = true;
        pll = STM32_RCC_PLLCFGR_M(HSI_HZ / PLL_IN_HZ);
        stm32_clocks.source = STM32_CLOCK_HSI_PLL;
    }
    rcc->PLLCFGR = (rcc->PLLCFGR & STM32_RCC_PLLCFGR_RESERVED) | pll | STM32_RCC_PLLCFGR_N(PLL_N) |
                   STM32_RCC_PLLCFGR_P(PLL_P) | STM32_RCC_PLLCFGR_Q(PLL_Q);
    rcc->CR |= STM32_RCC_CR_PLLON;
    if (!wait_bits(&rcc->CR, STM32_RCC_CR_PLLRDY, STM32_RCC_CR_PLLRDY)) {
        stm32_clocks.pll_timeout = true;
        rcc->CR &= ~STM32_RCC_CR_HSEON;
        run_on_hsi();
        return;
    }

    /* Wait states first, and only go fast once the flash has taken them. */
    stm32_flash_t *flash = STM32_FLASH;
    flash->ACR = STM32_FLASH_ACR_LATENCY(BOARD_FLASH_WAIT_STATES);
    flash->ACR |= STM32_FLASH_ACR_ICRST | STM32_FLASH_ACR_DCRST;
    flash->ACR = STM32_FLASH_ACR_LATENCY(BOARD_FLASH_WAIT_STATES) | STM32_FLASH_ACR_PRFTEN |
                 STM32_FLASH_ACR_ICEN | STM32_FLASH_ACR_DCEN;
    if ((flash->ACR & STM32_FLASH_ACR_LATENCY_MASK) != BOARD_FLASH_WAIT_STATES) {
        stm32_clocks.flash_refused = true;
        rcc->CR &= ~STM32_RCC_CR_HSEON;
        run_on_hsi();
        return;
    }

    /* AHB at the full speed, the two APBs as the board divides them. */
    rcc->CFGR = (rcc->CFGR & ~STM32_RCC_CFGR_PRESCALERS_MASK) | STM32_RCC_CFGR_HPRE_DIV1 |
                STM32_RCC_CFGR_PPRE1(BOARD_APB1_DIV) | STM32_RCC_CFGR_PPRE2(BOARD_APB2_DIV);
    rcc->CFGR = (rcc->CFGR & ~STM32_RCC_CFGR_SW_MASK) | STM32_RCC_CFGR_SW_PLL;
    if (!wait_bits(&rcc->CFGR, STM32_RCC_CFGR_SWS_MASK, STM32_RCC_CFGR_SWS_PLL)) {
        stm32_clocks.pll_timeout = true;
        rcc->CR &= ~STM32_RCC_CR_HSEON;
        run_on_hsi();
        return;
    }
    stm32_clocks.sysclk_hz = SYSCLK_PLL_HZ;
    stm32_clocks.pclk1_hz = PCLK1_HZ;
    stm32_clocks.pclk2_hz = PCLK2_HZ;
    /* A timer on a divided APB runs at twice its bus clock (RM0090 §6.2). */
    stm32_clocks.tim_apb1_hz = BOARD_APB1_DIV == 1u ? PCLK1_HZ : 2u * PCLK1_HZ;
    stm32_clocks.tim_apb2_hz = BOARD_APB2_DIV == 1u ? PCLK2_HZ : 2u * PCLK2_HZ;
}

const char *stm32_clock_name(void)
{
    static const char *const names[] = {"HSE+PLL", "HSI+PLL", "HSI"};
    return names[stm32_clocks.source];
}

/* RCC enable bits by base address (RM0090 §7.3.10-14). */
typedef struct {
    uint32_t base;
    uint8_t bus; /* 0 AHB1, 1 APB1, 2 APB2 */
    uint8_t bit;
} periph_clock_t;

static const periph_clock_t periph_clocks[] = {
    {STM32_TIM2_BASE, 1, 0},    {STM32_TIM3_BASE, 1, 1},    {STM32_TIM4_BASE, 1, 2},
    {STM32_TIM5_BASE, 1, 3},    {STM32_TIM6_BASE, 1, 4},    {STM32_TIM7_BASE, 1, 5},
    {STM32_TIM12_BASE, 1, 6},   {STM32_TIM13_BASE, 1, 7},   {STM32_TIM14_BASE, 1, 8},
    {STM32_USART2_BASE, 1, 17}, {STM32_USART3_BASE, 1, 18}, {STM32_PWR_BASE, 1, 28},
    {STM32_TIM1_BASE, 2, 0},    {STM32_TIM8_BASE, 2, 1},    {STM32_USART1_BASE, 2, 4},
    {STM32_USART6_BASE, 2, 5},  {STM32_TIM9_BASE, 2, 16},   {STM32_TIM10_BASE, 2, 17},
    {STM32_TIM11_BASE, 2, 18},
};

int stm32_periph_enable(uint32_t base)
{
    stm32_rcc_t *rcc = STM32_RCC;
    volatile uint32_t *reg = NULL;
    uint32_t bit = 0u;
    if (base >= STM32_GPIOA_BASE && base < STM32_GPIOA_BASE + 9u * STM32_GPIO_STRIDE) {
        reg = &rcc->AHB1ENR;
        bit = (base - STM32_GPIOA_BASE) / STM32_GPIO_STRIDE;
    }
    for (size_t i = 0; reg == NULL && i < sizeof periph_clocks / sizeof periph_clocks[0]; i++) {
        if (periph_clocks[i].base == base) {
            reg = periph_clocks[i].bus == 1u ? &rcc->APB1ENR : &rcc->APB2ENR;
            bit = periph_clocks[i].bit;
        }
    }
    if (reg == NULL) {
        return -1;
    }
    *reg |= 1u << bit;
    (void)*reg; /* the clock needs two cycles before the peripheral may be touched */
    return 0;
}

uint32_t stm32_timer_clock_hz(uint32_t tim_base)
{
    return tim_base >= STM32_TIM1_BASE ? stm32_clocks.tim_apb2_hz : stm32_clocks.tim_apb1_hz;
}

uint32_t stm32_reset_flags(void)
{
    return reset_flags;
}

const char *stm32_reset_name(uint32_t flags)
{
    if (flags & STM32_RCC_CSR_IWDGRSTF) {
        return "watchdog";
    }
    if (flags & STM32_RCC_CSR_WWDGRSTF) {
        return "window watchdog";
    }
    if (flags & STM32_RCC_CSR_SFTRSTF) {
        return "software";
    }
    if (flags & STM32_RCC_CSR_LPWRRSTF) {
        return "low-power";
    }
    if (flags & STM32_RCC_CSR_PORRSTF) {
        return "power-on";
    }
    if (flags & STM32_RCC_CSR_BORRSTF) {
        return "brown-out";
    }
    if (flags & STM32_RCC_CSR_PINRSTF) {
        return "reset pin";
    }
    return "unknown";
}
