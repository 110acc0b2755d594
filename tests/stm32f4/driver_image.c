/* SPDX-License-Identifier: MIT */
/* A test image that links every HAL function of the STM32F4 port, used or not by the core yet,
 * so storage_model_test.py can run the drivers' own code against register models. */
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

typedef struct {
    size_t (*size)(void);
    int (*begin)(uint8_t);
    int (*write)(uint8_t, uint32_t, const void *, size_t);
    int (*commit)(uint8_t);
    int (*read)(uint8_t, uint32_t, void *, size_t);
    void (*kick)(void);
    void (*start)(uint32_t);
} driver_table_t;

const driver_table_t driver_table = {
    hal_storage_size, hal_storage_begin, hal_storage_write, hal_storage_commit,
    hal_storage_read, hal_watchdog_kick, stm32_watchdog_start,
};

int main(void)
{
    (void)hal_init();
    /* Keep the table, and with it every driver, through --gc-sections. */
    __asm__ volatile("" : : "r"(&driver_table));
    for (;;) {
        cm_wfi();
    }
}
