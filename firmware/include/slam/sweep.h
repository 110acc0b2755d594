/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The servo sweep of the sonar (paper §II.A): a state machine run once per control tick.
 *
 * The servo visits its stops from the first angle to the last (40°, 60°, ... 180°: eight
 * stops 20° apart by default; the paper's 65°, 83°, ... 155° with slam_config_paper()) and
 * then back from the last to the first, over and over;
 * each direction visits every stop once, so every bearing is sampled equally often.
 * At each stop:
 *
 *   1. command the servo (the tick the stop begins);
 *   2. wait settle_ticks for it to get there and settle, and until ping_interval_ticks
 *      have passed since the last ping (the sensor's measurement cycle: a ping sooner
 *      may hear the late echo of the one before);
 *   3. trigger the ping;
 *   4. wait for the echo, or for a timeout (the HAL's own, or echo_timeout_ticks);
 *   5. deliver exactly one reading tagged with the stop's servo angle, and begin the next
 *      stop in the same tick.
 *
 * The module does no I/O: sweep_step() takes what the sonar reported this tick and says
 * what to do (command the servo, trigger a ping) and what was read. robot_tick() does the
 * HAL calls. All timing is counted in control ticks (10 ms).
 */
#ifndef SLAM_SWEEP_H
#define SLAM_SWEEP_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"

/** What the sonar reported this tick, for a sweep that waits for an echo. */
typedef enum {
    SWEEP_ECHO_PENDING = 0, /**< nothing yet */
    SWEEP_ECHO_DONE,        /**< an echo came back; its width is given */
    SWEEP_ECHO_TIMEOUT,     /**< the sensor gave up (HC-SR04: 38 ms without an echo) */
} sweep_echo_t;

/** One completed sonar reading. */
typedef struct {
    uint8_t stop;       /**< index of the stop, 0 = first angle */
    bool echo;          /**< true: an echo of echo_us; false: a timeout */
    int32_t servo_mdeg; /**< servo angle θo of the stop */
    bam32_t servo;      /**< the same as a binary angle */
    uint32_t echo_us;   /**< echo pulse width in µs (0 on a timeout) */
} sweep_reading_t;

/** What the caller must do in this tick, and what was read. */
typedef struct {
    bool servo_cmd;          /**< command the servo to servo_pulse_us now */
    bool trigger;            /**< trigger a ping now */
    bool reading_ready;      /**< reading holds a completed reading */
    uint16_t servo_pulse_us; /**< servo pulse width, µs */
    sweep_reading_t reading;
} sweep_out_t;

/** Phases of one stop. */
typedef enum {
    SWEEP_BEGIN = 0, /**< the next step commands the servo */
    SWEEP_SETTLE,    /**< the servo is moving and settling */
    SWEEP_WAIT,      /**< the ping is out; waiting for the echo */
} sweep_phase_t;

/** Sweep state and counters. */
typedef struct {
    int32_t stop_mdeg[SLAM_SWEEP_STOPS_MAX];      /**< servo angle of each stop */
    bam32_t stop_bam[SLAM_SWEEP_STOPS_MAX];       /**< the same as binary angles */
    uint16_t stop_pulse_us[SLAM_SWEEP_STOPS_MAX]; /**< the servo pulse of each stop */
    uint8_t stops;                                /**< number of stops n */
    uint8_t settle_ticks;                         /**< ticks from servo command to ping */
    uint8_t echo_timeout_ticks;                   /**< ticks from ping to giving up */
    uint8_t ping_interval_ticks;                  /**< least ticks from one ping to the next */
    uint8_t since_ping;                           /**< ticks since the last ping (saturating) */
    uint8_t seq;       /**< position in the back-and-forth cycle, 0 .. 2n-1 */
    uint8_t phase;     /**< a sweep_phase_t */
    uint8_t ticks;     /**< ticks spent in the phase */
    uint32_t pings;    /**< pings triggered */
    uint32_t echoes;   /**< readings with an echo */
    uint32_t timeouts; /**< readings without one (HAL or sweep timeout) */
} sweep_t;

/** Compute the stops from a checked configuration and start at the first stop. */
void sweep_init(sweep_t *s, const slam_config_t *cfg);

/** Whether the sweep waits for an echo: only then need the caller poll the sonar. */
bool sweep_waiting(const sweep_t *s);

/**
 * One control tick of the sweep. ISR-safe, O(1).
 * @param echo     what the sonar reported this tick (ignored unless sweep_waiting())
 * @param echo_us  the echo width in µs when echo is SWEEP_ECHO_DONE
 * @param out      out: the actions for this tick and a completed reading, if any
 */
void sweep_step(sweep_t *s, sweep_echo_t echo, uint32_t echo_us, sweep_out_t *out);

/** The stop visited at cycle position @p seq (0 .. 2n-1): 0..n-1, then n-1..0. */
uint8_t sweep_stop_at(const sweep_t *s, uint8_t seq);

#endif /* SLAM_SWEEP_H */
