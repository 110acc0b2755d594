/* SPDX-License-Identifier: MIT */
/* The ground truth as an exported map: solid obstacles filled, the outside unknown. */
#include <stdlib.h>

#include "hal_common/mapexport.h"
#include "host_sim.h"

#define REACHED 1u
#define OUTSIDE 2u

/* A cell a flood may enter: not a boundary, not marked yet. */
static bool open_cell(const uint8_t *truth, const uint8_t *mark, uint32_t c)
{
    return mark[c] == 0u && truth[c] == 0u;
}

/* Seeds a flood of the row y from the open cells of columns l..r: one a run of them. */
static size_t seed_row(const map_geom_t *g, const uint8_t *truth, uint8_t *mark, uint8_t tag,
                       uint32_t *stack, size_t top, uint32_t y, uint32_t l, uint32_t r)
{
    bool run = false;
    for (uint32_t x = l; x <= r; x++) {
        uint32_t c = y * g->a + x;
        bool open = open_cell(truth, mark, c);
        if (open && !run) {
            mark[c] = tag;
            stack[top++] = c;
        }
        run = open;
    }
    return top;
}

/*
 * 4-connected flood over non-boundary cells from the seeds already marked in mark[] (and
 * on the stack), a row's span at a time: each span marks the open cells left and right of
 * its seed, then seeds the rows above and below it. Every marked cell lies in one span, and
 * every span looks at its four sides, so it marks what a cell-by-cell flood marks.
 */
static void flood(const map_geom_t *g, const uint8_t *truth, uint8_t *mark, uint8_t tag,
                  uint32_t *stack, size_t top)
{
    while (top > 0u) {
        uint32_t c = stack[--top];
        uint32_t y = c / g->a;
        uint32_t l = c - y * g->a;
        uint32_t r = l;
        while (l > 0u && open_cell(truth, mark, y * g->a + l - 1u)) {
            l--;
            mark[y * g->a + l] = tag;
        }
        while (r + 1u < g->a && open_cell(truth, mark, y * g->a + r + 1u)) {
            r++;
            mark[y * g->a + r] = tag;
        }
        if (y > 0u) {
            top = seed_row(g, truth, mark, tag, stack, top, y - 1u, l, r);
        }
        if (y + 1u < g->b) {
            top = seed_row(g, truth, mark, tag, stack, top, y + 1u, l, r);
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
