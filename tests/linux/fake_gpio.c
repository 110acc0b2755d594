/* SPDX-License-Identifier: MIT */
/* A fake GPIO chip behind lhal/gpio_if.h: scripted inputs and edges, recorded outputs. */
#define _GNU_SOURCE /* pipe2 */
#include "fake_gpio.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lhal/gpio_if.h"

#define FAKE_EDGES_MAX 256u

struct gpio_line {
    unsigned offset;
};

struct gpio_chip {
    int unused;
};

typedef struct {
    bool requested;
    bool output;
    bool edges;
    int value;
    unsigned rises;
    char busy_user[32];
    int pipe[2];
    edgeq_edge_t queue[FAKE_EDGES_MAX];
    size_t head;
    size_t n;
} fake_line_t;

static pthread_mutex_t fake_lock = PTHREAD_MUTEX_INITIALIZER;
static fake_line_t fake_lines[FAKE_GPIO_LINES];
static struct gpio_line fake_handles[FAKE_GPIO_LINES];
static struct gpio_chip fake_chip;
static bool fake_chip_missing;

static void fake_close_pipes(fake_line_t *l)
{
    for (int i = 0; i < 2; i++) {
        if (l->pipe[i] >= 0) {
            close(l->pipe[i]);
            l->pipe[i] = -1;
        }
    }
}

void fake_gpio_reset(void)
{
    pthread_mutex_lock(&fake_lock);
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        if (fake_lines[i].requested) {
            fake_close_pipes(&fake_lines[i]);
        }
        memset(&fake_lines[i], 0, sizeof fake_lines[i]);
        fake_lines[i].pipe[0] = fake_lines[i].pipe[1] = -1;
        fake_handles[i].offset = i;
    }
    fake_chip_missing = false;
    pthread_mutex_unlock(&fake_lock);
}

void fake_gpio_no_chip(void)
{
    fake_chip_missing = true;
}

void fake_gpio_busy(unsigned offset, const char *user)
{
    pthread_mutex_lock(&fake_lock);
    snprintf(fake_lines[offset].busy_user, sizeof fake_lines[offset].busy_user, "%s", user);
    pthread_mutex_unlock(&fake_lock);
}

void fake_gpio_level(unsigned offset, bool high)
{
    pthread_mutex_lock(&fake_lock);
    fake_lines[offset].value = high;
    pthread_mutex_unlock(&fake_lock);
}

void fake_gpio_edges(const fake_edge_t *edges, unsigned n)
{
    pthread_mutex_lock(&fake_lock);
    for (unsigned i = 0u; i < n; i++) {
        fake_line_t *l = &fake_lines[edges[i].offset];
        if (l->requested && l->edges && l->n < FAKE_EDGES_MAX) {
            l->queue[(l->head + l->n) % FAKE_EDGES_MAX] =
                (edgeq_edge_t){.ts_ns = edges[i].ts_ns, .rising = edges[i].rising};
            l->n++;
            l->value = edges[i].rising;
        }
    }
    /* Wake the reader only when everything is queued. */
    for (unsigned i = 0u; i < n; i++) {
        fake_line_t *l = &fake_lines[edges[i].offset];
        if (l->requested && l->edges) {
            const char byte = 1;
            (void)!write(l->pipe[1], &byte, 1u);
        }
    }
    pthread_mutex_unlock(&fake_lock);
}

void fake_gpio_edge(unsigned offset, uint64_t ts_ns, bool rising)
{
    const fake_edge_t e = {offset, ts_ns, rising};
    fake_gpio_edges(&e, 1u);
}

bool fake_gpio_requested(unsigned offset)
{
    pthread_mutex_lock(&fake_lock);
    bool v = fake_lines[offset].requested;
    pthread_mutex_unlock(&fake_lock);
    return v;
}

bool fake_gpio_is_output(unsigned offset)
{
    pthread_mutex_lock(&fake_lock);
    bool v = fake_lines[offset].requested && fake_lines[offset].output;
    pthread_mutex_unlock(&fake_lock);
    return v;
}

int fake_gpio_value(unsigned offset)
{
    pthread_mutex_lock(&fake_lock);
    int v = fake_lines[offset].value;
    pthread_mutex_unlock(&fake_lock);
    return v;
}

unsigned fake_gpio_rises(unsigned offset)
{
    pthread_mutex_lock(&fake_lock);
    unsigned v = fake_lines[offset].rises;
    pthread_mutex_unlock(&fake_lock);
    return v;
}

unsigned fake_gpio_requested_count(void)
{
    unsigned n = 0u;
    pthread_mutex_lock(&fake_lock);
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        n += fake_lines[i].requested ? 1u : 0u;
    }
    pthread_mutex_unlock(&fake_lock);
    return n;
}

/* ---- lhal/gpio_if.h ------------------------------------------------------------------ */

int gpio_chip_open(const char *name, gpio_chip_t **chip, char *err, size_t errlen)
{
    if (fake_chip_missing) {
        snprintf(err, errlen, "cannot open GPIO chip '%s': No such file or directory", name);
        errno = ENOENT;
        return -1;
    }
    *chip = &fake_chip;
    return 0;
}

const char *gpio_chip_describe(gpio_chip_t *chip)
{
    (void)chip;
    return "fakechip0 [fake]";
}

unsigned gpio_chip_lines(gpio_chip_t *chip)
{
    (void)chip;
    return FAKE_GPIO_LINES;
}

void gpio_chip_close(gpio_chip_t *chip)
{
    if (chip == NULL) {
        return;
    }
    pthread_mutex_lock(&fake_lock);
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        fake_line_t *l = &fake_lines[i];
        if (l->requested) {
            fake_close_pipes(l);
            l->requested = false;
            l->n = 0u;
        }
    }
    pthread_mutex_unlock(&fake_lock);
}

static int fake_request(unsigned offset, bool output, int value, gpio_line_t **line, char *err,
                        size_t errlen)
{
    if (offset >= FAKE_GPIO_LINES) {
        snprintf(err, errlen, "line %u does not exist on fakechip0 (%u lines)", offset, FAKE_GPIO_LINES);
        errno = EINVAL;
        return -1;
    }
    pthread_mutex_lock(&fake_lock);
    fake_line_t *l = &fake_lines[offset];
    int rc = 0;
    if (l->busy_user[0] != '\0' || l->requested) {
        snprintf(err, errlen, "line %u is in use by '%s'", offset,
                 l->busy_user[0] != '\0' ? l->busy_user : "sonarslam");
        errno = EBUSY;
        rc = -1;
    } else if (!output && pipe2(l->pipe, O_NONBLOCK | O_CLOEXEC) != 0) {
        snprintf(err, errlen, "pipe: %s", strerror(errno));
        rc = -1;
    } else {
        l->requested = true;
        l->output = output;
        l->edges = !output;
        if (output) {
            l->value = value;
        }
        *line = &fake_handles[offset];
    }
    pthread_mutex_unlock(&fake_lock);
    return rc;
}

int gpio_line_output(gpio_chip_t *chip, unsigned offset, int value, gpio_line_t **line,
                     char *err, size_t errlen)
{
    (void)chip;
    return fake_request(offset, true, value, line, err, errlen);
}

int gpio_line_edges(gpio_chip_t *chip, unsigned offset, lconf_bias_t bias, gpio_line_t **line,
                    char *err, size_t errlen)
{
    (void)chip;
    (void)bias;
    return fake_request(offset, false, 0, line, err, errlen);
}

int gpio_line_set(gpio_line_t *line, int value)
{
    pthread_mutex_lock(&fake_lock);
    fake_line_t *l = &fake_lines[line->offset];
    if (l->value == 0 && value != 0) {
        l->rises++;
    }
    l->value = value != 0;
    pthread_mutex_unlock(&fake_lock);
    return 0;
}

int gpio_line_get(gpio_line_t *line)
{
    return fake_gpio_value(line->offset);
}

int gpio_line_fd(gpio_line_t *line)
{
    pthread_mutex_lock(&fake_lock);
    int fd = fake_lines[line->offset].pipe[0];
    pthread_mutex_unlock(&fake_lock);
    return fd;
}

int gpio_line_read_edges(gpio_line_t *line, uint8_t src, edgeq_edge_t *out, size_t max)
{
    pthread_mutex_lock(&fake_lock);
    fake_line_t *l = &fake_lines[line->offset];
    size_t n = 0u;
    char drain[FAKE_EDGES_MAX];
    while (n < max && l->n > 0u) {
        out[n] = l->queue[l->head];
        out[n].src = src;
        l->head = (l->head + 1u) % FAKE_EDGES_MAX;
        l->n--;
        n++;
    }
    if (n > 0u) {
        (void)!read(l->pipe[0], drain, n);
    }
    pthread_mutex_unlock(&fake_lock);
    return (int)n;
}
