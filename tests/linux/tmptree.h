/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Temporary directory trees for tests: a fake /sys/class/pwm, storage directories, files
 * to read back. Paths are relative to a root made by tmptree_make(). Failures abort the
 * test (they are the machine's, not the code's).
 */
#ifndef TEST_TMPTREE_H
#define TEST_TMPTREE_H

#include <stdbool.h>

#define TMPTREE_PATH_MAX 128

/** Make a fresh directory /tmp/slam-lx-TAG-XXXXXX; its path goes to root. */
void tmptree_make(char root[TMPTREE_PATH_MAX], const char *tag);

/** Write a file (and the directories above it). */
void tmptree_file(const char *root, const char *rel, const char *content);

/** A sysfs-like PWM channel: pwmchipN/pwmM/{period,duty_cycle,enable}, empty. */
void tmptree_pwm_channel(const char *root, unsigned chip, unsigned channel);

/** A file's content (a static buffer of 64 KiB), or "<missing>". */
const char *tmptree_read(const char *root, const char *rel);

/** Whether a path exists. */
bool tmptree_exists(const char *root, const char *rel);

/** Remove one file. */
void tmptree_unlink(const char *root, const char *rel);

/** Remove the whole tree. */
void tmptree_remove(const char *root);

#endif /* TEST_TMPTREE_H */
