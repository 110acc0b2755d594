/* SPDX-License-Identifier: MIT */
/* Pose correction: its state, and the handover to the tick: what the background loop
 * publishes after each reading (localize.c maps them), which the tick adopts
 * (loc_adopt(), inline in slam/localize.h). */
#include "loc_tick.h"

#include <string.h>

#include "loc_filter.h"
#include "loc_hold.h"

void loc_init(loc_t *l, const slam_config_t *cfg)
{
    memset(l, 0, sizeof *l);
    l->on = cfg->localize != 0u;
    /* No correction: cos 0 is one, the rest is zero. */
    l->tick.pub.c = FIX_Q30_ONE;
    l->tick.corr.c = FIX_Q30_ONE;
    l->tick.pub_ahead[0] = LOC_AHEAD_NONE;
    l->tick.ahead[0] = LOC_AHEAD_NONE;
    loc_filter_init(&l->filter);
    loc_hold_init(&l->hold, cfg);
}

void loc_tick_publish(loc_tick_t *t, const loc_corr_t *corr, const int32_t ahead[2])
{
    t->pub = *corr;
    t->pub_ahead[0] = ahead[0];
    t->pub_ahead[1] = ahead[1];
}
