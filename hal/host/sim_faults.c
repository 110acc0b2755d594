/* SPDX-License-Identifier: MIT */
/* The simulated faults: stuck echo, servo stall (of sonar and servo 0), stopped encoder, lost
 * ticks. */
#include "sim_internal.h"

/* An episode lasts this long, uniform, s. */
#define SIM_EPISODE_MIN_S 0.5
#define SIM_EPISODE_MAX_S 3.0

void sim_faults_init(sim_t *s, uint64_t seed)
{
    const sim_errors_t *e = &s->e;
    for (int f = 0; f < SIM_FAULTS; f++) {
        sim_rng_seed(&s->faults.rng[f], seed, (uint64_t)(SIM_STREAM_FAULTS + f));
    }
    s->faults.episodes =
        e->echo_stuck_per_s > 0.0 || e->servo_stall_per_s > 0.0 || e->encoder_stop_per_s > 0.0;
}

/* Perhaps begin an episode of fault f, which comes at @p rate a second. */
static bool begin_episode(sim_t *s, int f, double rate)
{
    sim_faults_t *ft = &s->faults;
    if (rate <= 0.0 || s->time_us < ft->until_us[f] ||
        sim_rng_unit(&ft->rng[f]) >= rate * SIM_DT_S) {
        return false;
    }
    double len =
        SIM_EPISODE_MIN_S + (SIM_EPISODE_MAX_S - SIM_EPISODE_MIN_S) * sim_rng_unit(&ft->rng[f]);
    ft->until_us[f] = s->time_us + (uint64_t)llround(len * 1e6);
    return true;
}

void sim_faults_step(sim_t *s, const double turns[2], double common, double servo_before)
{
    sim_faults_t *ft = &s->faults;
    if (s->time_us < ft->until_us[SIM_FAULT_ENCODER]) {
        int w = ft->stopped_wheel;
        s->body.enc[w] -= (turns[w] - common) * s->body.counts_per_rad;
    }
    if (s->time_us < ft->until_us[SIM_FAULT_SERVO]) {
        s->servo[0].deg = servo_before;
    }
    const double rates[3] = {s->e.echo_stuck_per_s, s->e.servo_stall_per_s,
                             s->e.encoder_stop_per_s};
    for (int f = 0; f < 3; f++) {
        if (begin_episode(s, f, rates[f]) && f == SIM_FAULT_ENCODER) {
            ft->stopped_wheel = sim_rng_unit(&ft->rng[f]) < 0.5 ? 0 : 1;
        }
    }
}

bool sim_ticks_lost(const sim_t *s)
{
    return s->e.tick_miss > 0.0;
}

uint64_t sim_ticks_missed(const sim_t *s)
{
    return s->faults.ticks_missed;
}

bool sim_tick_lost(sim_t *s)
{
    if (s->e.tick_miss <= 0.0 || sim_rng_unit(&s->faults.rng[SIM_FAULT_TICK]) >= s->e.tick_miss) {
        return false;
    }
    s->faults.ticks_missed++;
    return true;
}
