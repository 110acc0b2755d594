/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What a chip folder gives the self-test image (selftest_main.c), besides its tick
 * (hal_tick_start(), hal_tick_overruns()), its watchdog kick and its critical section:
 * the clock, an instruction counter, and a way to stop the tick.
 *
 * Under QEMU with -icount shift=0 a free-running timer at the core clock counts one per
 * executed instruction: that timer is the counter (selftest.h, selftest_counter()).
 */
#ifndef CM_SELFTEST_PORT_H
#define CM_SELFTEST_PORT_H

/** Bring up the clock tree and start the counter selftest_counter() reads. First thing. */
void selftest_port_init(void);

/** Stop the tick for good (and forget one pending), before the report. */
void selftest_port_stop(void);

/** A short name of the clock source, for the report's `clock` line. */
const char *selftest_port_clock_name(void);

#endif /* CM_SELFTEST_PORT_H */
