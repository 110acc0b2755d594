/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Quadrature decoding of one wheel encoder: the standard 4x state table.
 *
 * The state is the levels of the two lines, (A << 1) | B. Going forward, A leads B:
 * 00 -> 10 -> 11 -> 01 -> 00, one count per edge of either line (4 counts per encoder
 * cycle); backwards the sequence reverses. A change of both lines at once cannot happen
 * on a working encoder and is counted as illegal, as is an edge that repeats its line's
 * level (the opposite edge in between was lost, e.g. when the kernel's event queue
 * overflowed); neither moves the count. An inverted wheel (mounted mirrored) counts the
 * other way, so the count always grows when the wheel rolls the robot forward.
 *
 * The count is the 16-bit wrapping counter the HAL reports. No locking: one thread owns a
 * decoder and publishes its count.
 */
#ifndef LHAL_QUAD_H
#define LHAL_QUAD_H

#include <stdbool.h>
#include <stdint.h>

/** The two lines of an encoder. */
typedef enum { QUAD_A = 0, QUAD_B = 1 } quad_line_t;

/** Decoder state and counters. */
typedef struct {
    uint8_t state;    /**< (A << 1) | B as last seen */
    bool invert;      /**< count the other way */
    uint16_t count;   /**< 4x counts, wrapping */
    uint32_t edges;   /**< edges fed */
    uint32_t illegal; /**< both lines changed at once, or an edge repeated its level */
} quad_t;

/** Start from the lines' present levels with a zero count. */
void quad_init(quad_t *q, bool a, bool b, bool invert);

/**
 * Move to a new state (both levels, e.g. read back after a resynchronisation).
 * @return the count's change: +1, -1, or 0 (no change, or an illegal transition)
 */
int quad_step(quad_t *q, uint8_t new_state);

/**
 * One edge of one line.
 * @param level  the line's level after the edge (true: a rising edge)
 * @return the count's change, as quad_step()
 */
int quad_edge(quad_t *q, quad_line_t line, bool level);

#endif /* LHAL_QUAD_H */
