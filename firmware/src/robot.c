/* SPDX-License-Identifier: MIT */
/* The robot: one control tick reads the sensors through the HAL and runs the core. */
#include "slam/robot.h"

#include "hal/hal.h"
#include "slam/error.h"

#define ROBOT_POSE_EVERY 10u /* ticks between POSE telemetry events */

SLAM_START_UP int robot_init(robot_t *r, const slam_config_t *cfg)
{
    if (slam_config_check(cfg, NULL) != SLAM_OK) {
        return SLAM_EINVAL;
    }
    hal_motor_set(HAL_WHEEL_LEFT, 0);
    hal_motor_set(HAL_WHEEL_RIGHT, 0);

    r->cfg = *cfg;
    odom_init(&r->odom, cfg, hal_encoder_count(HAL_WHEEL_LEFT), hal_encoder_count(HAL_WHEEL_RIGHT));
    sweep_init(&r->sweep, cfg);
    mapper_init(&r->mapper, cfg);
    readq_init(&r->readq, cfg);
    loc_init(&r->loc, cfg);
    explore_init(&r->explore, cfg);
    umbmark_init(&r->umbmark, cfg);
    r->loc.on = r->loc.on && !r->umbmark.on; /* UMBmark measures odometry itself */
    motion_init(&r->motion, cfg);
    grid_init(&r->grid, cfg);
    r->pose = odom_pose(&r->odom);
    r->bumps = hal_bump_count();
    r->bump_closed = false;
    r->bump_news = false;
    r->bumped = 0u;
    r->last = (sweep_out_t){0};
    r->ticks = 0u;
    r->tick_us = hal_time_us();
    r->ping_errors = 0u;
    r->idle_ticks = 0u;
    mapstore_init(&r->store, &r->grid);
    telem_init(&r->telem);
    r->next_save = (uint32_t)cfg->save_period_s * (1000000u / SLAM_TICK_US);
    r->save_requested = false;
    r->hold = 0u;
    r->held = false;
    r->pending = 0u;
    /* The second sonar's readings are mapped in robot_idle(), where the deferred readings
     * are: with the tick mapping OM itself, the two would write cells at once. */
    r->sonar1 = (robot_sonar1_t){
        .on = cfg->sonar1_map != 0u && hal_sonar_count() > HAL_SONAR_FIXED && r->readq.deferred,
        .ping_us = r->tick_us,
    };
    return SLAM_OK;
}

/* Asks the sonar for news only while the sweep waits for an echo. */
static sweep_echo_t poll_sonar(const sweep_t *s, uint32_t *echo_us)
{
    *echo_us = 0u;
    if (!sweep_waiting(s)) {
        return SWEEP_ECHO_PENDING;
    }
    switch (hal_sonar_poll(HAL_SONAR_SWEPT, echo_us)) {
    case HAL_SONAR_ECHO:
        return SWEEP_ECHO_DONE;
    case HAL_SONAR_TIMEOUT:
        return SWEEP_ECHO_TIMEOUT;
    default:
        return SWEEP_ECHO_PENDING;
    }
}

/*
 * Whether a bump switch has closed since the exploration last took a stall: the body is
 * against something, told at once where stalled wheels tell it a few ticks later. Only
 * a closing counts (a switch stays closed while the robot backs away); a tick that maps a
 * reading leaves it to the next, as it leaves stalls. A switch that cannot be read counts
 * as open (the wheels still tell).
 */
static bool bump_news(robot_t *r)
{
    bool closed = false;
    for (uint8_t b = 0; b < r->bumps && !closed; b++) {
        bool pressed = false;
        closed = hal_bump_read(b, &pressed) == HAL_OK && pressed;
    }
    if (closed && !r->bump_closed) {
        r->bump_news = true;
        r->bumped++;
    }
    r->bump_closed = closed;
    bool news = r->bump_news;
    r->bump_news = news && r->last.reading_ready;
    return news;
}

void robot_tick(robot_t *r)
{
    /* The periods since the last tick: more than one when ticks were lost (a tick that
     * overran, a late timer), and the wheels' travel then spans them all. */
    uint32_t now_us = hal_time_us();
    uint32_t dt_us = now_us - r->tick_us;
    r->tick_us = now_us;
    uint32_t periods = 1u;
    if (dt_us > SLAM_TICK_US + SLAM_TICK_US / 2u) {
        periods = (dt_us + SLAM_TICK_US / 2u) / SLAM_TICK_US;
    }
    /* Where are we: one odometry step (Eq. 8-12), and the correction against the map. */
    odom_step(&r->odom, hal_encoder_count(HAL_WHEEL_LEFT), hal_encoder_count(HAL_WHEEL_RIGHT));
    odom_pose_t odom = odom_pose(&r->odom);
    r->pose = loc_tick_pose(&r->loc, &odom);

    /* What does the sonar say: one step of the sweep. */
    uint32_t echo_us;
    sweep_echo_t echo = poll_sonar(&r->sweep, &echo_us);
    sweep_step(&r->sweep, echo, echo_us, &r->last);
    if (r->last.servo_cmd) {
        (void)hal_servo_set_pulse(HAL_SERVO_SWEEP, r->last.servo_pulse_us);
    }
    if (r->last.trigger && hal_sonar_trigger(HAL_SONAR_SWEPT) != HAL_OK) {
        r->ping_errors++;
    }

    /* Algorithm C.1: here whole, or TM here and the reading handed to robot_idle(), which
     * maps it (free-space evidence is too much work for a tick) and corrects the pose. */
    if (!r->readq.deferred) {
        mapper_tick(&r->mapper, &r->grid, &r->pose, &r->last);
    } else {
        (void)grid_tm_visit(&r->grid, r->pose.x_um, r->pose.y_um);
        if (r->last.reading_ready) {
            const sweep_reading_t *rd = &r->last.reading;
            /* Exploration remembers the obstacle at once, where the robot believes it (the
             * tick's correction is none with localization off). */
            odom_pose_t at = loc_apply(&r->loc.tick.corr, &r->mapper.ping_pose);
            mapper_note(&r->mapper, &at, rd);
            const readq_reading_t q = {
                .ping = r->mapper.ping_pose,
                .range_um = rd->echo ? sonar_range_um(&r->mapper.sonar, rd->echo_us) : 0u,
                .servo = rd->servo,
                .echo = rd->echo,
            };
            /* The correction published for the reading before, if the loop is done with it
             * (none is ever published with localization off). */
            if (readq_post(&r->readq, &q) == READQ_CURRENT) {
                loc_adopt(&r->loc);
            }
        }
        if (r->last.trigger) {
            r->mapper.ping_pose = odom; /* readings are logged and mapped from odometry */
        }
    }

    /* Telemetry: the pose ten times a second, and every reading. */
    if (r->ticks % ROBOT_POSE_EVERY == 0u) {
        telem_post_pose(&r->telem, r->ticks, &r->pose);
    }
    if (r->last.reading_ready) {
        const sweep_reading_t *rd = &r->last.reading;
        uint32_t range = rd->echo ? sonar_range_um(&r->mapper.sonar, rd->echo_us) : 0u;
        telem_post_reading(&r->telem, r->ticks, rd->stop, (uint8_t)r->mapper.last, rd->servo_mdeg,
                           range, &r->mapper.ping_pose);
    }

    /* Where to go, and the wheel speeds that get us there. Under a hold the exploration
     * waits where it is and the robot comes to a stand. */
    int32_t target_mm_s[2] = {0, 0};
    bool hold = r->hold != 0u;
    if (hold) {
        /* stand */
    } else if (r->umbmark.on) {
        if (umbmark_step(&r->umbmark, &odom, target_mm_s)) {
            /* A run begins where the robot has been put: the start pose. */
            odom_set_pose(&r->odom, &r->umbmark.start);
            r->pose = r->umbmark.start;
        }
    } else {
        bool stalled = motion_stalled(&r->motion);
        r->explore.moves.one_wheel = stalled && motion_one_wheel(&r->motion);
        if (r->bumps != 0u && bump_news(r)) {
            stalled = true;
            r->explore.moves.one_wheel = false;
        }
        explore_step(&r->explore, &r->pose, &r->last, &r->mapper, &r->grid, r->loc.tick.ahead,
                     stalled, target_mm_s);
    }
    motion_set_target(&r->motion, target_mm_s[ODOM_LEFT], target_mm_s[ODOM_RIGHT]);
    int16_t duty[2];
    motion_step(&r->motion, &r->odom, periods, duty);
    hal_motor_set(HAL_WHEEL_LEFT, duty[ODOM_LEFT]);
    hal_motor_set(HAL_WHEEL_RIGHT, duty[ODOM_RIGHT]);
    r->held = hold && motion_at_rest(&r->motion);

    r->ticks++;
}
