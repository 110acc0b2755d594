/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Quadrature decoding of one wheel encoder: the standard 4x state table.
 *
 * The state is the levels of the two lines, (A << 1) | B. Going forward, A leads B:
 * 00 -> 10 -> 11 -> 01 -> 00, one count per edge of either line (4 counts per encoder
 * cycle); backwards the sequence reverses. A change of both lines at once cannot happen
 * on a working encoder and is counted as illegal. An inverted wheel (mounted mirrored)
 * counts the other way, so the count always grows when the wheel rolls the robot forward.
 *
 * Lost edges (the kernel's 16-event queue of a line overflowed): an edge that repeats its
 * line's level says that the opposite edge in between was lost, and the edges of the
 * other line since then were decoded against a stale level, each the wrong way. The
 * decoder then puts the lost edge where a turning wheel's edges alternate (right after
 * the other line's first edge; before it when the line had no edge since the start),
 * counts again what followed it, and counts the loss. So a steady run with one lost edge
 * counts as if none were lost, and a lost edge never counts backwards once its line's
 * next edge has come.
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
    uint32_t illegal; /**< both lines changed at once, or an edge was lost */
    /* Per line (QUAD_A, QUAD_B), the other line's edges since this line's last edge: */
    bool seen[2];         /**< this line had an edge since quad_init() */
    uint8_t since[2];     /**< how many: 0, 1, or 2 for more */
    uint8_t pre_state[2]; /**< the state before the first of them */
    uint8_t mid_state[2]; /**< the state right after the first of them */
    int32_t first[2];     /**< what the first added to the count */
    int32_t late[2];      /**< what the ones after the first added */
} quad_t;

/** Start from the lines' present levels with a zero count. */
void quad_init(quad_t *q, bool a, bool b, bool invert);

/**
 * Move to a new state (both levels, e.g. read back after a resynchronisation). It does
 * not take part in the reconstruction of lost edges.
 * @return the count's change: +1, -1, or 0 (no change, or an illegal transition)
 */
int quad_step(quad_t *q, uint8_t new_state);

/**
 * One edge of one line.
 * @param level  the line's level after the edge (true: a rising edge)
 * @return the count's change: ±1 for an edge, or the correction when it reveals a lost
 *         edge (from -4 up to 4 in a steady run; more when it recounts a reversal)
 */
int quad_edge(quad_t *q, quad_line_t line, bool level);

#endif /* LHAL_QUAD_H */
