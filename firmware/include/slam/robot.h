/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The robot: wires the modules of the core to the HAL.
 *
 * A backend's program entry owns one `robot_t` (static storage), calls hal_init(), then
 * robot_init(), then hal_tick_start() with a callback that calls robot_tick(), and runs
 * robot_idle() in its background loop.
 *
 * robot_tick() is the body of the 10 ms control interrupt. Its work is O(1): one
 * odometry step, one sweep step (at most one servo command, one ping, one reading), one
 * TM update and at most one OM update (Algorithm C.1), one exploration step and one
 * speed-control step. Anything proportional to the map belongs in robot_idle().
 */
#ifndef SLAM_ROBOT_H
#define SLAM_ROBOT_H

#include <stdint.h>

#include "slam/config.h"
#include "slam/explore.h"
#include "slam/grid.h"
#include "slam/localize.h"
#include "slam/mapper.h"
#include "slam/mapstore.h"
#include "slam/motion.h"
#include "slam/odometry.h"
#include "slam/readings.h"
#include "slam/sweep.h"
#include "slam/telemetry.h"
#include "slam/umbmark.h"

/**
 * The second sonar (HAL_SONAR_FIXED), when sonar1_map asks for it and the board has it:
 * pinged by robot_idle(), never by the tick, and only while the sweep's sonar waits for no
 * echo, ping_interval_ticks after its own last ping; each reading mapped as a sweep
 * reading at the servo angle its beam faces (sonar1_mdeg), from the swept sonar's mount.
 */
typedef struct {
    bool on;                 /**< asked for, the board has it, and readings are deferred */
    bool waiting;            /**< a ping is out */
    uint32_t ping_us;        /**< hal_time_us() at the last ping (or ping refused) */
    readq_reading_t reading; /**< the reading under way (its ping's odometry pose), then
                                  the last one mapped */
    uint32_t readings;       /**< readings mapped */
    uint32_t echoes;         /**< of which echoes */
} robot_sonar1_t;

/** All state of the robot's firmware. */
typedef struct {
    slam_config_t cfg;    /**< the configuration in use */
    odom_t odom;          /**< pose tracking */
    sweep_t sweep;        /**< servo sweep */
    mapper_t mapper;      /**< Algorithm C.1 */
    readq_t readq;        /**< completed readings, from the tick to robot_idle() */
    loc_t loc;            /**< pose correction */
    explore_t explore;    /**< where to go */
    umbmark_t umbmark;    /**< the calibration test, instead of exploring (EXPLORE_UMBMARK) */
    motion_t motion;      /**< wheel speed control */
    grid_t grid;          /**< OM and TM */
    odom_pose_t pose;     /**< the pose after the last tick's odometry step */
    sweep_out_t last;     /**< what the sweep did in the last tick (for logs) */
    uint32_t ticks;       /**< control ticks since robot_init() */
    uint32_t tick_us;     /**< hal_time_us() when the last tick began */
    uint32_t ping_errors; /**< pings the sonar refused (busy) */
    uint32_t idle_ticks;  /**< robot_idle(): the tick count it saw last */
    mapstore_t store;     /**< map saves, run by robot_idle() */
    uint32_t next_save;   /**< the tick count at which the next periodic save begins */
    volatile bool save_requested; /**< robot_request_save() was called */
    volatile uint8_t hold;        /**< why robot_idle() asks the tick to stop the robot
                                       (ROBOT_HOLD_* bits); 0: drive */
    volatile bool held;           /**< the tick says the robot stands still under hold */
    uint8_t pending;       /**< commands that wait for the robot to stand (ROBOT_PENDING_*) */
    uint8_t bumps;         /**< the board's bump switches (hal_bump_count()), read every tick */
    bool bump_closed;      /**< a bump switch was closed in the last tick */
    bool bump_news;        /**< one closed since the exploration last took a stall */
    uint32_t bumped;       /**< ticks in which a bump switch closed (the first of each contact) */
    robot_sonar1_t sonar1; /**< the second sonar, run by robot_idle() */
    telem_t telem;         /**< telemetry: posted by the tick, sent by robot_idle() */
} robot_t;

/** Reasons to hold the robot still: a save beginning, a command waiting to be applied,
 *  and STOP (until START; the sweep goes on mapping). Written by robot_idle() only. */
#define ROBOT_HOLD_SAVE 0x01u
#define ROBOT_HOLD_COMMAND 0x02u
#define ROBOT_HOLD_STOP 0x04u

/**
 * What the calibration run (the CALIBRATE command) drives: the UMBmark test (umbmark.h),
 * umbmark_runs squares of square_side_um each way from the configured start pose, where
 * a person puts the robot during the pause before each run. While it runs the pose is
 * odometry alone (the correction of localize.h is off: odometry is what it measures).
 */
#define ROBOT_CALIBRATION_MODE EXPLORE_UMBMARK

/**
 * Check the configuration and start the robot: motors off, pose at the configured start,
 * empty maps, the sweep at its first stop. Call after hal_init(), before the tick starts.
 * @retval SLAM_OK      started
 * @retval SLAM_EINVAL  the configuration is bad (see slam_config_check()); @p r and the
 *                      hardware are left untouched
 */
int robot_init(robot_t *r, const slam_config_t *cfg);

/** One control period: the body of the 10 ms interrupt. ISR-context, O(1). */
void robot_tick(robot_t *r);

/**
 * Background work, from the main loop; never called from the tick: feeds the watchdog
 * while ticks progress, takes commands from the UART (telemetry.h: at most
 * ROBOT_RX_BYTES a call, each answered), maps the readings the tick queued (readings.h;
 * through the pose correction when it is on), pings and maps the second sonar
 * (robot_sonar1_t), sends telemetry, and saves the maps (every
 * save_period_s, and on request) a chunk per call. A command that changes the
 * configuration or the exploration mode waits until the tick has brought the robot to a
 * stand, then re-initialises what the configuration feeds (odometry gains, keeping the
 * pose; the sonar's limits; motion; exploration, from the pose where it stands). A save begins only
 * once the tick has brought the robot to a stand: beginning a slot erases it, and on an MCU that
 * stalls the CPU, ticks included, for up to two seconds.
 */
void robot_idle(robot_t *r);

/** Received bytes robot_idle() takes per call at most. */
#define ROBOT_RX_BYTES 32u

/** Ask robot_idle() to save the maps as soon as it can. ISR-safe. */
void robot_request_save(robot_t *r);

#endif /* SLAM_ROBOT_H */
