/* SPDX-License-Identifier: MIT */
/* The 4x quadrature state table, with illegal transitions and lost edges counted. */
#include "lhal/quad.h"

/* Index: old state << 2 | new state. 2 marks an illegal transition (both lines changed). */
static const int8_t quad_table[16] = {
    /* old 00 */ 0, -1, +1, 2,
    /* old 01 */ +1, 0, 2, -1,
    /* old 10 */ -1, 2, 0, +1,
    /* old 11 */ 2, +1, -1, 0,
};

void quad_init(quad_t *q, bool a, bool b, bool invert)
{
    q->state = (uint8_t)(((unsigned)a << 1) | (unsigned)b);
    q->invert = invert;
    q->count = 0u;
    q->edges = 0u;
    q->illegal = 0u;
}

int quad_step(quad_t *q, uint8_t new_state)
{
    new_state &= 3u;
    int d = quad_table[(q->state << 2) | new_state];
    q->state = new_state;
    if (d == 2) {
        q->illegal++;
        return 0;
    }
    if (q->invert) {
        d = -d;
    }
    q->count = (uint16_t)(q->count + (uint16_t)d);
    return d;
}

int quad_edge(quad_t *q, quad_line_t line, bool level)
{
    uint8_t bit = line == QUAD_A ? 2u : 1u;
    q->edges++;
    if (((q->state & bit) != 0u) == level) {
        /* The line is already at this level: the edge between was lost. */
        q->illegal++;
        return 0;
    }
    return quad_step(q, (uint8_t)(q->state ^ bit));
}
