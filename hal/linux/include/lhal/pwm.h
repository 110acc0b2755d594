/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Linux PWM channels through sysfs: ROOT/pwmchipN/pwmM/{period,duty_cycle,enable}.
 *
 * ROOT is /sys/class/pwm on a robot and any directory in tests. A channel that is not
 * exported yet is exported by writing M to ROOT/pwmchipN/export. Values are written in ns
 * as decimal text, each by open/write/close, the way `echo` does it, so the same code
 * works on sysfs attributes and on plain files. Duty writes skip an unchanged value.
 *
 * A channel's paths never change after pwm_open(), so pwm_kill() may be called from a
 * signal handler or another thread while the owner writes: it only uses async-signal-safe
 * calls and touches no cached state.
 */
#ifndef LHAL_PWM_H
#define LHAL_PWM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** Longest path of a channel's directory. */
#define PWM_PATH_MAX 240u

/** How long a robot waits for an exported channel to appear (pwm_open()'s wait_ms). */
#define PWM_EXPORT_WAIT_MS 1000u

/** One PWM channel. */
typedef struct {
    char dir[PWM_PATH_MAX];               /**< ROOT/pwmchipN/pwmM */
    char duty_path[PWM_PATH_MAX + 16u];   /**< dir/duty_cycle */
    char enable_path[PWM_PATH_MAX + 16u]; /**< dir/enable */
    uint32_t period_ns;                   /**< as last written by pwm_start() */
    uint32_t duty_ns;                     /**< as last written; UINT32_MAX before the first */
    bool enabled;                         /**< as last written */
} pwm_chan_t;

/**
 * Find a channel and export it if needed; writes nothing else.
 * @param root     the sysfs PWM class directory
 * @param wait_ms  after an export, how long to wait for the channel to appear (udev may
 *                 need a moment to make it writable); 0 in tests
 * @param err      out: on failure, what is missing and where
 * @return 0, or -1 with err set
 */
int pwm_open(pwm_chan_t *p, const char *root, unsigned chip, unsigned channel, unsigned wait_ms,
             char *err, size_t errlen);

/**
 * Whether the channel's period, duty_cycle and enable can be written (for --check).
 * @return 0, or -1 with err naming the first that cannot
 */
int pwm_writable(const pwm_chan_t *p, char *err, size_t errlen);

/**
 * Start the channel: duty 0, the period, the duty, enable (in the order the kernel
 * accepts from any previous state).
 * @return 0, or -errno of the first write that failed
 */
int pwm_start(pwm_chan_t *p, uint32_t period_ns, uint32_t duty_ns);

/**
 * Set the duty cycle; nothing is written when it is unchanged.
 * @param duty_ns  clamped to the period
 * @return 0, or -errno
 */
int pwm_set_duty(pwm_chan_t *p, uint32_t duty_ns);

/**
 * Duty 0 and disable.
 * @return 0, or -errno of the first write that failed (both are tried)
 */
int pwm_stop(pwm_chan_t *p);

/**
 * Duty 0 and disable, async-signal-safe and without touching the cached state.
 * @return 0, or -errno of the first write that failed (both are tried)
 */
int pwm_kill(const pwm_chan_t *p);

/**
 * Write a decimal number to a file as `echo N > path` does.
 * @return 0, or -errno
 */
int pwm_write_u32(const char *path, uint32_t value);

#endif /* LHAL_PWM_H */
