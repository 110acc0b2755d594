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
#include <sys/mman.h>
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
    bool kill_reader;
    int value;
    unsigned rises;
    char busy_user[32];
    int pipe[2];
    edgeq_edge_t queue[FAKE_EDGES_MAX];
    size_t head;
    size_t n;
} fake_line_t;

/* In memory shared with the processes forked from here, so a test can watch the lines of a
 * program it runs in a child. The lock is robust: a child that ends holding it (killed by
 * a signal) does not leave it held. */
typedef struct {
    pthread_mutex_t lock;
    fake_line_t lines[FAKE_GPIO_LINES];
    bool chip_missing;
} fake_shared_t;

static fake_shared_t *fake;
static struct gpio_line fake_handles[FAKE_GPIO_LINES];
static struct gpio_chip fake_chip;

static void fake_lock(void)
{
    if (pthread_mutex_lock(&fake->lock) == EOWNERDEAD) {
        pthread_mutex_consistent(&fake->lock);
    }
}

static void fake_unlock(void)
{
    pthread_mutex_unlock(&fake->lock);
}

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
    if (fake == NULL) {
        fake = mmap(NULL, sizeof *fake, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (fake == MAP_FAILED) {
            perror("fake_gpio: mmap");
            abort();
        }
        pthread_mutexattr_t a;
        pthread_mutexattr_init(&a);
        pthread_mutexattr_setpshared(&a, PTHREAD_PROCESS_SHARED);
        pthread_mutexattr_setrobust(&a, PTHREAD_MUTEX_ROBUST);
        pthread_mutex_init(&fake->lock, &a);
        pthread_mutexattr_destroy(&a);
        for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
            fake->lines[i].pipe[0] = fake->lines[i].pipe[1] = -1;
        }
    }
    fake_lock();
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        fake_close_pipes(&fake->lines[i]);
        memset(&fake->lines[i], 0, sizeof fake->lines[i]);
        fake->lines[i].pipe[0] = fake->lines[i].pipe[1] = -1;
        fake_handles[i].offset = i;
    }
    fake->chip_missing = false;
    fake_unlock();
}

void fake_gpio_no_chip(void)
{
    fake->chip_missing = true;
}

void fake_gpio_busy(unsigned offset, const char *user)
{
    fake_lock();
    snprintf(fake->lines[offset].busy_user, sizeof fake->lines[offset].busy_user, "%s", user);
    fake_unlock();
}

void fake_gpio_level(unsigned offset, bool high)
{
    fake_lock();
    fake->lines[offset].value = high;
    fake_unlock();
}

void fake_gpio_edges(const fake_edge_t *edges, unsigned n)
{
    fake_lock();
    for (unsigned i = 0u; i < n; i++) {
        fake_line_t *l = &fake->lines[edges[i].offset];
        if (l->requested && l->edges && l->n < FAKE_EDGES_MAX) {
            l->queue[(l->head + l->n) % FAKE_EDGES_MAX] =
                (edgeq_edge_t){.ts_ns = edges[i].ts_ns, .rising = edges[i].rising};
            l->n++;
            l->value = edges[i].rising;
        }
    }
    /* Wake the reader only when everything is queued. */
    for (unsigned i = 0u; i < n; i++) {
        fake_line_t *l = &fake->lines[edges[i].offset];
        if (l->requested && l->edges) {
            const char byte = 1;
            (void)!write(l->pipe[1], &byte, 1u);
        }
    }
    fake_unlock();
}

void fake_gpio_edge(unsigned offset, uint64_t ts_ns, bool rising)
{
    const fake_edge_t e = {offset, ts_ns, rising};
    fake_gpio_edges(&e, 1u);
}

bool fake_gpio_requested(unsigned offset)
{
    fake_lock();
    bool v = fake->lines[offset].requested;
    fake_unlock();
    return v;
}

bool fake_gpio_is_output(unsigned offset)
{
    fake_lock();
    bool v = fake->lines[offset].requested && fake->lines[offset].output;
    fake_unlock();
    return v;
}

int fake_gpio_value(unsigned offset)
{
    fake_lock();
    int v = fake->lines[offset].value;
    fake_unlock();
    return v;
}

unsigned fake_gpio_rises(unsigned offset)
{
    fake_lock();
    unsigned v = fake->lines[offset].rises;
    fake_unlock();
    return v;
}

void fake_gpio_kill_reader(unsigned offset)
{
    fake_lock();
    fake->lines[offset].kill_reader = true;
    fake_unlock();
}

unsigned fake_gpio_requested_count(void)
{
    unsigned n = 0u;
    fake_lock();
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        n += fake->lines[i].requested ? 1u : 0u;
    }
    fake_unlock();
    return n;
}

/* ---- lhal/gpio_if.h ------------------------------------------------------------------ */

int gpio_chip_open(const char *name, gpio_chip_t **chip, char *err, size_t errlen)
{
    if (fake->chip_missing) {
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
    fake_lock();
    for (unsigned i = 0u; i < FAKE_GPIO_LINES; i++) {
        fake_line_t *l = &fake->lines[i];
        if (l->requested) {
            fake_close_pipes(l);
            l->requested = false;
            l->n = 0u;
        }
    }
    fake_unlock();
}

static int fake_request(unsigned offset, bool output, int value, gpio_line_t **line, char *err,
                        size_t errlen)
{
    if (offset >= FAKE_GPIO_LINES) {
        snprintf(err, errlen, "line %u does not exist on fakechip0 (%u lines)", offset,
                 FAKE_GPIO_LINES);
        errno = EINVAL;
        return -1;
    }
    fake_lock();
    fake_line_t *l = &fake->lines[offset];
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
    fake_unlock();
    return rc;
}

int gpio_line_output(gpio_chip_t *chip, unsigned offset, int value, gpio_line_t **line, char *err,
                     size_t errlen)
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
    fake_lock();
    fake_line_t *l = &fake->lines[line->offset];
    if (l->value == 0 && value != 0) {
        l->rises++;
    }
    l->value = value != 0;
    fake_unlock();
    return 0;
}

int gpio_line_get(gpio_line_t *line)
{
    return fake_gpio_value(line->offset);
}

int gpio_line_fd(gpio_line_t *line)
{
    fake_lock();
    int fd = fake->lines[line->offset].pipe[0];
    fake_unlock();
    return fd;
}

int gpio_line_read_edges(gpio_line_t *line, uint8_t src, edgeq_edge_t *out, size_t max)
{
    fake_lock();
    fake_line_t *l = &fake->lines[line->offset];
    if (l->kill_reader) {
        l->kill_reader = false;
        fake_unlock();
        pthread_exit(NULL);
    }
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
    fake_unlock();
    return (int)n;
}
