/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A fake of lhal/gpio_if.h for tests: one chip of FAKE_GPIO_LINES lines whose inputs the
 * test drives (levels, timestamped edges) and whose outputs it reads back. Edge lines have
 * a real pipe as their descriptor, so the backend's events thread polls them as it polls
 * the kernel's. Thread-safe, and shared with child processes forked after the first
 * fake_gpio_reset(), so a test sees the lines of a program it runs in a child; reset
 * before each test.
 */
#ifndef TEST_FAKE_GPIO_H
#define TEST_FAKE_GPIO_H

#include <stdbool.h>
#include <stdint.h>

#define FAKE_GPIO_LINES 32u

/** Forget every line; close their descriptors. */
void fake_gpio_reset(void);

/** The next gpio_chip_open() fails (no such chip). */
void fake_gpio_no_chip(void);

/** Requests of this line fail as if another program held it. */
void fake_gpio_busy(unsigned offset, const char *user);

/** An input's level before it is requested (read back by gpio_line_get()). */
void fake_gpio_level(unsigned offset, bool high);

/** Queue an edge on an edge line with a kernel timestamp; its level follows. */
void fake_gpio_edge(unsigned offset, uint64_t ts_ns, bool rising);

/** An edge of a line, for fake_gpio_edges(). */
typedef struct {
    unsigned offset;
    uint64_t ts_ns;
    bool rising;
} fake_edge_t;

/** Queue edges of several lines at once: a reader sees all of them or none. */
void fake_gpio_edges(const fake_edge_t *edges, unsigned n);

/** Whether a line is requested now. */
bool fake_gpio_requested(unsigned offset);

/** Whether a requested line is an output. */
bool fake_gpio_is_output(unsigned offset);

/** An output's level. */
int fake_gpio_value(unsigned offset);

/** How many times an output went from low to high. */
unsigned fake_gpio_rises(unsigned offset);

/** How many lines are requested now. */
unsigned fake_gpio_requested_count(void);

/** The next thread that reads this edge line's events ends there (pthread_exit). */
void fake_gpio_kill_reader(unsigned offset);

#endif /* TEST_FAKE_GPIO_H */
