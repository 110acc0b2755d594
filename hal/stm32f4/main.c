/* SPDX-License-Identifier: MIT */
/* The robot image: bring the board up, run the mapper on the 10 ms tick, report on the UART. */
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

#define STATUS_EVERY_TICKS 100u /* one status line a second */

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

/* One line a second: a consistent snapshot taken with the tick held off. */
static void status(void)
{
    hal_irq_state_t s = hal_critical_enter();
    uint32_t ticks = robot.ticks;
    odom_pose_t pose = robot.pose;
    uint32_t pings = robot.sweep.pings;
    uint32_t echoes = robot.sweep.echoes;
    uint32_t timeouts = robot.sweep.timeouts;
    uint32_t hits = robot.mapper.hits;
    hal_critical_exit(s);

    text_line_t l;
    text_clear(&l);
    text_str(&l, "status t ");
    text_u32(&l, ticks / 100u);
    text_str(&l, " s ticks ");
    text_u32(&l, ticks);
    text_str(&l, " overruns ");
    text_u32(&l, hal_tick_overruns());
    text_str(&l, " pose ");
    text_i32(&l, pose.x_um / 1000);
    text_str(&l, " ");
    text_i32(&l, pose.y_um / 1000);
    text_str(&l, " mm ");
    text_i32(&l, fix_bam_to_mdeg(pose.heading) / 1000);
    text_str(&l, " deg pings ");
    text_u32(&l, pings);
    text_str(&l, " echoes ");
    text_u32(&l, echoes);
    text_str(&l, " timeouts ");
    text_u32(&l, timeouts);
    text_str(&l, " om_hits ");
    text_u32(&l, hits);
    text_str(&l, "\r\n");
    send(&l);
}

void stm32_fault_hook(const stm32_fault_t *f)
{
    text_line_t l;
    text_clear(&l);
    text_str(&l, "\r\nFAULT exception ");
    text_u32(&l, f->exception);
    if (f->why != NULL) {
        text_str(&l, ": ");
        text_str(&l, f->why);
    }
    text_str(&l, " pc 0x");
    text_hex(&l, f->pc, 8u);
    text_str(&l, " lr 0x");
    text_hex(&l, f->lr, 8u);
    text_str(&l, " cfsr 0x");
    text_hex(&l, f->cfsr, 8u);
    text_str(&l, " hfsr 0x");
    text_hex(&l, f->hfsr, 8u);
    text_str(&l, " bfar 0x");
    text_hex(&l, f->bfar, 8u);
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
        stm32_panic("bad configuration");
    }
    banner();
    if (hal_tick_start(tick, &robot) != HAL_OK) {
        stm32_panic("the tick did not start");
    }

    uint32_t reported = 0u;
    for (;;) {
        cm_wfi(); /* until the next tick or UART interrupt */
        robot_idle(&robot);
        uint32_t ticks = *(volatile const uint32_t *)&robot.ticks;
        if (ticks - reported >= STATUS_EVERY_TICKS) {
            reported = ticks;
            status();
        }
        stm32_uart_pump();
    }
}
