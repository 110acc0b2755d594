/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The one table of exploration modes: what `explore_mode` may hold.
 *
 * X(ENUM, value, name, summary): the enum constant (config.h's explore_mode_t), its
 * number (the configuration's value and the MODE command's byte: never renumber one, add
 * new modes at the end), the name every program and tool uses for it (host_sim
 * --explore, the telemetry tools' `mode` command), and one line saying what it does.
 * Everything else that lists the modes is generated from these rows.
 */
#ifndef SLAM_EXPLORE_MODES_H
#define SLAM_EXPLORE_MODES_H

#define SLAM_EXPLORE_MODES(X)                                                                      \
    X(EXPLORE_OFF, 0, off, "stand still; the map still updates")                                   \
    X(EXPLORE_RANDOM, 1, random, "the paper's random exploration with obstacle avoidance")         \
    X(EXPLORE_TM, 2, tm, "head for the least-visited cells of TM")                                 \
    X(EXPLORE_SQUARE, 3, square, "drive a square, counter-clockwise (odometry tests)")             \
    X(EXPLORE_WALLS, 4, walls, "follow what is met on the right; leave for the least visited way") \
    X(EXPLORE_UMBMARK, 5, umbmark, "the UMBmark test that calibrates odometry (umbmark.h)")

#endif /* SLAM_EXPLORE_MODES_H */
