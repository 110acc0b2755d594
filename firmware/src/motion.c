/* SPDX-License-Identifier: MIT */
/* Wheel speed control: acceleration-limited set speeds, feed-forward plus PI per wheel. */
#include "slam/motion.h"

#include <string.h>

/* 1 mm/s is 10 µm per 10 ms tick. */
#define MOTION_UM_TICK_PER_MM_S 10
#define MOTION_ERR_MAX (1 << 17) /* 131 mm in a tick: far beyond any real wheel */
#define MOTION_SPEED_SHIFT 2u    /* log2(MOTION_SPEED_TICKS) */

void motion_init(motion_t *m, const slam_config_t *cfg)
{
    memset(m, 0, sizeof *m);
    /* a mm/s² changes the speed by a/10 µm/tick in one tick; never less than 1. */
    m->accel_um_tick2 = ((int32_t)cfg->accel_mm_s2 + 5) / 10;
    if (m->accel_um_tick2 < 1) {
        m->accel_um_tick2 = 1;
    }
    m->top_um_tick = (int32_t)cfg->top_speed_mm_s * MOTION_UM_TICK_PER_MM_S;
    m->kp_q8 = cfg->motion_kp_q8;
    m->ki_q8 = cfg->motion_ki_q8;
    m->integral_max_um = m->ki_q8 > 0 ? (MOTION_DUTY_MAX * 256) / m->ki_q8 : 0;
}

static int32_t clamp(int32_t v, int32_t lo, int32_t hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

void motion_set_target(motion_t *m, int32_t left_mm_s, int32_t right_mm_s)
{
    int32_t top_mm_s = m->top_um_tick / MOTION_UM_TICK_PER_MM_S;
    m->target_um_tick[ODOM_LEFT] = clamp(left_mm_s, -top_mm_s, top_mm_s) * MOTION_UM_TICK_PER_MM_S;
    m->target_um_tick[ODOM_RIGHT] =
        clamp(right_mm_s, -top_mm_s, top_mm_s) * MOTION_UM_TICK_PER_MM_S;
}

void motion_step(motion_t *m, const odom_t *odom, uint32_t periods, int16_t duty[2])
{
    m->err_pos = (uint8_t)((m->err_pos + 1u) % MOTION_SPEED_TICKS);
    int32_t went = 0; /* both wheels' travel: twice the body's */
    for (unsigned w = 0; w < 2u; w++) {
        /* The ramp: the acceleration limit of §III.B. */
        int32_t step =
            clamp(m->target_um_tick[w] - m->set_um_tick[w], -m->accel_um_tick2, m->accel_um_tick2);
        int32_t set = m->set_um_tick[w] + step;
        m->set_um_tick[w] = set;
        /* The speed: the travel over the periods it took. After a lost tick the travel is
         * that of two periods, and taken for one it would read as twice the speed: the
         * control would brake, then push, and the wheels would slip. */
        int32_t rolled = odom->step_um[w];
        if (periods > 1u) {
            rolled /= (int32_t)periods;
        }
        /* An encoder glitch may claim any speed; the error is bounded so every product
         * below fits 32 bits. |set| is far below MOTION_ERR_MAX, so bounding the travel at
         * twice that first changes no error and keeps the difference, and the two wheels'
         * sum for the body's watch, within 32 bits. */
        int32_t travel = clamp(rolled, -2 * MOTION_ERR_MAX, 2 * MOTION_ERR_MAX);
        went += travel;
        int32_t err = clamp(set - travel, -MOTION_ERR_MAX, MOTION_ERR_MAX);
        /* Stall watch: a wheel asked to turn that hardly does. */
        int32_t set_abs = set < 0 ? -set : set;
        uint32_t got = rolled >= 0 ? (uint32_t)rolled : 0u - (uint32_t)rolled;
        if (set_abs >= MOTION_STALL_MIN_UM_TICK && got < (uint32_t)set_abs / 4u) {
            m->slow_ticks[w] =
                (uint16_t)(m->slow_ticks[w] < UINT16_MAX ? m->slow_ticks[w] + 1u : UINT16_MAX);
        } else {
            m->slow_ticks[w] = 0u;
        }
        int32_t *slot = &m->err_um_tick[w][m->err_pos];
        m->err_sum[w] = m->err_sum[w] - *slot + err;
        *slot = err;
        if (set == 0 && m->target_um_tick[w] == 0) {
            /* At rest: no output, and nothing left over to push the wheel later. */
            m->integral_um[w] = 0;
            duty[w] = 0;
            continue;
        }
        /* |set| <= 50 000 µm/tick, so set · 1000 fits 32 bits. */
        int32_t ff = set * MOTION_DUTY_MAX / m->top_um_tick;
        if (m->slow_ticks[w] >= MOTION_DEAD_TICKS) {
            /* A wheel that hardly turns as asked is held against something, or its
             * encoder has stopped counting: pushing harder would not free it, and on a
             * dead count it would run away and turn the robot blind. The feed-forward
             * alone, until the count comes back. */
            m->integral_um[w] = 0;
            duty[w] = (int16_t)clamp(ff, -MOTION_DUTY_MAX, MOTION_DUTY_MAX);
            continue;
        }
        /* |integral| <= 256 000 (integral_max_um) and |err| <= 2^17: the sum fits. */
        m->integral_um[w] = clamp(m->integral_um[w] + err, -m->integral_max_um, m->integral_max_um);
        /* (kp · Σe/N + ki · I) / 256, the division by N = 4 folded into the shift. With
         * |Σe| <= 2^19, kp <= 2^11 and |ki · I| <= 256 000, everything fits 32 bits. */
        int32_t acc =
            m->kp_q8 * m->err_sum[w] + m->ki_q8 * m->integral_um[w] * (int32_t)MOTION_SPEED_TICKS;
        int32_t pi = (acc + (1 << (7 + MOTION_SPEED_SHIFT))) >> (8u + MOTION_SPEED_SHIFT);
        duty[w] = (int16_t)clamp(ff + pi, -MOTION_DUTY_MAX, MOTION_DUTY_MAX); /* both small */
    }
    /* Stall watch of the body: both wheels asked one way and the body going under a
     * quarter of that. A body held back at one side turns to and fro as the wheels push
     * by turns, and each wheel's own watch starts afresh whenever it turns. */
    bool one_way = (m->set_um_tick[0] ^ m->set_um_tick[1]) >= 0;
    int32_t asked = m->set_um_tick[0] + m->set_um_tick[1];
    if (asked < 0) {
        asked = -asked;
        went = -went;
    }
    if (one_way && asked >= 2 * MOTION_STALL_MIN_UM_TICK && went < asked / 4) {
        m->body_slow = (uint16_t)(m->body_slow < UINT16_MAX ? m->body_slow + 1u : UINT16_MAX);
    } else {
        m->body_slow = 0u;
    }
}

bool motion_stalled(const motion_t *m)
{
    return m->slow_ticks[0] >= MOTION_STALL_TICKS || m->slow_ticks[1] >= MOTION_STALL_TICKS ||
           m->body_slow >= MOTION_STALL_TICKS;
}

bool motion_one_wheel(const motion_t *m)
{
    for (unsigned w = 0; w < 2u; w++) {
        int32_t other = m->set_um_tick[1u - w];
        other = other < 0 ? -other : other;
        if (m->slow_ticks[w] >= MOTION_STALL_TICKS && m->slow_ticks[1u - w] == 0u &&
            other >= MOTION_STALL_MIN_UM_TICK) {
            return true;
        }
    }
    return false;
}
