/* SPDX-License-Identifier: MIT */
/* The robot's background loop: commands over the link, the watchdog, the readings, the
 * second sonar, saves, telemetry. */
#include "slam/robot.h"

#include "hal/hal.h"
#include "slam/error.h"

/* Commands that wait for the robot to stand: re-initialise the modules the configuration
 * feeds, and restart the exploration's random stream from the configured seed. */
#define ROBOT_PENDING_RECONFIGURE 0x01u
#define ROBOT_PENDING_RESEED 0x02u

/* Set or clear one reason to hold the robot still (robot_idle() is the only writer). */
static void robot_hold(robot_t *r, uint8_t why, bool on)
{
    r->hold = (uint8_t)(on ? r->hold | why : r->hold & ~why);
}

void robot_request_save(robot_t *r)
{
    r->save_requested = true;
}

/* ---- commands over the telemetry link ----------------------------------------------------- */

/* What the configuration feeds, set up again with the robot standing and the tick shut
 * out: the odometry's gains (the pose stays), the sonar's limits, the speed control, and
 * the exploration from where the robot stands (its counters stay). */
static void robot_reconfigure(robot_t *r, bool reseed)
{
    hal_irq_state_t irq = hal_critical_enter();
    odom_t keep = r->odom;
    odom_init(&r->odom, &r->cfg, keep.last_count[ODOM_LEFT], keep.last_count[ODOM_RIGHT]);
    r->odom.x_um = keep.x_um;
    r->odom.y_um = keep.y_um;
    r->odom.heading_q16 = keep.heading_q16;
    sonar_init(&r->mapper.sonar, &r->cfg);
    motion_init(&r->motion, &r->cfg);

    slam_config_t here = r->cfg;
    here.start_x_um = r->pose.x_um;
    here.start_y_um = r->pose.y_um;
    here.start_heading_mdeg = fix_bam_to_mdeg(r->pose.heading);
    if (!reseed) {
        here.explore_seed = r->explore.machine.rng; /* the random stream goes on */
    }
    explore_count_t count = r->explore.count;
    explore_init(&r->explore, &here);
    r->explore.count = count;
    /* Into or out of the UMBmark test: the pose correction starts afresh (the hits it
     * held back are dropped), off while the test runs and puts odometry back at every run. */
    bool was = r->umbmark.on;
    umbmark_init(&r->umbmark, &r->cfg);
    if (was != r->umbmark.on) {
        readq_init(&r->readq, &r->cfg); /* (and the readings not yet mapped) */
        loc_init(&r->loc, &r->cfg);
        r->loc.on = r->loc.on && !r->umbmark.on;
    }
    hal_critical_exit(irq);
}

/* One well-formed command: answered, and done or left pending until the robot stands. */
static void robot_command(robot_t *r, const telem_cmd_t *c)
{
    telem_t *t = &r->telem;
    switch (c->type) {
    case TELEM_CMD_START:
        robot_hold(r, ROBOT_HOLD_STOP, false);
        telem_send_ack(t, c->type);
        break;
    case TELEM_CMD_STOP:
        robot_hold(r, ROBOT_HOLD_STOP, true);
        telem_send_ack(t, c->type);
        break;
    case TELEM_CMD_GET: {
        uint32_t v;
        if (telem_config_get(&r->cfg, c->key, &v) != 0) {
            telem_send_error(t, c->type, TELEM_ERR_KEY, c->key);
        } else {
            telem_send_config(t, &r->cfg, c->key);
        }
        break;
    }
    case TELEM_CMD_MODE:
    case TELEM_CMD_SET:
    case TELEM_CMD_CALIBRATE: {
        uint8_t key = c->type == TELEM_CMD_SET ? c->key : (uint8_t)TELEM_KEY_EXPLORE_MODE;
        uint32_t value = c->type == TELEM_CMD_SET    ? c->value
                         : c->type == TELEM_CMD_MODE ? c->key
                                                     : ROBOT_CALIBRATION_MODE;
        int rc = telem_config_set(&r->cfg, key, value);
        if (rc != 0) {
            telem_send_error(t, c->type, (uint8_t)-rc, c->type == TELEM_CMD_MODE ? 0u : key);
            break;
        }
        r->pending |= ROBOT_PENDING_RECONFIGURE;
        if (key == TELEM_KEY_EXPLORE_SEED) {
            r->pending |= ROBOT_PENDING_RESEED;
        }
        if (c->type == TELEM_CMD_SET) {
            telem_send_config(t, &r->cfg, key);
        } else {
            if (c->type == TELEM_CMD_CALIBRATE) {
                robot_hold(r, ROBOT_HOLD_STOP, false);
            }
            telem_send_ack(t, c->type);
        }
        break;
    }
    case TELEM_CMD_SAVE:
        if (!r->store.available) {
            telem_send_error(t, c->type, TELEM_ERR_UNSUPPORTED, 0u);
        } else {
            /* What is asked for is the map as it stands: the held-back hits go in first. */
            loc_flush(&r->loc, &r->mapper, &r->grid);
            robot_request_save(r);
            telem_send_ack(t, c->type);
        }
        break;
    case TELEM_CMD_SEND_MAP:
        telem_map_restart(t);
        telem_send_ack(t, c->type);
        break;
    default:
        telem_send_error(t, c->type, TELEM_ERR_COMMAND, 0u);
        break;
    }
}

/* ---- the readings the tick posted ---------------------------------------------------------- */

/* A reading of either sonar: with the pose correction on, mapped and matched by it; off,
 * mapped as the mapper alone maps it (the tick cannot: a beam's ray is too much work for
 * it). */
static void robot_map(robot_t *r, const readq_reading_t *rd)
{
    if (r->loc.on) {
        loc_reading(&r->loc, &r->mapper, &r->grid, rd);
    } else {
        readq_map(rd, &r->mapper, &r->grid);
    }
}

/* Each in turn, counted finished only after: the tick adopts what loc_reading() published
 * once it is. */
static void robot_readings(robot_t *r)
{
    readq_reading_t rd;
    while (readq_take(&r->readq, &rd)) {
        robot_map(r, &rd);
        readq_done(&r->readq);
    }
}

/* The second sonar: a ping while the sweep's sonar waits for no echo and
 * ping_interval_ticks after its own last one; its echo, or none, within the sweep's echo
 * timeout, mapped as a sweep reading is. */
static void robot_sonar1(robot_t *r)
{
    robot_sonar1_t *s = &r->sonar1;
    uint32_t now = hal_time_us();
    if (s->waiting) {
        uint32_t echo_us = 0u;
        int st = hal_sonar_poll(HAL_SONAR_FIXED, &echo_us);
        if (st != HAL_SONAR_ECHO && st != HAL_SONAR_TIMEOUT &&
            now - s->ping_us < (uint32_t)r->cfg.echo_timeout_ticks * SLAM_TICK_US) {
            return;
        }
        s->waiting = false;
        s->reading.echo = st == HAL_SONAR_ECHO;
        s->reading.range_um = s->reading.echo ? sonar_range_um(&r->mapper.sonar, echo_us) : 0u;
        s->readings++;
        s->echoes += s->reading.echo ? 1u : 0u;
        robot_map(r, &s->reading);
        return;
    }
    if (sweep_waiting(&r->sweep) ||
        now - s->ping_us < (uint32_t)r->cfg.ping_interval_ticks * SLAM_TICK_US) {
        return;
    }
    /* The pose is three words the tick rewrites: copy it in one piece, at the ping. */
    hal_irq_state_t irq = hal_critical_enter();
    odom_pose_t pose = odom_pose(&r->odom);
    hal_critical_exit(irq);
    s->ping_us = now;
    if (hal_sonar_trigger(HAL_SONAR_FIXED) == HAL_OK) {
        s->waiting = true;
        s->reading =
            (readq_reading_t){.ping = pose, .servo = fix_bam_from_mdeg(r->cfg.sonar1_mdeg)};
    }
}

/* Commands from the UART, then what waits for the robot to stand. Kept out of line, so
 * its buffers are not on the stack while robot_idle() saves the maps. */
__attribute__((noinline)) static void robot_commands(robot_t *r, uint32_t ticks)
{
    uint8_t rx[ROBOT_RX_BYTES];
    size_t n = hal_uart_read(rx, sizeof rx);
    telem_rx_expire(&r->telem, ticks);
    for (size_t i = 0; i < n; i++) {
        telem_cmd_t c;
        if (telem_rx_byte(&r->telem, rx[i], ticks, &c)) {
            robot_command(r, &c);
        }
    }
    if (r->pending != 0u) {
        robot_hold(r, ROBOT_HOLD_COMMAND, true);
        if (r->held) {
            robot_reconfigure(r, (r->pending & ROBOT_PENDING_RESEED) != 0u);
            r->pending = 0u;
            robot_hold(r, ROBOT_HOLD_COMMAND, false);
        }
    }
}

void robot_idle(robot_t *r)
{
    /* The watchdog is fed only while the tick makes progress, so a dead tick resets us. */
    uint32_t ticks = *(volatile const uint32_t *)&r->ticks; /* written by the tick */
    if (ticks != r->idle_ticks) {
        r->idle_ticks = ticks;
        hal_watchdog_kick();
    }
    robot_commands(r, ticks);
    robot_readings(r);
    if (r->sonar1.on) {
        robot_sonar1(r);
    }
    explore_way_work(&r->explore.way, &r->grid);

    uint32_t period = (uint32_t)r->cfg.save_period_s * (1000000u / SLAM_TICK_US);
    bool due = period != 0u && (int32_t)(ticks - r->next_save) >= 0;
    if (!r->store.active && r->store.available && (due || r->save_requested)) {
        /* Stop first: beginning a slot erases it, which may stall the CPU. */
        robot_hold(r, ROBOT_HOLD_SAVE, true);
        if (r->held) {
            /* The pose is three words the tick rewrites: copy it in one piece. */
            hal_irq_state_t irq = hal_critical_enter();
            odom_pose_t pose = r->pose;
            hal_critical_exit(irq);
            r->save_requested = false;
            r->next_save = ticks + period;
            mapstore_begin(&r->store, &r->grid, &pose, ticks);
            robot_hold(r, ROBOT_HOLD_SAVE, false);
        }
    }
    (void)mapstore_step(&r->store, &r->grid);

    telem_status_t st = {
        .ticks = ticks,
        .pings = r->sweep.pings,
        .echoes = r->sweep.echoes,
        .timeouts = r->sweep.timeouts,
        .om_hits = r->mapper.hits,
        .overruns = hal_tick_overruns(),
        .saves = r->store.saves,
        .explore_mode = r->cfg.explore_mode,
        .flags = (uint8_t)(((r->hold & ROBOT_HOLD_STOP) != 0u ? TELEM_FLAG_STOPPED : 0u) |
                           (r->pending != 0u ? TELEM_FLAG_PENDING : 0u) |
                           (explore_explored(&r->explore) ? TELEM_FLAG_EXPLORED : 0u)),
        .outside = r->grid.rejected,
    };
    telem_idle(&r->telem, &r->grid, &r->cfg, &st, ticks);
}
