/* SPDX-License-Identifier: MIT */
/* Telemetry UART: interrupt-driven TX and RX rings; hal_uart_write() never blocks. */
#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

#define TX_SIZE 256u /* powers of two: the indices run freely and wrap */
#define RX_SIZE 64u
_Static_assert((TX_SIZE & (TX_SIZE - 1u)) == 0u && (RX_SIZE & (RX_SIZE - 1u)) == 0u,
               "ring sizes must be powers of two");

static uint8_t tx_buf[TX_SIZE];
static volatile uint32_t tx_head; /* written by producers, inside an atomic block */
static volatile uint32_t tx_tail; /* written by the consumer: the TXE interrupt or the pump */
static uint8_t rx_buf[RX_SIZE];
static volatile uint32_t rx_head; /* written by the RXNE interrupt */
static volatile uint32_t rx_tail; /* written by hal_uart_read() */
static volatile uint32_t rx_dropped;

#define UART STM32_USART(BOARD_UART)

void stm32_uart_init(void)
{
    (void)stm32_periph_enable(BOARD_UART);
    UART->CR1 = 0u;
    uint32_t clk = BOARD_UART >= STM32_USART1_BASE && BOARD_UART < STM32_TIM9_BASE
                       ? stm32_clocks.pclk2_hz
                       : stm32_clocks.pclk1_hz;
    /* Oversampling by 16: BRR is the divider in 1/16ths, which is clk / baud rounded. */
    UART->BRR = (clk + BOARD_UART_BAUD / 2u) / BOARD_UART_BAUD;
    UART->CR2 = 0u;
    UART->CR3 = 0u;
    UART->CR1 =
        STM32_USART_CR1_UE | STM32_USART_CR1_TE | STM32_USART_CR1_RE | STM32_USART_CR1_RXNEIE;
    cm_nvic_enable(BOARD_UART_IRQ, BOARD_PRIO_UART);
}

/* Send one queued byte if the transmitter has room; false when there is nothing to send. */
static bool tx_one(void)
{
    uint32_t tail = tx_tail;
    if (tail == tx_head) {
        return false;
    }
    if ((UART->SR & STM32_USART_SR_TXE) != 0u) {
        UART->DR = tx_buf[tail % TX_SIZE];
        tx_tail = tail + 1u;
    }
    return true;
}

void BOARD_UART_IRQHandler(void)
{
    uint32_t sr = UART->SR;
    if ((sr & (STM32_USART_SR_RXNE | STM32_USART_SR_ORE)) != 0u) {
        uint8_t byte = (uint8_t)UART->DR; /* reading DR after SR clears RXNE and ORE */
        uint32_t head = rx_head;
        if (head - rx_tail < RX_SIZE) {
            rx_buf[head % RX_SIZE] = byte;
            rx_head = head + 1u;
        } else {
            rx_dropped = rx_dropped + 1u;
        }
    }
    if ((UART->CR1 & STM32_USART_CR1_TXEIE) != 0u && !tx_one()) {
        UART->CR1 &= ~STM32_USART_CR1_TXEIE; /* ring empty: stop asking */
    }
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    size_t n = 0;
    /* The tick and the main loop both write: the producer side is one atomic block. */
    CM_ATOMIC_BLOCK()
    {
        uint32_t head = tx_head;
        size_t room = TX_SIZE - (head - tx_tail);
        n = len < room ? len : room;
        for (size_t i = 0; i < n; i++) {
            tx_buf[(head + i) % TX_SIZE] = data[i];
        }
        tx_head = head + (uint32_t)n;
        if (n != 0u) {
            UART->CR1 |= STM32_USART_CR1_TXEIE;
        }
    }
    return n;
}

size_t hal_uart_read(uint8_t *data, size_t len)
{
    size_t n = 0;
    uint32_t tail = rx_tail;
    while (n < len && tail != rx_head) {
        data[n++] = rx_buf[tail % RX_SIZE];
        tail++;
    }
    rx_tail = tail;
    return n;
}

void stm32_uart_pump(void)
{
    CM_ATOMIC_BLOCK()
    {
        while ((UART->SR & STM32_USART_SR_TXE) != 0u && tx_one()) {
        }
    }
}

void stm32_uart_write_blocking(const char *s)
{
    for (; *s != '\0'; s++) {
        for (uint32_t n = 0; n < 100000u && (UART->SR & STM32_USART_SR_TXE) == 0u; n++) {
        }
        UART->DR = (uint8_t)*s;
    }
}
