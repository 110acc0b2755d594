/* SPDX-License-Identifier: MIT */
/* The ground truth as an exported map: solid obstacles filled, the outside unknown. */
#include <stdlib.h>

#include "hal_common/mapexport.h"
#include "host_sim.h"

#define REACHED 1u
#define OUTSIDE 2u

/* 4-connected flood over non-boundary cells from the seeds already marked in mark[]. */
static void flood(const map_geom_t *g, const uint8_t *truth, uint8_t *mark, uint8_t tag,
                  uint32_t *queue, size_t tail)
{
    size_t head = 0;
    while (head < tail) {
        uint32_t c = queue[head++];
        uint32_t x = c % g->a;
        uint32_t y = c / g->a;
        uint32_t next[4];
        size_t n = 0;
        if (x > 0u) {
            next[n++] = c - 1u;
        }
        if (x + 1u < g->a) {
            next[n++] = c + 1u;
        }
        if (y > 0u) {
            next[n++] = c - g->a;
        }
        if (y + 1u < g->b) {
            next[n++] = c + g->a;
        }
        for (size_t k = 0; k < n; k++) {
            if (mark[next[k]] == 0u && truth[next[k]] == 0u) {
                mark[next[k]] = tag;
                queue[tail++] = next[k];
            }
        }
    }
}

int truth_image(const map_geom_t *g, const uint8_t *truth, uint32_t start, uint8_t *out)
{
    size_t n = (size_t)g->a * g->b;
    uint8_t *mark = calloc(n, 1);
    uint32_t *queue = malloc(n * sizeof *queue);
    uint8_t *solid = malloc(n);
    if (mark == NULL || queue == NULL || solid == NULL) {
        free(mark);
        free(queue);
        free(solid);
        return -1;
    }
    size_t tail = 0;
    if (truth[start] == 0u) {
        mark[start] = REACHED;
        queue[tail++] = start;
    }
    flood(g, truth, mark, REACHED, queue, tail);
    tail = 0;
    for (uint32_t y = 0; y < g->b; y++) {
        for (uint32_t x = 0; x < g->a; x++) {
            uint32_t c = y * g->a + x;
            bool border = x == 0u || y == 0u || x + 1u == g->a || y + 1u == g->b;
            if (border && mark[c] == 0u && truth[c] == 0u) {
                mark[c] = OUTSIDE;
                queue[tail++] = c;
            }
        }
    }
    flood(g, truth, mark, OUTSIDE, queue, tail);
    /* Occupied: the boundaries and whatever neither flood reached; free inside the room. */
    for (size_t i = 0; i < n; i++) {
        solid[i] = (uint8_t)(truth[i] != 0u || mark[i] == 0u);
        mark[i] = (uint8_t)(mark[i] == REACHED || solid[i]); /* known */
    }
    mapx_trinary(OM_MODE_COUNT, mark, NULL, solid, g->a, g->b, out);
    free(mark);
    free(queue);
    free(solid);
    return 0;
}
