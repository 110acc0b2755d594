/* SPDX-License-Identifier: MIT */
/* Orders the edges of separately queued lines by kernel timestamp before they are decoded. */
#include "lhal/edgeq.h"

#include <string.h>

void edgeq_init(edgeq_t *q)
{
    q->n = 0u;
}

bool edgeq_push(edgeq_t *q, edgeq_edge_t e)
{
    if (q->n == EDGEQ_MAX) {
        return false;
    }
    /* Edges nearly always arrive in order, so the search from the back is short. */
    size_t i = q->n;
    while (i > 0u && q->e[i - 1u].ts_ns > e.ts_ns) {
        q->e[i] = q->e[i - 1u];
        i--;
    }
    q->e[i] = e;
    q->n++;
    return true;
}

size_t edgeq_pop_until(edgeq_t *q, uint64_t cutoff_ns, edgeq_edge_t *out, size_t max)
{
    size_t k = 0u;
    while (k < q->n && k < max && q->e[k].ts_ns <= cutoff_ns) {
        out[k] = q->e[k];
        k++;
    }
    if (k > 0u) {
        memmove(q->e, q->e + k, (q->n - k) * sizeof q->e[0]);
        q->n -= k;
    }
    return k;
}

bool edgeq_empty(const edgeq_t *q)
{
    return q->n == 0u;
}
