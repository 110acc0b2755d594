/* SPDX-License-Identifier: MIT */
/* The simulated bump switches: arcs of the body that close while it touches something there. */
#include <math.h>

#include "sim_internal.h"

/* A switch closes within this much of the body's edge: its travel, m. The body stops within
 * a micrometre of what it ran into (sim_body.c) and keeps its contact until it is 1 mm away. */
#define SIM_BUMP_TRAVEL_M 0.002
/* Rays across an arc at most this far apart, deg: a flat surface met within half of it of its
 * normal is within a few micrometres of the body's edge along the ray. */
#define SIM_BUMP_STEP_DEG 2.0

uint8_t sim_bump_count(const sim_t *s)
{
    return (uint8_t)s->p.bumps;
}

/* Whether a surface lies within the switch's travel somewhere across its arc. */
static bool arc_touches(const sim_t *s, const sim_bump_t *b)
{
    const sim_body_t *body = &s->body;
    double reach = s->p.body_radius_m + SIM_BUMP_TRAVEL_M;
    double span = b->to_deg - b->from_deg;
    int n = (int)ceil(span / SIM_BUMP_STEP_DEG);
    for (int i = 0; i <= n; i++) {
        double a = body->th + (b->from_deg + span * (double)i / (double)n) * SIM_DEG;
        if (room_ray(s->room, body->x, body->y, a, reach, NULL) <= reach) {
            return true;
        }
    }
    return false;
}

int sim_bump_read(const sim_t *s, uint8_t bump, bool *pressed)
{
    if (s->p.bumps == 0u) {
        return HAL_ENOSYS;
    }
    if (bump >= s->p.bumps || pressed == NULL) {
        return HAL_EINVAL;
    }
    /* Only a body in contact presses a switch: one that merely passes near a wall does not. */
    *pressed = s->body.contact && arc_touches(s, &s->p.bump[bump]);
    return HAL_OK;
}
