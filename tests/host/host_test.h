/* SPDX-License-Identifier: MIT */
/* Helpers shared by the host world's tests: scratch files, small rooms, a world per test. */
#ifndef HOST_TEST_H
#define HOST_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "host/sim.h"

/* Compare with decimal constants through (double): on x87 (-m32) C evaluates a bare
   constant like 0.3 in long double, which no double equals. */

#define TEST_PI 3.14159265358979323846

/* A scratch path in the test's build directory, unique to the process and a tag. */
static inline const char *test_path(const char *tag)
{
    static char buf[8][512];
    static unsigned n;
    char *p = buf[n++ % 8u];
    snprintf(p, sizeof buf[0], "%s/scratch-%ld-%s", HOST_TEST_DIR, (long)getpid(), tag);
    return p;
}

/* Write a text file; returns its path. */
static inline const char *test_write(const char *tag, const char *text)
{
    const char *path = test_path(tag);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, strlen(text), f), strlen(text));
    fclose(f);
    return path;
}

/* Load a room from text; fails the test on an error. */
static inline void test_room(room_t *r, const char *text)
{
    char err[300] = "";
    const char *path = test_write("room.room", text);
    int rc = room_load(r, path, NULL, err, sizeof err);
    if (rc != 0) {
        fail_msg("room_load: %s", err);
    }
    unlink(path);
}

/* Loading fails with a message that is @p path followed by @p after, and the room is left
 * as it was. */
static inline void test_load_refused(const char *path, const room_crop_t *crop, const char *after)
{
    room_t r;
    room_t before;
    memset(&r, 0xA5, sizeof r);
    memcpy(&before, &r, sizeof r);
    char err[400] = "";
    assert_int_equal(room_load(&r, path, crop, err, sizeof err), -1);
    char want[800];
    snprintf(want, sizeof want, "%s%s", path, after);
    if (strncmp(err, want, strlen(want)) != 0) {
        fail_msg("got \"%s\", want \"%s...\"", err, want);
    }
    assert_memory_equal(&r, &before, sizeof r); /* untouched */
}

/* A world with the given errors in a room. */
static inline sim_t *test_world(const room_t *r, const sim_errors_t *e, uint64_t seed)
{
    sim_params_t p;
    sim_params_default(&p);
    sim_t *s = sim_create(r, &p, e, seed);
    assert_non_null(s);
    return s;
}

static inline sim_t *test_ideal_world(const room_t *r)
{
    sim_errors_t e;
    sim_errors_ideal(&e);
    return test_world(r, &e, 1u);
}

/* Wrapped angle difference a - b in (-pi, pi]. */
static inline double test_angle_diff(double a, double b)
{
    double d = a - b;
    while (d > TEST_PI) {
        d -= 2.0 * TEST_PI;
    }
    while (d <= -TEST_PI) {
        d += 2.0 * TEST_PI;
    }
    return d;
}

#endif /* HOST_TEST_H */
