/* SPDX-License-Identifier: MIT */
/* Pose correction: its state, and the tick's side of it: each reading handed to the
 * background loop (localize.c drains them), and the correction taken back. loc_apply(),
 * which the tick calls too, stays in localize.c with the matching that shares its
 * arithmetic (inlined there: flash). */
#include "slam/localize.h"

#include <string.h>

#include "loc_internal.h"
#include "loc_kf.h"

void loc_count(uint32_t *c)
{
    if (*c != UINT32_MAX) {
        (*c)++;
    }
}

void loc_init(loc_t *l, const slam_config_t *cfg)
{
    memset(l, 0, sizeof *l);
    l->on = cfg->localize != 0u;
    l->deferred = l->on || cfg->om_mode == OM_MODE_EVIDENCE;
    /* LOC_REACH_CELLS within 2^15 units, the same for every grid size (the host's grid and
     * the MCU's then hold a point alike): 1 mm for 50 mm cells. Cells of 5 mm to 1 m make
     * the reach 2^16 µm or more and keep it within 32 bits. */
    l->point_shift = (uint8_t)(17 - __builtin_clz(LOC_REACH_CELLS * cfg->cell_um));
    /* No correction: cos 0 is one, the rest is zero. */
    l->corr.c = FIX_Q30_ONE;
    l->pub.c = FIX_Q30_ONE;
    l->tick_corr.c = FIX_Q30_ONE;
    l->placed.c = FIX_Q30_ONE;
    l->clear_um = (int32_t)cfg->clearance_um;
    l->pub_ahead[0] = LOC_AHEAD_NONE;
    l->tick_ahead[0] = LOC_AHEAD_NONE;
    lkf_init(&l->cov);
}

bool loc_post(loc_t *l, const loc_reading_t *rd)
{
    bool queued = false;
    uint8_t next = (uint8_t)((l->head + 1u) % LOC_QUEUE);
    if (next != l->tail) {
        l->queue[l->head] = *rd;
        l->head = next;
        queued = true;
    } else {
        loc_count(&l->dropped);
    }
    /* The correction after the reading before this one, which every backend has by now
     * unless its background loop fell behind (or is writing it right now). */
    uint32_t gen = l->pub_gen;
    if ((gen & 1u) == 0u && l->pub_seq == l->posted) {
        l->tick_corr = l->pub;
        l->tick_ahead[0] = l->pub_ahead[0];
        l->tick_ahead[1] = l->pub_ahead[1];
    } else {
        loc_count(&l->late);
    }
    l->posted++;
    return queued;
}
