/* SPDX-License-Identifier: MIT */
/* What host_sim measures as the robot runs: its setup, then after every tick the pose
 * errors, the coverage, the trajectory and the reading of the tick. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "host_sim.h"
#include "slam/error.h"

#define TRAJECTORY_EVERY 10u /* trajectory.csv: one row per 0.1 s */
#define COVERAGE_EVERY 1000u /* the coverage series: one point per 10 s */

static const double coverage_marks[3] = {0.5, 0.8, 0.9};

/* Free cells whose centre the robot's centre can reach from the start (4-connected,
 * clear of obstacles by the body radius): the cells exploration could visit. */
static void reachable_cells(const room_t *room, const sim_params_t *p, run_t *r, uint32_t start)
{
    const map_geom_t *g = &r->geom;
    size_t n = (size_t)g->a * g->b;
    uint32_t *queue = malloc(n * sizeof *queue);
    if (queue == NULL) {
        return;
    }
    size_t head = 0;
    size_t tail = 0;
    r->reachable[start] = 1u;
    queue[tail++] = start;
    while (head < tail) {
        uint32_t c = queue[head++];
        uint32_t x = c % g->a;
        uint32_t y = c / g->a;
        const int32_t dx[4] = {1, -1, 0, 0};
        const int32_t dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; k++) {
            int64_t nx = (int64_t)x + dx[k];
            int64_t ny = (int64_t)y + dy[k];
            if (nx < 0 || ny < 0 || nx >= g->a || ny >= g->b) {
                continue;
            }
            uint32_t nc = (uint32_t)ny * g->a + (uint32_t)nx;
            if (r->reachable[nc] || r->truth[nc]) {
                continue;
            }
            double wx = g->origin_x + ((double)nx + 0.5) * g->cell_m;
            double wy = g->origin_y + ((double)ny + 0.5) * g->cell_m;
            if (!room_disc_free(room, wx, wy, p->body_radius_m)) {
                continue;
            }
            r->reachable[nc] = 1u;
            queue[tail++] = nc;
        }
    }
    r->reachable_cells = (uint32_t)tail;
    free(queue);
}

int observe_init(run_t *r, const scenario_t *sc, const robot_t *robot, uint32_t *start_cell)
{
    const room_t *room = &sc->room;
    r->geom = map_geom_of(&robot->grid);
    room_rasterize(room, r->geom.origin_x, r->geom.origin_y, r->geom.cell_m, r->geom.a, r->geom.b,
                   r->truth);
    grid_cell_t start;
    (void)grid_cell_of(&robot->grid, sc->cfg.start_x_um, sc->cfg.start_y_um, &start);
    *start_cell = grid_index(&robot->grid, start);
    reachable_cells(room, &sc->params, r, *start_cell);
    if (walls_init(r, room, &sc->params, sc->cfg.confidence_radius_um * 1e-6, *start_cell) != 0) {
        fprintf(stderr, "host_sim: out of memory\n");
        return -1;
    }
    r->time_to[0] = r->time_to[1] = r->time_to[2] = -1.0;
    r->last_x = sc->sx;
    r->last_y = sc->sy;
    r->marked_x = r->marked_y = HUGE_VAL;
    r->prog_x = sc->sx;
    r->prog_y = sc->sy;
    r->explored_at_s = -1.0;
    return 0;
}

/* The odometry's error against the truth @p tr, and the path driven. Every period, so
 * sqrt() of the squares rather than hypot() (a tenth of the cost; nothing here comes near
 * the overflow hypot() guards against). */
static void track_errors(run_t *r, const sim_truth_t *tr, double ox, double oy, double oth,
                         double *ep, double *eth)
{
    double ex = ox - tr->x;
    double ey = oy - tr->y;
    double px = tr->x - r->last_x;
    double py = tr->y - r->last_y;
    *ep = sqrt(ex * ex + ey * ey);
    *eth = fabs(wrap_pi(oth - tr->th));
    r->max_pos_err = *ep > r->max_pos_err ? *ep : r->max_pos_err;
    r->max_th_err = *eth > r->max_th_err ? *eth : r->max_th_err;
    r->final_pos_err = *ep;
    r->final_th_err = *eth;
    r->path_m += sqrt(px * px + py * py);
    r->last_x = tr->x;
    r->last_y = tr->y;
}

/* Coverage: TM > 0 on a reachable cell, and when each mark was reached. */
static void track_coverage(run_t *r, const robot_t *robot, double t)
{
    grid_cell_t c;
    if (grid_cell_of(&robot->grid, robot->pose.x_um, robot->pose.y_um, &c) == SLAM_OK) {
        uint32_t i = grid_index(&robot->grid, c);
        if (!r->seen[i]) {
            r->seen[i] = 1u;
            r->visited_cells += r->reachable[i];
            for (int k = 0; k < 3; k++) {
                if (r->time_to[k] < 0.0 &&
                    r->visited_cells >= coverage_marks[k] * r->reachable_cells) {
                    r->time_to[k] = t;
                }
            }
        }
    }
}

/*
 * Progress: the time since the robot last came PROGRESS_M from where it was then. A
 * deliberate stand (the exploration done, or its mode standing; a hold for a save, a
 * command or STOP) does not count: it moves the clock on without forgiving the time
 * before or after it, so a robot wedged between two saves is still seen wedged.
 */
static void progress_tick(run_t *r, const robot_t *robot, double x, double y, double t)
{
    if (robot->hold != 0u || explore_standing(&robot->explore)) {
        r->prog_t += TICK_S;
    }
    double dx = x - r->prog_x;
    double dy = y - r->prog_y;
    if (dx * dx + dy * dy >= PROGRESS_M * PROGRESS_M) { /* every tick: no hypot() */
        r->prog_x = x;
        r->prog_y = y;
        r->prog_t = t;
    } else if (t - r->prog_t > r->stuck_s) {
        r->stuck_s = t - r->prog_t;
        r->stuck_from_s = r->prog_t;
    }
    if (r->explored_at_s < 0.0 && explore_explored(&robot->explore)) {
        r->explored_at_s = t;
    }
}

/* Touches: each from the body meeting an obstacle until it is out of contact and has moved
 * on MOVED_ON_M from where it met it. */
static void touches_tick(run_t *r, bool contact, double x, double y, double t)
{
    if (r->touching) {
        if (!contact && hypot(x - r->touch_from_x, y - r->touch_from_y) >= MOVED_ON_M) {
            r->touching = false;
            double took = t - r->touch_from_t;
            if (r->touches <= TOUCHES_LISTED) {
                r->touch_recovery_s[r->touches - 1u] = took;
            }
            r->touch_recovery_max_s =
                took > r->touch_recovery_max_s ? took : r->touch_recovery_max_s;
        }
        return;
    }
    if (contact) {
        r->touching = true;
        r->touches++;
        r->touch_from_t = t;
        r->touch_from_x = x;
        r->touch_from_y = y;
        if (r->touches <= TOUCHES_LISTED) {
            r->touch_recovery_s[r->touches - 1u] = -1.0;
        }
    }
}

/* One point of the coverage series. */
static void series_point(run_t *r, double t)
{
    r->series[r->nseries][0] = t;
    r->series[r->nseries][1] =
        r->reachable_cells ? (double)r->visited_cells / r->reachable_cells : 0.0;
    r->series[r->nseries][2] = r->wall_cells ? (double)r->walls_covered / r->wall_cells : 0.0;
    r->nseries++;
}

/* One row of trajectory.csv: odometry and truth. */
static void trajectory_row(FILE *trajectory, double t, double ox, double oy, double oth,
                           const sim_truth_t *tr)
{
    char line[192];
    char *e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
    e = fmt_fixed(e, ox, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, oy, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(oth), CSV_HEADING_DECIMALS, ',');
    e = fmt_fixed(e, tr->x, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, tr->y, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(tr->th), CSV_HEADING_DECIMALS, '\n');
    fwrite(line, 1, (size_t)(e - line), trajectory);
}

/* Cells along a beam's axis at most: a reading touches 0.5 m / L + 3 of them (mapper.h). */
#define AXIS_CELLS 2048u

/*
 * An echo into the perfect-odometry map, and the truth cells (walls) it lowered: the cells
 * along the beam's true axis from the sensor (sx, sy) to a cell beyond where the reading
 * reaches (its range, or rc), compared before and after. Counted by whether the echo came
 * by a mirror path: a long, wrong range whose free-space evidence crosses a wall.
 */
static void ideal_echo(run_t *r, firmware_t *fw, const odom_pose_t *truth_pose, bam32_t servo,
                       uint32_t d_um, double sx, double sy, double bearing, bool mirrored)
{
    static uint32_t cells[AXIS_CELLS];
    static uint8_t before[AXIS_CELLS];
    const map_geom_t *g = &r->geom;
    double reach = fmin(d_um * 1e-6, r->rc_m) + g->cell_m;
    double c = cos(bearing);
    double sn = sin(bearing);
    size_t n = 0;
    for (double t = 0.0; t <= reach && n < AXIS_CELLS; t += 0.25 * g->cell_m) {
        /* In the grid exactly when the floors are: qa >= 0 and qa < a, and then the
         * conversion is the floor, with no floor() to compute. */
        double qa = (sx + t * c - g->origin_x) / g->cell_m;
        double qb = (sy + t * sn - g->origin_y) / g->cell_m;
        if (!(qa >= 0.0 && qb >= 0.0 && qa < (double)g->a && qb < (double)g->b)) {
            continue;
        }
        uint32_t i = (uint32_t)qb * g->a + (uint32_t)qa;
        if (n == 0u || cells[n - 1u] != i) {
            cells[n] = i;
            before[n++] = fw->ideal_grid.om[i];
        }
    }
    (void)mapper_reading(&fw->ideal_mapper, &fw->ideal_grid, truth_pose, servo, d_um);
    for (size_t k = 0; k < n; k++) {
        if (r->truth[cells[k]] && fw->ideal_grid.om[cells[k]] < before[k]) {
            r->walls_lowered[mirrored ? 0 : 1]++;
        }
    }
}

/* The middle of a scoring_estimate.csv row: what the pose correction knows of its own
 * doubt once the reading is processed, for a pose-integrity flag to be measured against
 * the truth. Integers in the filter's units are exact in a double. */
static char *estimate_stats(char *e, const loc_t *l)
{
    static const unsigned cov[6][2] = {{0, 0}, {0, 1}, {1, 1}, {0, 2}, {1, 2}, {2, 2}};
    for (size_t k = 0; k < 6u; k++) {
        e = fmt_fixed(e, (double)l->filter.cov.p[cov[k][0]][cov[k][1]], 0, ',');
    }
    const loc_match_t *m = &l->match;
    e = fmt_fixed(e, m->tried, 0, ',');
    e = fmt_fixed(e, m->applied, 0, ',');
    e = fmt_fixed(e, m->refused, 0, ',');
    e = fmt_fixed(e, m->last_points, 0, ',');
    e = fmt_fixed(e, m->last_step[0] * 1e-4, 4, ',');
    e = fmt_fixed(e, m->last_step[1] * 1e-4, 4, ',');
    return fmt_fixed(e, m->last_step[2] * 1e-5, 5, ',');
}

/* A reading as both sonars give it: its beam as a servo angle, its echo, and the pose of
 * its ping, odometry and truth. */
typedef struct {
    int32_t servo_mdeg;
    bam32_t servo;
    bool echo;
    uint32_t range_um;
    const odom_pose_t *odom;
    sim_ping_t ping;
    double mount_x, mount_y; /* where the sonar sits on the robot, m */
    bool mark;               /* its sonar position marks what is observable */
} reading_t;

/* The last column of a scoring_estimate.csv row: OM's byte, as the reading left it, in the
 * cell where the echo ends seen from the estimated pose (empty without an echo or off the
 * grid). A lost pose puts echoes where OM holds free space: evidence for a pose-integrity
 * flag that does not come from the matcher. */
static char *om_at_echo(char *e, const robot_t *robot, const odom_pose_t *est, const reading_t *rd)
{
    int32_t x;
    int32_t y;
    grid_cell_t c;
    if (rd->echo) {
        sonar_obstacle(&robot->mapper.sonar, est, rd->servo, rd->range_um, &x, &y);
        if (grid_cell_of(&robot->grid, x, y, &c) == 0) {
            return fmt_fixed(e, robot->grid.om[grid_index(&robot->grid, c)], 0, '\n');
        }
    }
    *e++ = '\n';
    return e;
}

/* A reading, with the pose of its ping: odometry and truth. It marks what became
 * observable and the walls it covered, goes into the perfect-odometry maps, and is logged
 * to readings.csv (and its estimated pose to scoring_estimate.csv). */
static void observe_reading(run_t *r, firmware_t *fw, const reading_t *rd, FILE *readings, double t)
{
    const robot_t *robot = &fw->robot;
    const sim_ping_t ping = rd->ping;
    const odom_pose_t *op = rd->odom;
    double sx = ping.x + rd->mount_x * cos(ping.th) - rd->mount_y * sin(ping.th);
    double sy = ping.y + rd->mount_x * sin(ping.th) + rd->mount_y * cos(ping.th);
    /* Cells within rc of a sonar position are observable; a new disc only once the
     * sonar has moved by a cell (the disc's edge is then within a cell of exact). */
    if (rd->mark && hypot(sx - r->marked_x, sy - r->marked_y) >= r->geom.cell_m) {
        mark_disc(&r->geom, r->observable, sx, sy, robot->cfg.confidence_radius_um * 1e-6);
        r->marked_x = sx;
        r->marked_y = sy;
    }
    walls_ping(r, sx, sy, ping.bearing, t);
    char line[512];
    char *e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
    e = fmt_fixed(e, rd->servo_mdeg / 1000.0, CSV_SERVO_DECIMALS, ',');
    uint32_t d = rd->echo ? rd->range_um : 0u;
    odom_pose_t truth_pose = {to_um(ping.x), to_um(ping.y), to_bam(ping.th)};
    if (rd->echo) {
        e = fmt_fixed(e, d * 1e-6, CSV_LENGTH_DECIMALS, ',');
        ideal_echo(r, fw, &truth_pose, rd->servo, d, sx, sy, ping.bearing,
                   ping.kind == SIM_PING_MULTIPATH);
    } else {
        *e++ = ',';
        mapper_timeout(&fw->ideal_mapper, &fw->ideal_grid, &truth_pose);
    }
    const char *status = reading_status(&robot->mapper.sonar, rd->echo, d);
    size_t n = strlen(status);
    memcpy(e, status, n);
    e += n;
    *e++ = ',';
    e = fmt_fixed(e, op->x_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, op->y_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(bam_rad(op->heading)), CSV_HEADING_DECIMALS, ',');
    e = fmt_fixed(e, ping.x, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, ping.y, CSV_LENGTH_DECIMALS, ',');
    e = fmt_fixed(e, wrap_pi(ping.th), CSV_HEADING_DECIMALS, '\n');
    fwrite(line, 1, (size_t)(e - line), readings);
    if (r->estimates != NULL) {
        /* Where the robot believed the ping was (odometry and the correction of the tick),
         * for a mapper outside this program to map from the firmware's estimate. */
        odom_pose_t est = loc_tick_pose(&robot->loc, op);
        e = fmt_fixed(line, t, CSV_TIME_DECIMALS, ',');
        e = fmt_fixed(e, est.x_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, est.y_um * 1e-6, CSV_LENGTH_DECIMALS, ',');
        e = fmt_fixed(e, wrap_pi(bam_rad(est.heading)), CSV_HEADING_DECIMALS, ',');
        e = estimate_stats(e, &robot->loc);
        e = om_at_echo(e, robot, &est, rd);
        fwrite(line, 1, (size_t)(e - line), r->estimates);
    }
}

/* The sweep's reading of this tick, and the second sonar's that robot_idle() mapped after
 * it (the firmware maps it from the servo's axis, and so do the perfect-odometry maps;
 * walls are looked at from where it sits; the swept sonar's positions alone mark what is
 * observable, a few centimetres from its own). */
static void observe_readings(run_t *r, firmware_t *fw, const sim_t *sim, const sim_params_t *p,
                             FILE *readings, double t)
{
    const robot_t *robot = &fw->robot;
    const robot_sonar1_t *s1 = &robot->sonar1;
    const sweep_out_t *sw = &robot->last;
    if (sw->reading_ready) {
        const reading_t rd = {
            .servo_mdeg = sw->reading.servo_mdeg,
            .servo = sw->reading.servo,
            .echo = sw->reading.echo,
            .range_um =
                sw->reading.echo ? sonar_range_um(&robot->mapper.sonar, sw->reading.echo_us) : 0u,
            .odom = &robot->mapper.ping_pose,
            .ping = sim_last_ping(sim),
            .mount_x = p->sonar_x_m,
            .mount_y = p->sonar_y_m,
            .mark = true,
        };
        observe_reading(r, fw, &rd, readings, t);
    }
    if (s1->readings != r->sonar1_seen) {
        r->sonar1_seen = s1->readings;
        const reading_t rd = {
            .servo_mdeg = robot->cfg.sonar1_mdeg,
            .servo = s1->reading.servo,
            .echo = s1->reading.echo,
            .range_um = s1->reading.range_um,
            .odom = &s1->reading.ping,
            .ping = sim_last_ping_on(sim, HAL_SONAR_FIXED),
            .mount_x = p->extra_sonar[0].x_m,
            .mount_y = p->extra_sonar[0].y_m,
        };
        observe_reading(r, fw, &rd, readings, t);
    }
}

void observe_tick(run_t *r, firmware_t *fw, const sim_t *sim, const sim_truth_t *before,
                  const sim_params_t *p, const run_logs_t *logs, uint64_t tick, bool last)
{
    /* The firmware read its encoders at the start of the period: compare its pose with
     * the truth of that instant, not with the world already advanced by the period. */
    const sim_truth_t tr = *before;
    const robot_t *robot = &fw->robot;
    double t = (double)tick * TICK_S;
    double ox = robot->pose.x_um * 1e-6;
    double oy = robot->pose.y_um * 1e-6;
    double oth = bam_rad(robot->pose.heading);
    double ep;
    double eth;
    track_errors(r, &tr, ox, oy, oth, &ep, &eth);

    /* The perfect-odometry maps' TM, at the true pose. */
    (void)grid_tm_visit(&fw->ideal_grid, to_um(tr.x), to_um(tr.y));

    track_coverage(r, robot, t);
    sim_truth_t after = sim_truth(sim);
    clearance_tick(r, after.x, after.y);
    touch_tick(r, after.contact, after.x, after.y, after.th, t, ep, eth);
    touches_tick(r, after.contact, after.x, after.y, t);
    progress_tick(r, robot, after.x, after.y, t);
    if (((tick + 1u) % COVERAGE_EVERY == 0u || last) && r->nseries < 4096u) {
        series_point(r, t);
    }
    if (tick % TRAJECTORY_EVERY == 0u || last) {
        trajectory_row(logs->trajectory, t, ox, oy, oth, &tr);
    }
    observe_readings(r, fw, sim, p, logs->readings, t);
}
