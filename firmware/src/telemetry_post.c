/* SPDX-License-Identifier: MIT */
/* Telemetry's half in the tick: events posted into the ring that robot_idle() sends
 * (telemetry.c holds the rest, built for size on the MCU; this part for speed). */
#include "slam/telemetry.h"

/* The ring has one producer (the tick) and one consumer (idle), which on Linux run on
 * different cores: an index is published with release order after its slot is written,
 * and read with acquire order before the slot is read. */
static void post(telem_t *t, const telem_event_t *e)
{
    uint8_t head = t->head;
    uint8_t next = (uint8_t)((head + 1u) % TELEM_RING);
    if (next == __atomic_load_n(&t->tail, __ATOMIC_ACQUIRE)) {
        t->dropped++;
        return;
    }
    t->ring[head] = *e;
    __atomic_store_n(&t->head, next, __ATOMIC_RELEASE);
}

void telem_post_pose(telem_t *t, uint32_t ticks, const odom_pose_t *pose)
{
    telem_event_t e = {.type = TELEM_POSE, .ticks = ticks, .pose = *pose};
    post(t, &e);
}

void telem_post_reading(telem_t *t, uint32_t ticks, uint8_t stop, uint8_t outcome,
                        int32_t servo_mdeg, uint32_t range_um, const odom_pose_t *ping)
{
    telem_event_t e = {.type = TELEM_READING,
                       .stop = stop,
                       .outcome = outcome,
                       .ticks = ticks,
                       .pose = *ping,
                       .servo_mdeg = servo_mdeg,
                       .range_um = range_um};
    post(t, &e);
}
