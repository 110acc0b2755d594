/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The Linux backend as its program sees it: what hal.h cannot say (configuration, errors,
 * shutdown, safety, statistics).
 *
 * Threads: the tick thread runs the hal_tick_start() callback every 10 ms from a timerfd,
 * with SCHED_FIFO when permitted, holding the critical-section mutex; it does no I/O: the
 * outputs it sets (motor duty and direction, servos, the sonars' triggers) go to the output
 * thread, which writes them. The events thread reads encoder, echo and bump switch edges,
 * so the tick reads what they left, never a line. The watchdog
 * thread checks every 10 ms that ticks, both other threads (and the background loop's
 * kicks) go on, and stops the motors if not. Everything else runs in the caller's (main)
 * thread; robot_idle() runs inside lhal_idle_lock().
 *
 * Safety: the motors stop, the direction and standby lines low first and then PWM duty 0
 * and disabled, without any lock a stuck thread may hold: when lhal_shutdown() runs, when
 * the watchdog trips (a stalled or dead thread), when a hardware operation fails (a fault),
 * at lhal_signal_stop() (for SIGINT and SIGTERM handlers) and at lhal_emergency_stop()
 * (for crash handlers). Once stopped they stay stopped until the next hal_init().
 */
#ifndef LHAL_LHAL_H
#define LHAL_LHAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "lhal/echo.h"
#include "lhal/lconf.h"
#include "lhal/tickstat.h"

/** Why the backend stopped the motors on its own. */
typedef enum {
    LHAL_FAULT_NONE = 0,
    LHAL_FAULT_WATCHDOG, /**< the tick or the background loop stalled */
    LHAL_FAULT_IO,       /**< a GPIO, PWM or timer operation failed */
} lhal_fault_t;

/** Counters of the backend, a consistent snapshot. */
typedef struct {
    tickstat_t tick;            /**< the tick's accounting: ticks, late, overruns, missed */
    bool sched_fifo;            /**< the tick runs with SCHED_FIFO */
    uint16_t enc_count[2];      /**< the HAL's encoder counters */
    uint32_t enc_edges[2];      /**< edges decoded per wheel */
    uint32_t enc_illegal[2];    /**< impossible transitions and lost edges per wheel */
    unsigned sonars;            /**< sonars wired: sonar[0 .. sonars - 1] count */
    echo_t sonar[LCONF_SONARS]; /**< each sonar's counters: pings, echoes, timeouts by cause */
    unsigned bumps;             /**< bump switches wired */
    uint32_t bump_high;         /**< bit i set while bump switch i's line is high */
    uint64_t uart_sent;         /**< telemetry bytes written */
    uint64_t uart_dropped;      /**< telemetry bytes dropped (no room) */
    bool kernel_ts_realtime;    /**< edge timestamps are not CLOCK_MONOTONIC (kernel < 5.7) */
    uint32_t events_rounds;     /**< times the events thread went round (it does every 10 ms) */
    uint32_t output_rounds;     /**< times the output thread went round (the same) */
    uint32_t outputs_posted;    /**< output changes set through hal.h */
    uint32_t outputs_written;   /**< the last of them the output thread has written */
    const char *output_writing; /**< what the output thread writes now ("servo_pwm"), or NULL */
} lhal_stats_t;

/** Use this configuration at the next hal_init() (copied). */
void lhal_configure(const lconf_t *cfg);

/**
 * Replace the monotonic clock of hal_time_us(), the echo deadlines and the watchdog
 * (tests freeze and step it); NULL restores CLOCK_MONOTONIC. Call before hal_init().
 * The tick's timer and its accounting always use the real clock.
 */
void lhal_set_clock(uint64_t (*now_ns)(void));

/** Why hal_init() or hal_tick_start() failed: names the key and the reason. */
const char *lhal_error(void);

/** The telemetry stream's device, or the pseudo-terminal a viewer opens. */
const char *lhal_telemetry_name(void);

/**
 * Stop the motors (lines low at once), stop the threads, disable the PWM outputs, release
 * everything. A thread that does not end within a second (stuck in a call that does not
 * return) is left behind, and then nothing is released: the process is to end. Safe to
 * call more than once and after a failed hal_init().
 * @return every thread ended (false: one was left behind)
 */
bool lhal_shutdown(void);

/**
 * Stop the motors for good from a SIGINT or SIGTERM handler: flags and a wake-up of the
 * watchdog thread, which drops the lines and the PWM at once. Async-signal-safe and
 * without I/O of its own, so a hung device cannot hold the handler.
 */
void lhal_signal_stop(void);

/** Stop the motors now and for good, in the calling thread (for crash handlers). */
void lhal_emergency_stop(void);

/**
 * The background loop's turn: take the critical section, waiting at most 20 ms (a tick
 * that does not end holds it). robot_idle() and whatever reads the robot's state run
 * between this and lhal_idle_unlock(), so the tick never changes what they read; the
 * storage calls they make let the tick in while their file I/O blocks.
 * @retval HAL_OK     taken
 * @retval HAL_EBUSY  the tick held it for longer; try again after checking lhal_fault()
 */
int lhal_idle_lock(void);

/** End the background loop's turn. */
void lhal_idle_unlock(void);

/**
 * Whether the backend stopped the motors on its own.
 * @param msg  out: what happened, when a fault is returned (may be NULL)
 */
lhal_fault_t lhal_fault(char *msg, size_t msglen);

/** A snapshot of the counters. */
void lhal_stats(lhal_stats_t *out);

/** Write the counters as a short human-readable report. */
void lhal_report(FILE *f);

/**
 * --check: open the chip, every configured line and PWM channel, the telemetry stream and
 * the storage directory; report each on @p out; move nothing (outputs are requested low,
 * PWM channels are exported at most, never written). Needs no hal_init().
 * @return the number of items that failed
 */
unsigned lhal_check(const lconf_t *cfg, FILE *out);

#endif /* LHAL_LHAL_H */
