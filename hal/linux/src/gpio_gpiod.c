/* SPDX-License-Identifier: MIT */
/* The backend's GPIO through libgpiod 1.6: the only file that calls gpiod_*. */
#define _POSIX_C_SOURCE 200809L
#include "lhal/gpio_if.h"

#include <errno.h>
#include <fcntl.h>
#include <gpiod.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GPIO_CONSUMER "sonarslam"

/* libgpiod owns the line objects; ours only points at one. */
struct gpio_line {
    struct gpiod_line *line;
};

/* The chip holds the handles of its requested lines, so closing it frees everything. */
struct gpio_chip {
    struct gpiod_chip *chip;
    char describe[96];
    struct gpio_line lines[GPIO_IF_LINES_MAX];
    unsigned nlines;
};

int gpio_chip_open(const char *name, gpio_chip_t **out, char *err, size_t errlen)
{
    gpio_chip_t *c = calloc(1u, sizeof *c);
    if (c == NULL) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    c->chip = gpiod_chip_open_lookup(name);
    if (c->chip == NULL) {
        snprintf(err, errlen, "cannot open GPIO chip '%s': %s (see gpiodetect)", name,
                 strerror(errno));
        free(c);
        return -1;
    }
    snprintf(c->describe, sizeof c->describe, "%s [%s]", gpiod_chip_name(c->chip),
             gpiod_chip_label(c->chip));
    *out = c;
    return 0;
}

const char *gpio_chip_describe(gpio_chip_t *chip)
{
    return chip->describe;
}

unsigned gpio_chip_lines(gpio_chip_t *chip)
{
    return gpiod_chip_num_lines(chip->chip);
}

void gpio_chip_close(gpio_chip_t *chip)
{
    if (chip == NULL) {
        return;
    }
    /* Closing the chip releases every line requested through it and frees them. */
    gpiod_chip_close(chip->chip);
    free(chip);
}

/* Requests a line, saying who holds it when it is taken. */
static int gpio_request(gpio_chip_t *chip, unsigned offset, int type, int flags, int value,
                        gpio_line_t **out, char *err, size_t errlen)
{
    if (chip->nlines == GPIO_IF_LINES_MAX) {
        snprintf(err, errlen, "more than %u lines requested", GPIO_IF_LINES_MAX);
        errno = ENOSPC;
        return -1;
    }
    struct gpiod_line *l = gpiod_chip_get_line(chip->chip, offset);
    if (l == NULL) {
        snprintf(err, errlen, "line %u does not exist on %s (%u lines)", offset, chip->describe,
                 gpiod_chip_num_lines(chip->chip));
        return -1;
    }
    struct gpiod_line_request_config rc = {
        .consumer = GPIO_CONSUMER, .request_type = type, .flags = flags};
    if (gpiod_line_request(l, &rc, value) != 0) {
        int e = errno;
        const char *user = gpiod_line_consumer(l);
        if (e == EBUSY && user != NULL) {
            snprintf(err, errlen, "line %u is in use by '%s'", offset, user);
        } else {
            snprintf(err, errlen, "cannot request line %u: %s", offset, strerror(e));
        }
        errno = e;
        return -1;
    }
    gpio_line_t *g = &chip->lines[chip->nlines++];
    g->line = l;
    *out = g;
    return 0;
}

int gpio_line_output(gpio_chip_t *chip, unsigned offset, int value, gpio_line_t **line, char *err,
                     size_t errlen)
{
    return gpio_request(chip, offset, GPIOD_LINE_REQUEST_DIRECTION_OUTPUT, 0, value, line, err,
                        errlen);
}

int gpio_line_edges(gpio_chip_t *chip, unsigned offset, lconf_bias_t bias, gpio_line_t **line,
                    char *err, size_t errlen)
{
    static const int flags[] = {
        [LCONF_BIAS_AS_IS] = 0,
        [LCONF_BIAS_DISABLE] = GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE,
        [LCONF_BIAS_PULL_UP] = GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP,
        [LCONF_BIAS_PULL_DOWN] = GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN,
    };
    if (gpio_request(chip, offset, GPIOD_LINE_REQUEST_EVENT_BOTH_EDGES, flags[bias], 0, line, err,
                     errlen) != 0) {
        return -1;
    }
    /* Non-blocking, so a reader can look at every line without waiting on any. */
    int fd = gpiod_line_event_get_fd((*line)->line);
    int fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) != 0) {
        snprintf(err, errlen, "line %u: cannot make its events non-blocking: %s", offset,
                 strerror(errno));
        return -1;
    }
    return 0;
}

int gpio_line_set(gpio_line_t *line, int value)
{
    return gpiod_line_set_value(line->line, value);
}

int gpio_line_get(gpio_line_t *line)
{
    return gpiod_line_get_value(line->line);
}

int gpio_line_fd(gpio_line_t *line)
{
    return gpiod_line_event_get_fd(line->line);
}

int gpio_line_read_edges(gpio_line_t *line, uint8_t src, edgeq_edge_t *out, size_t max)
{
    struct gpiod_line_event ev[16];
    unsigned want = max < 16u ? (unsigned)max : 16u;
    int n = gpiod_line_event_read_fd_multiple(gpiod_line_event_get_fd(line->line), ev, want);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        return 0;
    }
    for (int i = 0; i < n; i++) {
        out[i] = (edgeq_edge_t){
            .ts_ns = (uint64_t)ev[i].ts.tv_sec * 1000000000u + (uint64_t)ev[i].ts.tv_nsec,
            .src = src,
            .rising = ev[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE,
        };
    }
    return n;
}
