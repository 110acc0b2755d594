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
    int (*tick_start)(hal_tick_fn, void *);
    uint32_t (*overruns)(void);
    uint32_t (*time_us)(void);
    uint16_t (*encoder)(hal_wheel_t);
    void (*motor)(hal_wheel_t, int16_t);
    int (*servo)(uint8_t, uint16_t);
    int (*trigger)(uint8_t);
    int (*poll)(uint8_t, uint32_t *);
    uint8_t (*servo_count)(void);
    uint8_t (*sonar_count)(void);
    uint8_t (*bump_count)(void);
    int (*bump_read)(uint8_t, bool *);
    size_t (*uart_write)(const uint8_t *, size_t);
    size_t (*uart_read)(uint8_t *, size_t);
    hal_irq_state_t (*critical_enter)(void);
    void (*critical_exit)(hal_irq_state_t);
    void (*safe)(void);
} driver_table_t;

const driver_table_t driver_table = {
    hal_storage_size,    hal_storage_begin,  hal_storage_write,    hal_storage_commit,
    hal_storage_read,    hal_watchdog_kick,  stm32_watchdog_start, hal_tick_start,
    hal_tick_overruns,   hal_time_us,        hal_encoder_count,    hal_motor_set,
    hal_servo_set_pulse, hal_sonar_trigger,  hal_sonar_poll,       hal_servo_count,
    hal_sonar_count,     hal_bump_count,     hal_bump_read,        hal_uart_write,
    hal_uart_read,       hal_critical_enter, hal_critical_exit,    cm_safe_outputs,
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
