/* SPDX-License-Identifier: MIT */
/* The 4x quadrature state table, with illegal transitions and lost edges counted. */
#include "lhal/quad.h"

/* Index: old state << 2 | new state. 2 marks an illegal transition (both lines changed). */
static const int8_t quad_table[16] = {
    /* old 00 */ 0,  -1, +1, 2,
    /* old 01 */ +1, 0,  2,  -1,
    /* old 10 */ -1, 2,  0,  +1,
    /* old 11 */ 2,  +1, -1, 0,
};

void quad_init(quad_t *q, bool a, bool b, bool invert)
{
    uint8_t s = (uint8_t)(((unsigned)a << 1) | (unsigned)b);
    *q = (quad_t){.state = s, .invert = invert, .pre_state = {s, s}};
}

/* The count's change of a one-line transition, for this wheel's direction. */
static int quad_move(const quad_t *q, uint8_t from, uint8_t to)
{
    int d = quad_table[(from << 2) | to];
    return q->invert ? -d : d;
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

/* The line is already at this level: its opposite edge in between was lost. Put the lost
 * edge where the edges of a turning wheel alternate: right after the other line's first
 * edge since this line's last one, or before it when this line had no edge since the
 * start and the other line one edge. Count again the other line's edges after the lost
 * one (they were decoded against the stale level), and the lost edge and this one. With
 * no edge of the other line in between, the two cancel. */
static int quad_lost(quad_t *q, unsigned x, uint8_t bit)
{
    q->illegal++;
    if (q->since[x] == 0u) {
        return 0;
    }
    bool before_first = !q->seen[x] && q->since[x] == 1u;
    uint8_t at = before_first ? q->pre_state[x] : q->mid_state[x];
    int32_t d = -2 * (q->late[x] + (before_first ? q->first[x] : 0));
    d += quad_move(q, at, (uint8_t)(at ^ bit));
    d += quad_move(q, (uint8_t)(q->state ^ bit), q->state);
    q->count = (uint16_t)(q->count + (uint16_t)d);
    return (int)d;
}

int quad_edge(quad_t *q, quad_line_t line, bool level)
{
    unsigned x = line == QUAD_A ? 0u : 1u;
    uint8_t bit = line == QUAD_A ? 2u : 1u;
    q->edges++;
    int d = ((q->state & bit) != 0u) == level ? quad_lost(q, x, bit)
                                              : quad_step(q, (uint8_t)(q->state ^ bit));
    /* This line starts over; for the other one, this is one more edge since its last. */
    q->seen[x] = true;
    q->since[x] = 0u;
    q->pre_state[x] = q->state;
    q->late[x] = 0;
    unsigned y = x ^ 1u;
    if (q->since[y] == 0u) {
        q->since[y] = 1u;
        q->mid_state[y] = q->state;
        q->first[y] = d;
    } else {
        q->since[y] = 2u;
        q->late[y] += d;
    }
    return d;
}
