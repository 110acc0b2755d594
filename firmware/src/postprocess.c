/* SPDX-License-Identifier: MIT */
/* Map post-processing (threshold, template, insert) in place with two rows of scratch. */
#include "slam/postprocess.h"

#include <stdbool.h>
#include <string.h>

void post_threshold(uint8_t *map, size_t w, size_t h, uint8_t threshold, uint8_t om_max)
{
    for (size_t i = 0; i < w * h; i++) {
        map[i] = map[i] <= threshold ? 0u : om_max;
    }
}

/* The three rows around row y as they were before the step: above and this row come from
 * the scratch copies, below is still untouched in the map. NULL rows lie beyond the border. */
typedef struct {
    const uint8_t *above;
    const uint8_t *here;
    const uint8_t *below;
    size_t w;
} post_rows_t;

static bool occupied(const uint8_t *row, size_t x, size_t w)
{
    return row != NULL && x < w && row[x] != 0u;
}

/* x - 1 wraps to SIZE_MAX at the left border, which occupied() treats as outside. */
static unsigned neighbours8(const post_rows_t *r, size_t x)
{
    unsigned n = 0;
    const uint8_t *rows[3] = {r->above, r->here, r->below};
    for (unsigned i = 0; i < 3u; i++) {
        n += occupied(rows[i], x - 1u, r->w) + occupied(rows[i], x + 1u, r->w);
        if (i != 1u) {
            n += occupied(rows[i], x, r->w);
        }
    }
    return n;
}

static bool between_opposites(const post_rows_t *r, size_t x)
{
    size_t w = r->w;
    return (occupied(r->here, x - 1u, w) && occupied(r->here, x + 1u, w)) ||
           (occupied(r->above, x, w) && occupied(r->below, x, w)) ||
           (occupied(r->above, x - 1u, w) && occupied(r->below, x + 1u, w)) ||
           (occupied(r->above, x + 1u, w) && occupied(r->below, x - 1u, w));
}

typedef enum { POST_TEMPLATE, POST_INSERT } post_op_t;

/* Runs one neighbourhood operation over the map, row by row, deciding every cell from
 * the map as it was before the operation. */
static void neighbourhood_pass(uint8_t *map, size_t w, size_t h, post_op_t op, uint8_t value,
                               uint8_t *scratch)
{
    uint8_t *copy[2] = {scratch, scratch + w};
    post_rows_t r = {.above = NULL, .w = w};
    for (size_t y = 0; y < h; y++) {
        uint8_t *row = map + y * w;
        uint8_t *here = copy[y & 1u];
        memcpy(here, row, w);
        r.here = here;
        r.below = y + 1u < h ? row + w : NULL;
        for (size_t x = 0; x < w; x++) {
            if (op == POST_TEMPLATE) {
                if (here[x] != 0u && neighbours8(&r, x) < value) {
                    row[x] = 0u;
                }
            } else if (here[x] == 0u && between_opposites(&r, x)) {
                row[x] = value;
            }
        }
        r.above = here;
    }
}

void post_template(uint8_t *map, size_t w, size_t h, uint8_t k, uint8_t *scratch)
{
    neighbourhood_pass(map, w, h, POST_TEMPLATE, k, scratch);
}

void post_insert(uint8_t *map, size_t w, size_t h, uint8_t om_max, uint8_t *scratch)
{
    neighbourhood_pass(map, w, h, POST_INSERT, om_max, scratch);
}

int post_run(const uint8_t *om, uint8_t *out, size_t w, size_t h, const post_params_t *p,
             uint8_t *scratch)
{
    if (w == 0u || h == 0u || p->k > 8u || p->insert > 1u || p->om_max == 0u) {
        return SLAM_EINVAL;
    }
    memcpy(out, om, w * h);
    post_threshold(out, w, h, p->threshold, p->om_max);
    if (p->k > 0u) {
        post_template(out, w, h, p->k, scratch);
    }
    if (p->insert != 0u) {
        post_insert(out, w, h, p->om_max, scratch);
    }
    return SLAM_OK;
}
