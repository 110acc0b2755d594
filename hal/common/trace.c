/* SPDX-License-Identifier: MIT */
/* HAL traces: writing and reading the tick-by-tick record of a run. */
#include "hal_common/trace.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"

void trace_write_header(FILE *f, const slam_config_t *cfg)
{
    fprintf(f, "sonarslam-trace 1\n");
    cfgtext_write_raw(f, cfg, "config ");
}

void trace_write_tick(FILE *f, const trace_tick_t *t)
{
    fprintf(f, "tick %u %u %c %lu %c %d %d %u\n", (unsigned)t->enc[0], (unsigned)t->enc[1], t->poll,
            (unsigned long)t->echo_us, t->trig, (int)t->duty[0], (int)t->duty[1],
            (unsigned)t->servo_us);
}

void trace_write_end(FILE *f, uint64_t ticks)
{
    fprintf(f, "end %llu\n", (unsigned long long)ticks);
}

static int parse_tick(const char *line, trace_tick_t *t)
{
    unsigned e0;
    unsigned e1;
    unsigned long echo;
    int d0;
    int d1;
    unsigned servo;
    char poll;
    char trig;
    int used = 0;
    if (sscanf(line, "tick %u %u %c %lu %c %d %d %u%n", &e0, &e1, &poll, &echo, &trig, &d0, &d1,
               &servo, &used) != 8 ||
        line[used] != '\0' || e0 > UINT16_MAX || e1 > UINT16_MAX || echo > UINT32_MAX ||
        strchr("-ibet", poll) == NULL || strchr("-ob", trig) == NULL || d0 < INT16_MIN ||
        d0 > INT16_MAX || d1 < INT16_MIN || d1 > INT16_MAX || servo > UINT16_MAX) {
        return -1;
    }
    *t = (trace_tick_t){
        .enc = {(uint16_t)e0, (uint16_t)e1},
        .poll = poll,
        .echo_us = (uint32_t)echo,
        .trig = trig,
        .duty = {(int16_t)d0, (int16_t)d1},
        .servo_us = (uint16_t)servo,
    };
    return 0;
}

int trace_read(const char *path, slam_config_t *cfg, trace_tick_t **ticks, size_t *n, char *err,
               size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    slam_config_t c;
    slam_config_default(&c);
    trace_tick_t *v = NULL;
    size_t len = 0;
    size_t cap = 0;
    char line[256];
    unsigned lineno = 0;
    int ended = 0;
    int rc = 0;
    while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
        lineno++;
        line[strcspn(line, "\r\n")] = '\0';
        char key[64];
        long long raw;
        unsigned long long count;
        char msg[160] = "";
        if (lineno == 1) {
            if (strcmp(line, "sonarslam-trace 1") != 0) {
                snprintf(msg, sizeof msg, "not a version 1 sonarslam trace");
            }
        } else if (ended) {
            snprintf(msg, sizeof msg, "text after the end line");
        } else if (strncmp(line, "config ", 7) == 0) {
            if (sscanf(line, "config %63s %lld", key, &raw) != 2) {
                snprintf(msg, sizeof msg, "expected 'config KEY VALUE'");
            } else {
                (void)cfgtext_set_raw(&c, key, raw, msg, sizeof msg);
            }
        } else if (strncmp(line, "tick ", 5) == 0) {
            if (len == cap) {
                cap = cap ? 2u * cap : 4096u;
                trace_tick_t *grown = realloc(v, cap * sizeof *v);
                if (grown == NULL) {
                    snprintf(msg, sizeof msg, "out of memory");
                } else {
                    v = grown;
                }
            }
            if (msg[0] == '\0' && parse_tick(line, &v[len]) != 0) {
                snprintf(msg, sizeof msg, "malformed tick line");
            } else if (msg[0] == '\0') {
                len++;
            }
        } else if (sscanf(line, "end %llu", &count) == 1) {
            ended = 1;
            if (count != len) {
                snprintf(msg, sizeof msg, "end says %llu ticks, the trace has %zu", count, len);
            }
        } else {
            snprintf(msg, sizeof msg, "unexpected line");
        }
        if (msg[0] != '\0') {
            snprintf(err, errlen, "%s:%u: %s", path, lineno, msg);
            rc = -1;
        }
    }
    fclose(f);
    if (rc == 0 && !ended) {
        snprintf(err, errlen, "%s: no end line (truncated trace?)", path);
        rc = -1;
    }
    if (rc != 0) {
        free(v);
        return -1;
    }
    *cfg = c;
    *ticks = v;
    *n = len;
    return 0;
}
