/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Orders the edges of lines that the kernel queues separately, by their timestamps.
 *
 * The GPIO character device (v1 ABI, libgpiod 1.6) gives every requested line its own
 * event queue, so the edges of an encoder's A and B lines arrive through two file
 * descriptors. Read one after the other, an edge of B can be seen before an earlier edge
 * of A that was queued in between, and a quadrature decoder fed in that order counts the
 * wrong way. The queue holds edges back until they are older than a cutoff (the time the
 * reading began, minus a margin for the kernel's own queueing delay), then releases them
 * in timestamp order. Ties keep their arrival order.
 *
 * Timestamps are the kernel's, in ns (CLOCK_MONOTONIC since Linux 5.7). No locking: one
 * thread owns a queue.
 */
#ifndef LHAL_EDGEQ_H
#define LHAL_EDGEQ_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** One edge of one line. */
typedef struct {
    uint64_t ts_ns; /**< kernel timestamp of the edge */
    uint8_t src;    /**< which line, as the caller numbers them */
    bool rising;    /**< true: low to high */
} edgeq_edge_t;

/** Edges a queue can hold back. */
#define EDGEQ_MAX 256u

/** A queue of held-back edges, oldest first. */
typedef struct {
    edgeq_edge_t e[EDGEQ_MAX];
    size_t n;
} edgeq_t;

/** Empty the queue. */
void edgeq_init(edgeq_t *q);

/**
 * Add an edge in timestamp order (after any edge with the same timestamp).
 * @retval true   added
 * @retval false  the queue is full; nothing changed (release edges first)
 */
bool edgeq_push(edgeq_t *q, edgeq_edge_t e);

/**
 * Take the oldest edges with ts_ns <= cutoff_ns, in order.
 * @param cutoff_ns  UINT64_MAX releases everything
 * @param out        room for @p max edges
 * @return how many were taken
 */
size_t edgeq_pop_until(edgeq_t *q, uint64_t cutoff_ns, edgeq_edge_t *out, size_t max);

/** Whether the queue holds no edge. */
bool edgeq_empty(const edgeq_t *q);

#endif /* LHAL_EDGEQ_H */
