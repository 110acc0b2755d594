/* SPDX-License-Identifier: MIT */
/* Linux sysfs PWM channels: export, start, duty writes that skip repeats, and a kill switch. */
#define _POSIX_C_SOURCE 200809L
#include "lhal/pwm.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* Formats without stdio, so pwm_kill() stays async-signal-safe. */
static size_t pwm_format_u32(char *buf, uint32_t v)
{
    char tmp[10];
    size_t n = 0u;
    do {
        tmp[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    for (size_t i = 0u; i < n; i++) {
        buf[i] = tmp[n - 1u - i];
    }
    buf[n] = '\n';
    return n + 1u;
}

int pwm_write_u32(const char *path, uint32_t value)
{
    char buf[12];
    size_t len = pwm_format_u32(buf, value);
    int fd = open(path, O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) {
        return -errno;
    }
    ssize_t w = write(fd, buf, len);
    int rc = w == (ssize_t)len ? 0 : (w < 0 ? -errno : -EIO);
    if (close(fd) != 0 && rc == 0) {
        rc = -errno;
    }
    return rc;
}

static bool pwm_is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static void pwm_sleep_ms(unsigned ms)
{
    struct timespec ts = {.tv_sec = (time_t)(ms / 1000u), .tv_nsec = (long)(ms % 1000u) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

int pwm_open(pwm_chan_t *p, const char *root, unsigned chip, unsigned channel, unsigned wait_ms,
             char *err, size_t errlen)
{
    char chipdir[PWM_PATH_MAX];
    int n = snprintf(chipdir, sizeof chipdir, "%s/pwmchip%u", root, chip);
    if (n < 0 || (size_t)n >= sizeof chipdir ||
        snprintf(p->dir, sizeof p->dir, "%s/pwm%u", chipdir, channel) >= (int)sizeof p->dir) {
        snprintf(err, errlen, "PWM path under '%s' is too long", root);
        return -1;
    }
    snprintf(p->duty_path, sizeof p->duty_path, "%s/duty_cycle", p->dir);
    snprintf(p->enable_path, sizeof p->enable_path, "%s/enable", p->dir);
    p->period_ns = 0u;
    p->duty_ns = UINT32_MAX;
    p->enabled = false;

    if (!pwm_is_dir(chipdir)) {
        snprintf(err, errlen, "%s does not exist (is the PWM overlay or driver loaded?)", chipdir);
        return -1;
    }
    if (pwm_is_dir(p->dir)) {
        return 0;
    }
    char export_path[PWM_PATH_MAX + 8u];
    snprintf(export_path, sizeof export_path, "%s/export", chipdir);
    int rc = pwm_write_u32(export_path, channel);
    if (rc != 0) {
        snprintf(err, errlen, "cannot export channel %u: %s: %s", channel, export_path,
                 strerror(-rc));
        return -1;
    }
    for (unsigned waited = 0u;; waited += 10u) {
        if (pwm_is_dir(p->dir) && access(p->duty_path, W_OK) == 0) {
            return 0;
        }
        if (waited >= wait_ms) {
            break;
        }
        pwm_sleep_ms(10u);
    }
    snprintf(err, errlen, "%s did not appear after exporting channel %u (does pwmchip%u have it?)",
             p->dir, channel, chip);
    return -1;
}

int pwm_writable(const pwm_chan_t *p, char *err, size_t errlen)
{
    static const char *const attrs[] = {"period", "duty_cycle", "enable"};
    for (size_t i = 0u; i < sizeof attrs / sizeof attrs[0]; i++) {
        char path[PWM_PATH_MAX + 16u];
        snprintf(path, sizeof path, "%s/%s", p->dir, attrs[i]);
        if (access(path, W_OK) != 0) {
            snprintf(err, errlen, "%s is not writable: %s", path, strerror(errno));
            return -1;
        }
    }
    return 0;
}

int pwm_start(pwm_chan_t *p, uint32_t period_ns, uint32_t duty_ns)
{
    char path[PWM_PATH_MAX + 16u];
    snprintf(path, sizeof path, "%s/period", p->dir);
    /* The kernel refuses a period below the present duty, so the duty goes to 0 first. */
    int rc = pwm_write_u32(p->duty_path, 0u);
    if (rc == 0) {
        p->duty_ns = 0u;
        rc = pwm_write_u32(path, period_ns);
    }
    if (rc == 0) {
        p->period_ns = period_ns;
        rc = pwm_set_duty(p, duty_ns);
    }
    if (rc == 0) {
        rc = pwm_write_u32(p->enable_path, 1u);
        p->enabled = rc == 0;
    }
    return rc;
}

int pwm_set_duty(pwm_chan_t *p, uint32_t duty_ns)
{
    if (duty_ns > p->period_ns) {
        duty_ns = p->period_ns;
    }
    if (duty_ns == p->duty_ns) {
        return 0;
    }
    int rc = pwm_write_u32(p->duty_path, duty_ns);
    p->duty_ns = rc == 0 ? duty_ns : UINT32_MAX;
    return rc;
}

int pwm_stop(pwm_chan_t *p)
{
    int rc = pwm_write_u32(p->duty_path, 0u);
    p->duty_ns = rc == 0 ? 0u : UINT32_MAX;
    int rc2 = pwm_write_u32(p->enable_path, 0u);
    p->enabled = rc2 != 0 && p->enabled;
    return rc != 0 ? rc : rc2;
}

int pwm_kill(const pwm_chan_t *p)
{
    if (p->dir[0] == '\0') {
        return 0;
    }
    int rc = pwm_write_u32(p->duty_path, 0u);
    int rc2 = pwm_write_u32(p->enable_path, 0u);
    return rc != 0 ? rc : rc2;
}
