/* SPDX-License-Identifier: MIT */
/* Prints what the compiled C makes of every configuration field and exploration mode, for
 * tests/test_config_tables.py to hold against tools/slamtools/link.py's reading of the tables.
 *
 * Each fact comes from the code that uses it, not from the table alone: the names, their
 * order, the defaults and the types from the text configuration (cfgtext_*), the keys and
 * whether they are live from the telemetry's GET and SET, the words from cfgtext_rule().
 * Only the ranges are the table's own, as the compiler evaluates them (test_config.c holds
 * slam_config_check() to them). Lines, tab-separated:
 *   grid A B
 *   keys MAX KNOWN          TELEM_CONFIG_KEY_MAX and how many ids GET knows
 *   field NAME TYPE DEFAULT LO HI ID LIVE WORDS
 *   mode VALUE NAME
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "slam/config_fields.h"
#include "slam/telemetry.h"

static const struct {
    const char *name;
    long long lo, hi;
} ranges[] = {
#define RANGE(name, type, dflt, lo, hi, rule, id, live, words)                                     \
    {#name, (long long)(lo), (long long)(hi)},
    SLAM_CONFIG_FIELDS(RANGE)
#undef RANGE
};

/* The field's type as the text configuration treats it: which raw values it takes, and
 * whether it writes a decimal. */
static const char *text_type(const char *name, const char *text)
{
    slam_config_t c;
    slam_config_default(&c);
    char err[256];
    if (cfgtext_set_raw(&c, name, -1, err, sizeof err) == 0) {
        return strchr(text, '.') != NULL ? "Q30" : "I32";
    }
    if (cfgtext_set_raw(&c, name, 256, err, sizeof err) != 0) {
        return "U8";
    }
    return cfgtext_set_raw(&c, name, 65536, err, sizeof err) != 0 ? "U16" : "U32";
}

/* The telemetry key whose value follows the field: GET every key, change the field
 * through the text configuration, and see which key's value changed. 0: none, or more
 * than one. */
static unsigned key_of(const char *name, long long raw)
{
    slam_config_t c;
    slam_config_default(&c);
    uint32_t before[256];
    for (unsigned k = 0; k < 256u; k++) {
        before[k] = 0u;
        (void)telem_config_get(&c, (uint8_t)k, &before[k]);
    }
    char err[256];
    if (cfgtext_set_raw(&c, name, raw == 0 ? 1 : raw - 1, err, sizeof err) != 0) {
        return 0u;
    }
    unsigned found = 0u;
    for (unsigned k = 0; k < 256u; k++) {
        uint32_t v = 0u;
        if (telem_config_get(&c, (uint8_t)k, &v) == 0 && v != before[k]) {
            found = found == 0u ? k : 256u;
        }
    }
    return found == 256u ? 0u : found;
}

int main(void)
{
    slam_config_t d;
    slam_config_default(&d);
    FILE *text = tmpfile();
    FILE *raw = tmpfile();
    if (text == NULL || raw == NULL) {
        perror("config_view: tmpfile");
        return 1;
    }
    cfgtext_write(text, &d);
    cfgtext_write_raw(raw, &d, "");
    rewind(text);
    rewind(raw);

    printf("grid\t%u\t%u\n", (unsigned)SLAM_GRID_A, (unsigned)SLAM_GRID_B);
    unsigned known = 0u;
    for (unsigned k = 0; k < 256u; k++) {
        uint32_t v;
        known += telem_config_get(&d, (uint8_t)k, &v) == 0;
    }
    printf("keys\t%u\t%u\n", (unsigned)TELEM_CONFIG_KEY_MAX, known);

    char name[64], value[64], name2[64];
    long long dflt;
    while (fscanf(text, "%63s = %63s\n", name, value) == 2) {
        if (fscanf(raw, "%63s %lld\n", name2, &dflt) != 2 || strcmp(name, name2) != 0) {
            fprintf(stderr, "config_view: cfgtext_write and cfgtext_write_raw disagree at %s\n",
                    name);
            return 1;
        }
        long long lo = 0, hi = -1;
        for (size_t i = 0; i < sizeof ranges / sizeof ranges[0]; i++) {
            if (strcmp(ranges[i].name, name) == 0) {
                lo = ranges[i].lo;
                hi = ranges[i].hi;
            }
        }
        unsigned key = key_of(name, dflt);
        int live = -1;
        if (key != 0u) {
            uint32_t v = 0u;
            (void)telem_config_get(&d, (uint8_t)key, &v);
            slam_config_t c = d;
            int rc = telem_config_set(&c, (uint8_t)key, v);
            live = rc == 0 ? 1 : rc == -(int)TELEM_ERR_FIXED ? 0 : -1;
        }
        const char *words = cfgtext_rule(name);
        printf("field\t%s\t%s\t%lld\t%lld\t%lld\t%u\t%d\t%s\n", name, text_type(name, value), dflt,
               lo, hi, key, live, words != NULL ? words : "(none)");
    }
    fclose(text);
    fclose(raw);

#define MODE(id, value, name, ...) printf("mode\t%d\t%s\n", (int)(id), #name);
    SLAM_EXPLORE_MODES(MODE)
#undef MODE
    return 0;
}
