/* SPDX-License-Identifier: MIT */
/* Telemetry on a serial device or a pseudo-terminal, written without ever blocking. */
#define _GNU_SOURCE /* posix_openpt/ptsname_r, B460800 and up */
#include "lhal/serial.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

static const struct {
    uint32_t baud;
    speed_t speed;
} serial_speeds[] = {
    {9600u, B9600},     {19200u, B19200},   {38400u, B38400},   {57600u, B57600},
    {115200u, B115200}, {230400u, B230400}, {460800u, B460800}, {921600u, B921600},
};

bool serial_baud_supported(uint32_t baud)
{
    for (size_t i = 0u; i < sizeof serial_speeds / sizeof serial_speeds[0]; i++) {
        if (serial_speeds[i].baud == baud) {
            return true;
        }
    }
    return false;
}

static speed_t serial_speed(uint32_t baud)
{
    for (size_t i = 0u; i < sizeof serial_speeds / sizeof serial_speeds[0]; i++) {
        if (serial_speeds[i].baud == baud) {
            return serial_speeds[i].speed;
        }
    }
    return B115200;
}

/* Raw 8N1 without flow control: the stream is binary frames, not text. */
static int serial_raw(int fd, uint32_t baud, bool set_speed)
{
    struct termios t;
    if (tcgetattr(fd, &t) != 0) {
        return -1;
    }
    cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~(tcflag_t)CRTSCTS;
    if (set_speed &&
        (cfsetispeed(&t, serial_speed(baud)) != 0 || cfsetospeed(&t, serial_speed(baud)) != 0)) {
        return -1;
    }
    return tcsetattr(fd, TCSANOW, &t);
}

static int serial_fail(serial_t *s, char *err, size_t errlen, const char *what)
{
    snprintf(err, errlen, "telemetry '%s': %s: %s", s->name, what, strerror(errno));
    serial_close(s);
    return -1;
}

int serial_open(serial_t *s, const char *spec, uint32_t baud, char *err, size_t errlen)
{
    *s = (serial_t){.fd = -1, .peer_fd = -1};
    snprintf(s->name, sizeof s->name, "%s", spec);
    if (strcmp(spec, "none") == 0) {
        return 0;
    }
    if (strcmp(spec, "pty") == 0) {
        s->fd = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
        if (s->fd < 0) {
            return serial_fail(s, err, errlen, "cannot open a pseudo-terminal");
        }
        if (grantpt(s->fd) != 0 || unlockpt(s->fd) != 0 ||
            ptsname_r(s->fd, s->name, sizeof s->name) != 0) {
            return serial_fail(s, err, errlen, "cannot set up the pseudo-terminal");
        }
        s->peer_fd = open(s->name, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
        if (s->peer_fd < 0 || serial_raw(s->peer_fd, baud, false) != 0) {
            return serial_fail(s, err, errlen, "cannot open the pseudo-terminal's end");
        }
        return 0;
    }
    s->fd = open(spec, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (s->fd < 0) {
        return serial_fail(s, err, errlen, "cannot open");
    }
    if (isatty(s->fd) && serial_raw(s->fd, baud, true) != 0) {
        return serial_fail(s, err, errlen, "cannot configure");
    }
    return 0;
}

size_t serial_write(serial_t *s, const uint8_t *data, size_t len)
{
    size_t done = 0u;
    while (s->fd >= 0 && done < len) {
        ssize_t w = write(s->fd, data + done, len - done);
        if (w > 0) {
            done += (size_t)w;
        } else if (w < 0 && errno == EINTR) {
            continue;
        } else {
            break; /* full (EAGAIN) or gone: drop the rest, never wait */
        }
    }
    s->sent += done;
    s->dropped += len - done;
    return done;
}

size_t serial_read(serial_t *s, uint8_t *data, size_t len)
{
    if (s->fd < 0 || len == 0u) {
        return 0u;
    }
    ssize_t r;
    do {
        r = read(s->fd, data, len);
    } while (r < 0 && errno == EINTR);
    return r > 0 ? (size_t)r : 0u;
}

void serial_close(serial_t *s)
{
    if (s->peer_fd >= 0) {
        close(s->peer_fd);
    }
    if (s->fd >= 0) {
        close(s->fd);
    }
    s->fd = -1;
    s->peer_fd = -1;
}
