/* SPDX-License-Identifier: MIT */
/* The simulated robot's lifetime, its truth, and the period that ties its models together. */
#include <math.h>
#include <stdlib.h>

#include "sim_internal.h"

sim_t *sim_create(const room_t *room, const sim_params_t *p, const sim_errors_t *e, uint64_t seed)
{
    if (room == NULL || sim_params_check(p, e, NULL) != 0 ||
        !room_disc_free(room, room->start_x, room->start_y, p->body_radius_m)) {
        return NULL;
    }
    sim_t *s = calloc(1u, sizeof *s);
    if (s == NULL) {
        return NULL;
    }
    s->room = room;
    s->p = *p;
    s->e = *e;
    if (sim_sonar_init(s, seed) != 0) {
        sim_destroy(s);
        return NULL;
    }
    sim_body_init(s, room->start_x, room->start_y, room->start_th, seed);
    sim_servo_init(s);
    sim_faults_init(s, seed);
    return s;
}

void sim_destroy(sim_t *s)
{
    if (s != NULL) {
        sim_sonar_free(s);
        free(s);
    }
}

sim_truth_t sim_truth(const sim_t *s)
{
    const sim_body_t *b = &s->body;
    return (sim_truth_t){
        .x = b->x,
        .y = b->y,
        .th = b->th,
        .servo_deg = s->servo[0].deg,
        .wheel_mps = {b->omega[0] * b->r_act[0], b->omega[1] * b->r_act[1]},
        .collisions = b->collisions,
        .ticks_missed = s->faults.ticks_missed,
        .contact = b->contact,
        .time_us = s->time_us,
        .ticks = s->ticks,
    };
}

int sim_place(sim_t *s, double x, double y, double th)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(th) ||
        !room_disc_free(s->room, x, y, s->p.body_radius_m)) {
        return -1;
    }
    sim_body_place(s, x, y, th);
    return 0;
}

void sim_step(sim_t *s)
{
    double turns[2];
    double common = sim_body_step(s, turns);
    double servo_before = s->servo[0].deg;
    for (uint32_t i = 0; i < s->p.servos; i++) {
        sim_servo_step(&s->servo[i]);
    }
    if (s->faults.episodes) {
        sim_faults_step(s, turns, common, servo_before);
    }
    s->time_us += HAL_TICK_PERIOD_US;
    s->ticks++;
}
