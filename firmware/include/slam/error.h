/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The one error enum of the mapping core.
 *
 * A fallible call of the core returns `int`: 0 (SLAM_OK) or one of the negative codes
 * below. A value and an error are never folded into one return.
 */
#ifndef SLAM_ERROR_H
#define SLAM_ERROR_H

/** Return codes of the core; every error is negative. */
typedef enum {
    SLAM_OK = 0,        /**< success */
    SLAM_EINVAL = -1,   /**< an argument or configuration value is out of its range */
    SLAM_EOUTSIDE = -2, /**< a world point lies outside the A×B grid */
    SLAM_EIO = -3,      /**< the hardware (HAL) reported a failure */
    SLAM_ENOSYS = -4,   /**< the operation is not supported by this build or backend */
} slam_err_t;

#endif /* SLAM_ERROR_H */
