/* SPDX-License-Identifier: MIT */
/* Algorithm C.1: TM at the robot's cell each tick, OM at the obstacle cell per reading. */
#include "slam/mapper.h"

#include <string.h>

#include "slam/error.h"

#ifndef MAPPER_RAY_UM
#define MAPPER_RAY_UM 500000u /* a beam clears the last 0.5 m before its echo, or rc */
#endif

void mapper_init(mapper_t *m, const slam_config_t *cfg)
{
    memset(m, 0, sizeof *m);
    sonar_init(&m->sonar, cfg);
    m->cell_um = cfg->cell_um;
    m->last = MAPPER_TIMEOUT;
}

static void count(uint32_t *counter)
{
    if (*counter != UINT32_MAX) {
        (*counter)++;
    }
}

static void count_n(uint32_t *counter, uint32_t n)
{
    *counter = *counter > UINT32_MAX - n ? UINT32_MAX : *counter + n;
}

mapper_outcome_t mapper_classify(const mapper_t *m, uint32_t range_um)
{
    if (range_um >= m->sonar.confidence_um) {
        return MAPPER_FAR;
    }
    return range_um < m->sonar.range_min_um ? MAPPER_NEAR : MAPPER_HIT;
}

/*
 * The faces of walls, for an echo in the evidence map, before its beam clears anything.
 * - Its cell already holds a wall: the face is there, and the cell a cell further along
 *   the beam lies behind it, where no beam reaches. Evidence of a wall there came from
 *   readings placed wrongly (a pose or a range error), and nothing else could ever take it
 *   away: it is lowered, to unknown at most (grid_om_behind()), so that a wall seen from
 *   one side stays as thin as its face instead of thickening over hours.
 * - Its cell does not, and the cell a cell nearer along the beam does: the echo lies just
 *   behind a face the map holds, `shadowed`. A caller that holds the pose to the map
 *   (localize.c) matches such a hit, which pulls the pose back to the face, but does not
 *   map it.
 */
static void faces(mapper_t *m, grid_t *g, const sonar_beam_t *beam, uint32_t range_um, int32_t x_um,
                  int32_t y_um)
{
    grid_cell_t hit;
    if (grid_cell_of(g, x_um, y_um, &hit) != SLAM_OK ||
        (range_um <= m->cell_um && grid_state(g, grid_index(g, hit)) != GRID_OCCUPIED)) {
        return; /* (an echo nearer than a cell has no cell nearer along its beam) */
    }
    bool wall = grid_state(g, grid_index(g, hit)) == GRID_OCCUPIED;
    int32_t x;
    int32_t y;
    grid_cell_t next;
    sonar_beam_point(beam, wall ? range_um + m->cell_um : range_um - m->cell_um, &x, &y);
    if (grid_cell_of(g, x, y, &next) != SLAM_OK || (next.a == hit.a && next.b == hit.b)) {
        return;
    }
    if (wall) {
        grid_om_behind(g, next);
    } else {
        m->shadowed = grid_state(g, grid_index(g, next)) == GRID_OCCUPIED;
    }
}

mapper_outcome_t mapper_free(mapper_t *m, grid_t *g, const odom_pose_t *at_ping, bam32_t servo,
                             uint32_t range_um, int32_t *hit_x_um, int32_t *hit_y_um)
{
    mapper_outcome_t out = mapper_classify(m, range_um);
    m->last = out;
    if (out == MAPPER_NEAR) {
        count(&m->near);
        return out;
    }
    sonar_beam_t beam;
    sonar_beam(&m->sonar, at_ping, servo, &beam);
    if (out == MAPPER_HIT) {
        sonar_beam_point(&beam, range_um, hit_x_um, hit_y_um);
    } else {
        count(&m->far);
    }
    if (g->mode == OM_MODE_EVIDENCE) {
        m->shadowed = false;
        if (out == MAPPER_HIT) {
            faces(m, g, &beam, range_um, *hit_x_um, *hit_y_um);
        }
        /* Up to one cell short of the echo, or to rc for a far one, over the last
         * MAPPER_RAY_UM: the cells nearer the robot are crossed by readings from farther
         * away, and its own cell holds no obstacle: the body stands there. */
        uint32_t reach = out == MAPPER_FAR       ? m->sonar.confidence_um
                         : range_um > m->cell_um ? range_um - m->cell_um
                                                 : 0u;
        int32_t xe;
        int32_t ye;
        sonar_beam_point(&beam, reach, &xe, &ye);
        int32_t xs = at_ping->x_um;
        int32_t ys = at_ping->y_um;
        if (reach > MAPPER_RAY_UM) {
            count_n(&m->cleared, grid_om_free(g, xs, ys) == SLAM_OK ? 1u : 0u);
            sonar_beam_point(&beam, reach - MAPPER_RAY_UM, &xs, &ys);
        }
        count_n(&m->cleared, grid_om_ray(g, xs, ys, xe, ye));
    }
    return out;
}

mapper_outcome_t mapper_hit(mapper_t *m, grid_t *g, int32_t x_um, int32_t y_um)
{
    return mapper_hit_rest(m, g, x_um, y_um, 0u);
}

mapper_outcome_t mapper_hit_rest(mapper_t *m, grid_t *g, int32_t x_um, int32_t y_um, uint8_t placed)
{
    m->last_x_um = x_um;
    m->last_y_um = y_um;
    if (grid_om_add(g, x_um, y_um, (uint8_t)(g->hit - placed)) == SLAM_OK) {
        m->last = MAPPER_HIT;
        count(&m->hits);
    } else {
        m->last = MAPPER_OUTSIDE;
        count(&m->outside);
    }
    return m->last;
}

mapper_outcome_t mapper_reading(mapper_t *m, grid_t *g, const odom_pose_t *at_ping, bam32_t servo,
                                uint32_t range_um)
{
    int32_t x;
    int32_t y;
    if (mapper_free(m, g, at_ping, servo, range_um, &x, &y) != MAPPER_HIT) {
        return m->last;
    }
    return mapper_hit(m, g, x, y);
}

void mapper_note(mapper_t *m, const odom_pose_t *at_ping, const sweep_reading_t *rd)
{
    if (!rd->echo) {
        m->last = MAPPER_TIMEOUT;
        return;
    }
    uint32_t range_um = sonar_range_um(&m->sonar, rd->echo_us);
    m->last = mapper_classify(m, range_um);
    if (m->last == MAPPER_HIT) {
        sonar_obstacle(&m->sonar, at_ping, rd->servo, range_um, &m->last_x_um, &m->last_y_um);
    }
}

void mapper_timeout(mapper_t *m, grid_t *g, const odom_pose_t *at_ping)
{
    m->last = MAPPER_TIMEOUT;
    count(&m->timeouts);
    if (g->mode == OM_MODE_EVIDENCE) {
        count_n(&m->cleared, grid_om_free(g, at_ping->x_um, at_ping->y_um) == SLAM_OK ? 1u : 0u);
    }
}

void mapper_tick(mapper_t *m, grid_t *g, const odom_pose_t *pose, const sweep_out_t *sw)
{
    /* Step 1: the trajectory map, once per control period. */
    (void)grid_tm_visit(g, pose->x_um, pose->y_um);

    /* Step 2: a reading completed this tick, with the pose of its ping. The reading is
     * handled before a new ping is recorded: a stop that ends begins the next one in the
     * same tick, but its ping is never sent in that tick (settle_ticks >= 1). */
    if (sw->reading_ready) {
        if (sw->reading.echo) {
            uint32_t d = sonar_range_um(&m->sonar, sw->reading.echo_us);
            (void)mapper_reading(m, g, &m->ping_pose, sw->reading.servo, d);
        } else {
            mapper_timeout(m, g, &m->ping_pose);
        }
    }
    if (sw->trigger) {
        m->ping_pose = *pose;
    }
}
