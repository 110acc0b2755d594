/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The few GPIO operations the backend needs, so that one file holds every libgpiod call
 * (src/gpio_gpiod.c, the 1.6 API) and a move to libgpiod 2.x replaces that file alone.
 * Tests link a fake in its place.
 *
 * Lines belong to one chip and are released when it is closed. Edge lines deliver both
 * edges with kernel timestamps through a pollable descriptor. Functions that fail set
 * errno and, where they take one, write a message naming the line and the reason.
 */
#ifndef LHAL_GPIO_IF_H
#define LHAL_GPIO_IF_H

#include <stddef.h>

#include "lhal/edgeq.h"
#include "lhal/lconf.h"

/** The most lines one chip hands out (the backend uses LCONF_LINES at most). */
#define GPIO_IF_LINES_MAX 24u
_Static_assert(LCONF_LINES <= GPIO_IF_LINES_MAX, "a chip hands out every line robot.conf wires");

typedef struct gpio_chip gpio_chip_t;
typedef struct gpio_line gpio_line_t;

/**
 * Open a GPIO chip by name ("gpiochip0"), path, label ("pinctrl-bcm2711") or number.
 * @return 0, or -1 with err
 */
int gpio_chip_open(const char *name, gpio_chip_t **chip, char *err, size_t errlen);

/** "gpiochip0 [pinctrl-bcm2711]", for messages. */
const char *gpio_chip_describe(gpio_chip_t *chip);

/** How many lines the chip has. */
unsigned gpio_chip_lines(gpio_chip_t *chip);

/** Release every line and close the chip (NULL is ignored). */
void gpio_chip_close(gpio_chip_t *chip);

/**
 * Request a line as an output.
 * @param value  its level from the moment it is requested
 * @param line   out: a handle owned by the chip, valid until gpio_chip_close()
 * @return 0, or -1 with err (e.g. "line 17 is in use by 'foo'")
 */
int gpio_line_output(gpio_chip_t *chip, unsigned offset, int value, gpio_line_t **line, char *err,
                     size_t errlen);

/**
 * Request a line as an input with both-edge events.
 * @return 0, or -1 with err
 */
int gpio_line_edges(gpio_chip_t *chip, unsigned offset, lconf_bias_t bias, gpio_line_t **line,
                    char *err, size_t errlen);

/** Drive an output line. @return 0, or -1 (errno set) */
int gpio_line_set(gpio_line_t *line, int value);

/** Read a line's level. @return 0 or 1, or -1 (errno set) */
int gpio_line_get(gpio_line_t *line);

/** The descriptor that polls readable when an edge line has edges queued. */
int gpio_line_fd(gpio_line_t *line);

/**
 * Take the queued edges of an edge line, oldest first, without blocking.
 * @param src  stored in each edge's src
 * @return how many (up to max; 0 when none is queued), or -1 (errno set)
 */
int gpio_line_read_edges(gpio_line_t *line, uint8_t src, edgeq_edge_t *out, size_t max);

#endif /* LHAL_GPIO_IF_H */
