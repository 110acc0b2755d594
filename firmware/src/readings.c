/* SPDX-License-Identifier: MIT */
/* The readings queue between the tick and robot_idle(), and a reading mapped without the
 * pose correction. */
#include "slam/readings.h"

#include <string.h>

static void count(uint32_t *c)
{
    if (*c != UINT32_MAX) {
        (*c)++;
    }
}

void readq_init(readq_t *q, const slam_config_t *cfg)
{
    memset(q, 0, sizeof *q);
    q->deferred = cfg->localize != 0u || cfg->om_mode == OM_MODE_EVIDENCE;
}

readq_post_t readq_post(readq_t *q, const readq_reading_t *rd)
{
    /* Finished up to this one: then what the loop published last is for this reading. A
     * full ring means seven readings unfinished, so a lost reading is late too. Only what
     * the ring takes is posted: a lost reading is never finished, and counting it would
     * leave every later reading late. */
    readq_post_t out = q->drained == q->posted ? READQ_CURRENT : READQ_LATE;
    uint8_t next = (uint8_t)((q->head + 1u) % READQ_SLOTS);
    if (next != q->tail) {
        q->slot[q->head] = *rd;
        q->head = next;
        q->posted++;
    } else {
        count(&q->dropped);
        out = READQ_DROPPED;
    }
    if (out != READQ_CURRENT) {
        count(&q->late);
    }
    return out;
}

bool readq_take(readq_t *q, readq_reading_t *rd)
{
    uint8_t t = q->tail;
    if (t == q->head) {
        return false;
    }
    *rd = q->slot[t];
    q->tail = (uint8_t)((t + 1u) % READQ_SLOTS);
    return true;
}

void readq_done(readq_t *q)
{
    q->drained++;
}

void readq_map(const readq_reading_t *rd, mapper_t *m, grid_t *g)
{
    if (rd->echo) {
        (void)mapper_reading(m, g, &rd->ping, rd->servo, rd->range_um);
    } else {
        mapper_timeout(m, g, &rd->ping);
    }
}
