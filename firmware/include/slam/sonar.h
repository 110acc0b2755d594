/* SPDX-License-Identifier: MIT */
/**
 * @file
 * From one sonar reading to an obstacle point in the world (paper §II.A, Eq. 3-5).
 *
 * The HC-SR04 reports the width of its echo pulse; the distance is half the sound's
 * round trip, d = width · c / 2. The servo turns the sensor about a vertical axis mounted
 * at (mount_x, mount_y) in the robot frame (x forward, y left); servo angle θo = 90°
 * points straight ahead (plus an optional mount yaw). The beam's world bearing is
 *
 *     θ = Ψ + (π/2 − θo) + yaw                       (Eq. 3)
 *
 * and the obstacle lies at distance d along it from the servo axis:
 *
 *     xo = xs + d·cos θ,  yo = ys + d·sin θ          (Eq. 4-5)
 *
 * where (xs, ys) is the servo axis in the world: the robot pose plus the mount offset
 * rotated by Ψ. With a zero offset this is exactly the paper's equations.
 * Only readings inside the confidence sector (range_min <= d < rc) are used for OM.
 */
#ifndef SLAM_SONAR_H
#define SLAM_SONAR_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/config.h"
#include "slam/fixed.h"
#include "slam/odometry.h"

/** Sensor geometry and conversions, fixed at initialisation. */
typedef struct {
    int32_t mount_x_um;          /**< servo axis in the robot frame, forward */
    int32_t mount_y_um;          /**< servo axis in the robot frame, left */
    bam32_t mount_yaw;           /**< extra yaw of the servo frame */
    uint32_t um_per_echo_us_q16; /**< c / 2 in µm per µs of echo, Q16.16 */
    uint32_t range_min_um;       /**< shorter readings are discarded */
    uint32_t confidence_um;      /**< rc */
} sonar_t;

/** Set the geometry and conversions from a checked configuration. */
void sonar_init(sonar_t *s, const slam_config_t *cfg);

/**
 * Distance of an echo: d = width · c / 2, rounded to whole µm. ISR-safe, O(1).
 * @param echo_us  echo pulse width in µs (any value; 38 ms is about 6.5 m)
 */
uint32_t sonar_range_um(const sonar_t *s, uint32_t echo_us);

/** Whether a distance lies in the confidence sector: range_min <= d < rc. */
bool sonar_in_confidence(const sonar_t *s, uint32_t range_um);

/** World bearing of the beam (Eq. 3) for robot heading Ψ and servo angle θo. */
bam32_t sonar_bearing(const sonar_t *s, bam32_t heading, bam32_t servo);

/** A reading's beam in the world: where it starts and its direction. */
typedef struct {
    int32_t x_um; /**< the servo axis */
    int32_t y_um;
    q1_30_t c; /**< cos and sin of the bearing θ (Eq. 3) */
    q1_30_t s;
} sonar_beam_t;

/** The beam of a reading from a pose at a servo angle (Eq. 3 and the mount). O(1). */
void sonar_beam(const sonar_t *s, const odom_pose_t *pose, bam32_t servo, sonar_beam_t *b);

/** The point at a distance along a beam (Eq. 4-5), saturated at the int32_t limits. */
void sonar_beam_point(const sonar_beam_t *b, uint32_t range_um, int32_t *x_um, int32_t *y_um);

/**
 * The servo axis in the world: the pose plus the mount offset turned by Ψ. ISR-safe, O(1).
 * @param x_um, y_um  out: where every beam of this pose starts, µm
 */
void sonar_origin(const sonar_t *s, const odom_pose_t *pose, int32_t *x_um, int32_t *y_um);

/**
 * The obstacle point of a reading (Eq. 4-5 with the mount offset): sonar_beam_point() of
 * its sonar_beam(). ISR-safe, O(1).
 * @param pose      robot pose at the moment of the ping
 * @param servo     servo angle θo of the reading
 * @param range_um  d
 * @param x_um, y_um  out: the obstacle point in the world, µm (saturated at the
 *                    int32_t limits, which lie far outside any grid)
 */
void sonar_obstacle(const sonar_t *s, const odom_pose_t *pose, bam32_t servo, uint32_t range_um,
                    int32_t *x_um, int32_t *y_um);

#endif /* SLAM_SONAR_H */
