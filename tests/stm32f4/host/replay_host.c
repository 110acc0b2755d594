/* SPDX-License-Identifier: MIT */
/*
 * The host half of the STM32F4 self-test: the scenario the MCU image replays, run through
 * the same replay HAL and self-test code on the PC, printing the same report.
 *
 *   replay_host [--check-trace TRACE]
 *
 * --check-trace first decodes the compiled-in scenario tick by tick against the text
 * trace it was generated from (read with hal_common's trace_read()), so the generator and
 * the decoder are checked against the project's own trace reader. Exit status 0 when
 * everything matches, the replay saw no mismatch and the pose correction applied matches
 * (when on), 1 otherwise, 2 on a bad argument.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal/hal.h"
#include "hal_common/config_text.h"
#include "hal_common/trace.h"
#include "hal_replay.h"
#include "selftest.h"

static robot_t robot;

uint32_t selftest_counter(void)
{
    return 0u;
}

void selftest_print(const char *s)
{
    fputs(s, stdout);
}

/* The rest of the platform's part of the HAL is hal_synchronous's: the tick and the
 * background loop run in turn here, in one thread. */

/* The configuration as text, so two can be compared field by field without padding. */
static char *config_text(const slam_config_t *cfg)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (f == NULL) {
        return NULL;
    }
    cfgtext_write_raw(f, cfg, "");
    fclose(f);
    return buf;
}

static int check_trace(const char *path)
{
    slam_config_t cfg;
    trace_tick_t *ticks = NULL;
    size_t n = 0;
    char err[256];
    if (trace_read(path, &cfg, &ticks, &n, err, sizeof err) != 0) {
        fprintf(stderr, "replay_host: %s\n", err);
        return 1;
    }
    int rc = 0;
    slam_config_t compiled;
    replay_scenario.config(&compiled);
    char *a = config_text(&cfg);
    char *b = config_text(&compiled);
    if (a == NULL || b == NULL || strcmp(a, b) != 0) {
        fprintf(stderr, "replay_host: %s: the compiled-in configuration differs from the trace's\n",
                path);
        rc = 1;
    }
    free(a);
    free(b);
    if (n != replay_scenario.ticks) {
        fprintf(stderr, "replay_host: %s has %zu ticks, the compiled-in scenario %lu\n", path, n,
                (unsigned long)replay_scenario.ticks);
        rc = 1;
    }
    replay_start(&replay_scenario);
    for (size_t i = 0; rc == 0 && i < n; i++) {
        trace_tick_t t;
        const trace_tick_t *w = &ticks[i];
        if (replay_next(&t) != 0) {
            fprintf(stderr, "replay_host: the compiled-in scenario does not decode at tick %zu\n",
                    i);
            rc = 1;
        } else if (t.enc[0] != w->enc[0] || t.enc[1] != w->enc[1] || t.poll != w->poll ||
                   t.echo_us != w->echo_us || t.trig != w->trig || t.duty[0] != w->duty[0] ||
                   t.duty[1] != w->duty[1] || t.servo_us != w->servo_us) {
            fprintf(stderr, "replay_host: tick %zu decodes differently from %s\n", i, path);
            rc = 1;
        }
    }
    if (rc == 0 && replay_next(NULL) != -1) {
        fprintf(stderr, "replay_host: the compiled-in scenario has bytes after its last tick\n");
        rc = 1;
    }
    free(ticks);
    if (rc == 0) {
        fprintf(stderr, "replay_host: %s: %zu ticks decode identically\n", path, n);
    }
    return rc;
}

int main(int argc, char **argv)
{
    int rc = 0;
    if (argc == 3 && strcmp(argv[1], "--check-trace") == 0) {
        rc = check_trace(argv[2]);
    } else if (argc != 1) {
        fprintf(stderr, "usage: replay_host [--check-trace TRACE]\n");
        return 2;
    }
    selftest_t st;
    if (selftest_begin(&st, &robot, NULL, 0u) == 0) {
        while (!selftest_done(&st)) {
            selftest_step(&st);
            robot_idle(&robot);
        }
    }
    selftest_report(&st, false);
    if (!selftest_passed(&st)) {
        fprintf(stderr, "replay_host: the replay failed (see the 'replay' line)\n");
        rc = 1;
    }
    if (robot.cfg.localize != 0u && robot.loc.match.applied == 0u) {
        fprintf(stderr, "replay_host: the scenario never applies the pose correction: a longer "
                        "trace is needed (make trace)\n");
        rc = 1;
    }
    return rc;
}
