/* SPDX-License-Identifier: MIT */
/* The robot image: bring the board up, say hello in text, then run the mapper on the 10 ms
 * tick while robot_idle() streams telemetry frames on the UART (tools/telemetry.py). */
#include <string.h>

#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "slam/error.h"
#include "slam/robot.h"
#include "stm32f4_port.h"
#include "text.h"

#ifndef SLAM_VERSION
#define SLAM_VERSION "unknown"
#endif

static robot_t robot;

static void tick(void *ctx)
{
    robot_tick(ctx);
}

static void send(const text_line_t *l)
{
    (void)hal_uart_write((const uint8_t *)l->buf, l->len);
    stm32_uart_pump();
}

static void banner(void)
{
    text_line_t l;
    text_clear(&l);
    text_str(&l, "sonarslam " SLAM_VERSION " stm32f4 board " BOARD_NAME ": clock ");
    text_str(&l, stm32_clock_name());
    text_str(&l, " ");
    text_u32(&l, stm32_clocks.sysclk_hz / 1000000u);
    text_str(&l, " MHz");
    if (stm32_clocks.hse_timeout) {
        text_str(&l, " (crystal did not start)");
    }
    if (stm32_clocks.pll_timeout) {
        text_str(&l, " (PLL did not lock)");
    }
    if (stm32_clocks.flash_refused) {
        text_str(&l, " (flash wait states refused)");
    }
    text_str(&l, ", reset ");
    text_str(&l, stm32_reset_name(stm32_reset_flags()));
    text_str(&l, "\r\n");
    send(&l);
    text_clear(&l);
    text_str(&l, "grid ");
    text_u32(&l, SLAM_GRID_A);
    text_str(&l, "x");
    text_u32(&l, SLAM_GRID_B);
    text_str(&l, " cells of ");
    text_u32(&l, robot.cfg.cell_um / 1000u);
    text_str(&l, " mm, map storage 2 x ");
    text_u32(&l, (uint32_t)(hal_storage_size() / 1024u));
    text_str(&l, " KiB\r\n");
    send(&l);
}

void cm_fault_hook(const cm_fault_t *f)
{
    text_line_t l;
    text_clear(&l);
    text_str(&l, "\r\n");
    text_fault(&l, f);
    text_str(&l, "; motors off, waiting for the watchdog\r\n");
    stm32_uart_write_blocking(l.buf);
}

int main(void)
{
    (void)hal_init();
    slam_config_t cfg;
    slam_config_default(&cfg);
    const char *bad = NULL;
    if (slam_config_check(&cfg, &bad) != SLAM_OK || robot_init(&robot, &cfg) != SLAM_OK) {
        text_line_t l;
        text_clear(&l);
        text_str(&l, "sonarslam: bad configuration: ");
        text_str(&l, bad != NULL ? bad : "?");
        text_str(&l, "; motors off\r\n");
        stm32_uart_write_blocking(l.buf);
        cm_panic("bad configuration");
    }
    banner();
    if (hal_tick_start(tick, &robot) != HAL_OK) {
        cm_panic("the tick did not start");
    }

    for (;;) {
        cm_wfi();           /* until the next tick or UART interrupt */
        robot_idle(&robot); /* telemetry: HELLO, POSE, READING, MAP_ROW, STATUS frames */
        stm32_uart_pump();
    }
}
