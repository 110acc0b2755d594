/* SPDX-License-Identifier: MIT */
/**
 * @file
 * What a run offers viewers outside the program: the robot's UART live on a
 * pseudo-terminal (--link, link.c) and the run as a ROS bag (--bag, bag.c).
 */
#ifndef HOST_SIM_VIEWERS_H
#define HOST_SIM_VIEWERS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "host_sim.h"

/* ---- --link PATH (link.c) --------------------------------------------------------------- */

/**
 * The robot's UART as a pseudo-terminal, as the Linux robot offers it (telemetry = pty):
 * what the firmware writes goes out on it (and to --telemetry too, when given), and what
 * a viewer writes to it arrives at the robot's UART as commands, each tick. PATH is a
 * symbolic link to the pseudo-terminal's device, made at start and removed at the end.
 * Writes never block: bytes no one reads are dropped once the terminal's buffer is full,
 * as a UART with no cable drops them.
 */
typedef struct {
    const char *path; /* the symbolic link to it; NULL: no link (a zeroed link_t) */
    int fd;           /* the pseudo-terminal's master end, or -1 */
    int peer;         /* our own hold on its other end: a viewer may come and go */
    char device[128]; /* the other end, /dev/pts/N */
    FILE *sink;       /* the UART sink: the terminal, and tee when set */
    FILE *tee;        /* --telemetry, or NULL */
    uint64_t sent;    /* bytes written to the terminal */
    uint64_t dropped; /* bytes it had no room for */
    uint64_t lost;    /* command bytes the robot's UART had no room for */
} link_t;

/** Check, changing nothing, that PATH can be made a link: 0, or -1 with a message. */
int link_check(const char *path);

/**
 * Open the pseudo-terminal and link PATH to it; say where it is on stderr unless quiet.
 * @return 0, or -1 with a message
 */
int link_open(link_t *l, const char *path, bool quiet);

/** Route the robot's UART to the terminal (and to @p tee, the --telemetry file, or NULL). */
int link_start(link_t *l, FILE *tee);

/**
 * Hand the robot's UART the bytes a viewer wrote (once a tick).
 * @return false once Ctrl-C or SIGTERM asked the run to end (a linked run has no other
 *         end but --duration); true otherwise, and always without a link
 */
bool link_poll(link_t *l);

/** Detach the UART from the terminal, close it and remove the link (safe to repeat, and on
 *  a link never opened). */
void link_close(link_t *l);

/* ---- --bag FILE (bag.c) ------------------------------------------------------------------- */

/**
 * Check before the run that FILE can be written and that tools/rosbag_out.py can run
 * (Debian's python3-rosbag and the message packages): 0, or -1 with a message saying
 * what to install.
 */
int bag_check(const char *file);

/**
 * Write the run's files in @p dir as a ROS bag (tools/rosbag_out.py): the maps, the
 * odometry, the true pose and the sonar with its cone (@p cone_deg) and range
 * (range_min_um of the configuration, @p max_m).
 * @return 0, or 1 with a message
 */
int bag_write(const char *dir, const char *file, double cone_deg, double max_m, bool quiet);

#endif /* HOST_SIM_VIEWERS_H */
