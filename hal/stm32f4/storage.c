/* SPDX-License-Identifier: MIT */
/* Map storage in two flash sectors: erase, program and read, from the background loop only. */
#include <string.h>

#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "slam/mapstore.h"
#include "stm32f4_port.h"

/* The board's grid is the one the core was built with (the build reads it from the table),
 * and a slot holds a whole record of it: else saves would be refused at run time. */
_Static_assert(BOARD_GRID_A == SLAM_GRID_A && BOARD_GRID_B == SLAM_GRID_B,
               "the board table's BOARD_GRID_A/B differ from the core's SLAM_GRID_A/B: "
               "link the image with the board's core (stm32f4_board_core)");
_Static_assert(sizeof(mapstore_header_t) + 2u * (uint64_t)SLAM_GRID_CELLS <= BOARD_STORAGE_BYTES,
               "a map record (header + OM + TM of BOARD_GRID_A x BOARD_GRID_B) does not fit "
               "BOARD_STORAGE_BYTES: make the board's grid smaller or its storage slots larger");

/*
 * Erasing or programming the flash stalls every read of it, so the CPU stops for as long
 * as the operation lasts when it runs from flash: up to 2 s for a 128 KiB sector erase
 * (RM0090 Table 45), 16 µs for a word. Ticks that fall in an erase come late and are
 * counted as overruns; stop the robot before saving a map. The watchdog is given
 * STM32_WATCHDOG_ERASE_MS for the erase and its normal timeout back afterwards.
 */

/* Polls of BSY after an operation: the stall makes the first poll return when the flash
 * is done; the bound only keeps a flash interface that never answers (QEMU) from hanging. */
#define FLASH_WAIT_LOOPS 1000000u

static const struct {
    uint32_t addr;
    uint8_t sector;
} slots[HAL_STORAGE_SLOTS] = {
    {BOARD_STORAGE_ADDR0, BOARD_STORAGE_SECTOR0},
    {BOARD_STORAGE_ADDR1, BOARD_STORAGE_SECTOR1},
};

static bool slot_open[HAL_STORAGE_SLOTS]; /* erased by hal_storage_begin(), not yet committed */

static void require_thread_mode(void)
{
    if (cm_ipsr() != 0u) {
        cm_panic("map storage used from an interrupt");
    }
}

static bool flash_idle(void)
{
    for (uint32_t n = 0; n < FLASH_WAIT_LOOPS; n++) {
        if ((STM32_FLASH->SR & STM32_FLASH_SR_BSY) == 0u) {
            return true;
        }
    }
    return false;
}

/* Wait for the operation under way; true when it ended without an error flag. */
static bool flash_done(void)
{
    return flash_idle() && (STM32_FLASH->SR & STM32_FLASH_SR_ERRORS) == 0u;
}

static bool flash_unlock(void)
{
    if ((STM32_FLASH->CR & STM32_FLASH_CR_LOCK) != 0u) {
        STM32_FLASH->KEYR = STM32_FLASH_KEY1;
        STM32_FLASH->KEYR = STM32_FLASH_KEY2;
    }
    /* A wrong key sequence keeps it locked until the next reset. */
    if ((STM32_FLASH->CR & STM32_FLASH_CR_LOCK) != 0u || !flash_idle()) {
        return false;
    }
    STM32_FLASH->SR = STM32_FLASH_SR_ERRORS | STM32_FLASH_SR_EOP; /* rc_w1: clear stale flags */
    return true;
}

static void flash_lock(void)
{
    STM32_FLASH->CR = STM32_FLASH_CR_LOCK;
}

/* The data cache may hold words from before the erase or program: flush it. */
static void flash_dcache_flush(void)
{
    uint32_t acr = STM32_FLASH->ACR;
    STM32_FLASH->ACR = acr & ~STM32_FLASH_ACR_DCEN;
    STM32_FLASH->ACR = (acr & ~STM32_FLASH_ACR_DCEN) | STM32_FLASH_ACR_DCRST;
    STM32_FLASH->ACR = acr;
}

static bool range_ok(uint8_t slot, uint32_t offset, size_t len)
{
    return slot < HAL_STORAGE_SLOTS && offset <= BOARD_STORAGE_BYTES &&
           len <= BOARD_STORAGE_BYTES - offset;
}

size_t hal_storage_size(void)
{
    return BOARD_STORAGE_BYTES;
}

int hal_storage_begin(uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS) {
        return HAL_EINVAL;
    }
    require_thread_mode();
    slot_open[slot] = false;
    if (!flash_unlock()) {
        flash_lock();
        return HAL_EIO;
    }
    stm32_watchdog_set_timeout(STM32_WATCHDOG_ERASE_MS);
    STM32_FLASH->CR =
        BOARD_FLASH_PSIZE | STM32_FLASH_CR_SER | STM32_FLASH_CR_SNB(slots[slot].sector);
    STM32_FLASH->CR |= STM32_FLASH_CR_STRT;
    bool done = flash_done();
    stm32_watchdog_set_timeout(STM32_WATCHDOG_MS);
    flash_lock();
    flash_dcache_flush();
    /* Trust only what reads back: an erased sector is all ones. */
    const volatile uint32_t *word = (const volatile uint32_t *)slots[slot].addr;
    for (uint32_t i = 0; done && i < BOARD_STORAGE_BYTES / 4u; i++) {
        done = word[i] == 0xFFFFFFFFu;
    }
    if (!done) {
        return HAL_EIO;
    }
    slot_open[slot] = true;
    return HAL_OK;
}

int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    if (!range_ok(slot, offset, len) || !slot_open[slot] || (data == NULL && len != 0u)) {
        return HAL_EINVAL;
    }
    require_thread_mode();
    if (len == 0u) {
        return HAL_OK;
    }
    if (!flash_unlock()) {
        flash_lock();
        return HAL_EIO;
    }
    const uint8_t *src = data;
    uint32_t addr = slots[slot].addr + offset;
    uint32_t end = addr + (uint32_t)len;
    bool ok = true;
    while (ok && addr < end) {
        if (addr % 4u == 0u && end - addr >= 4u) {
            /* Whole aligned words at the configured parallelism. */
            uint32_t w;
            memcpy(&w, src, 4u);
            STM32_FLASH->CR = BOARD_FLASH_PSIZE | STM32_FLASH_CR_PG;
            *(volatile uint32_t *)addr = w;
            addr += 4u;
            src += 4u;
        } else {
            /* The unaligned head and tail byte by byte, at x8 parallelism. */
            STM32_FLASH->CR = STM32_FLASH_CR_PSIZE_X8 | STM32_FLASH_CR_PG;
            *(volatile uint8_t *)addr = *src;
            addr += 1u;
            src += 1u;
        }
        cm_dsb();
        ok = flash_done();
    }
    flash_lock();
    flash_dcache_flush();
    /* Read back what was programmed, a byte at a time (the library's memcmp would cost the
     * image about 100 bytes of flash). */
    const volatile uint8_t *got = (const volatile uint8_t *)(slots[slot].addr + offset);
    const uint8_t *want = data;
    for (size_t i = 0; ok && i < len; i++) {
        ok = got[i] == want[i];
    }
    return ok ? HAL_OK : HAL_EIO;
}

int hal_storage_commit(uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS || !slot_open[slot]) {
        return HAL_EINVAL;
    }
    /* Programmed flash is durable already: committing closes the slot for writing. */
    slot_open[slot] = false;
    return HAL_OK;
}

int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    if (!range_ok(slot, offset, len) || (data == NULL && len != 0u)) {
        return HAL_EINVAL;
    }
    if (len != 0u) {
        memcpy(data, (const void *)(slots[slot].addr + offset), len);
    }
    return HAL_OK;
}
