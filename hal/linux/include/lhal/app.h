/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The sonarslam-linux program as a function, so tests can run it against a fake GPIO.
 *
 *   sonarslam-linux --config robot.conf [--check] [--ticks N]
 *
 * Exit status: APP_EXIT_OK; APP_EXIT_HARDWARE when the hardware cannot be opened or
 * --check finds a problem; APP_EXIT_USAGE for a bad command line or configuration;
 * APP_EXIT_SAFETY when the backend stopped the motors on its own (watchdog, I/O fault).
 */
#ifndef LHAL_APP_H
#define LHAL_APP_H

#include <stdio.h>

enum {
    APP_EXIT_OK = 0,
    APP_EXIT_HARDWARE = 1,
    APP_EXIT_USAGE = 2,
    APP_EXIT_SAFETY = 3,
};

/**
 * Run the program.
 * @param out  reports (--help, --check, the run's summary)
 * @param err  errors and warnings
 * @return the exit status
 */
int app_main(int argc, char **argv, FILE *out, FILE *err);

#endif /* LHAL_APP_H */
