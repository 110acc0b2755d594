/* SPDX-License-Identifier: MIT */
/**
 * @file
 * ARM semihosting, for the self-test image only: text to the debugger's (or QEMU's)
 * console and an exit status. Without a debugger attached the BKPT instruction faults, so
 * the robot image never uses it.
 */
#ifndef CM_SEMIHOST_H
#define CM_SEMIHOST_H

#include <stdint.h>

/** Write a NUL-terminated string to the host console (SYS_WRITE0). */
void semihost_write0(const char *s);

/** End the program with an exit status (SYS_EXIT_EXTENDED); QEMU exits with it. */
_Noreturn void semihost_exit(uint32_t status);

#endif /* CM_SEMIHOST_H */
