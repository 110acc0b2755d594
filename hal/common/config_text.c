/* SPDX-License-Identifier: MIT */
/* slam_config_t as `key = value` text: one table of fields, parsing and writing. */
#include "hal_common/config_text.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "slam/error.h"

typedef enum { T_U8, T_U16, T_U32, T_I32, T_Q30 } field_type_t;

typedef struct {
    const char *name;
    size_t offset;
    field_type_t type;
} field_t;

#define F(name, type) {#name, offsetof(slam_config_t, name), type}
static const field_t fields[] = {
    F(wheel_diameter_left_um, T_U32), F(wheel_diameter_right_um, T_U32),
    F(wheel_base_um, T_U32),          F(encoder_counts_per_rev, T_U32),
    F(cal_left, T_Q30),               F(cal_right, T_Q30),
    F(cal_base, T_Q30),               F(start_x_um, T_I32),
    F(start_y_um, T_I32),             F(start_heading_mdeg, T_I32),
    F(cell_um, T_U32),                F(start_cell_a, T_U16),
    F(start_cell_b, T_U16),           F(om_max, T_U8),
    F(tm_max, T_U8),                  F(om_mode, T_U8),
    F(om_hit, T_U8),                  F(om_miss, T_U8),
    F(confidence_radius_um, T_U32),
    F(range_min_um, T_U32),           F(sound_speed_mm_per_s, T_U32),
    F(mount_x_um, T_I32),             F(mount_y_um, T_I32),
    F(mount_yaw_mdeg, T_I32),         F(sweep_first_mdeg, T_I32),
    F(sweep_last_mdeg, T_I32),        F(sweep_stops, T_U8),
    F(settle_ticks, T_U8),            F(echo_timeout_ticks, T_U8),
    F(servo_pulse_0deg_us, T_U16),    F(servo_pulse_180deg_us, T_U16),
    F(post_threshold, T_U8),          F(post_template_k, T_U8),
    F(post_insert, T_U8),
    F(top_speed_mm_s, T_U16),         F(accel_mm_s2, T_U16),
    F(motion_kp_q8, T_U16),           F(motion_ki_q8, T_U16),
    F(explore_mode, T_U8),            F(cruise_mm_s, T_U16),
    F(turn_mm_s, T_U16),              F(avoid_um, T_U32),
    F(clearance_um, T_U32),           F(square_side_um, T_U32),
    F(square_laps, T_U8),
    F(explore_seed, T_U32),           F(save_period_s, T_U16),
    F(localize, T_U8),
    F(ping_interval_ticks, T_U8),     F(follow_um, T_U32),
    F(umbmark_runs, T_U8),            F(umbmark_pause_s, T_U16),
};
#undef F

static const field_t *find_field(const char *key)
{
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        if (strcmp(fields[i].name, key) == 0) {
            return &fields[i];
        }
    }
    return NULL;
}

static int bad_value(const char *key, const char *value, const char *why, char *err, size_t n)
{
    snprintf(err, n, "%s = '%s': %s", key, value, why);
    return -2;
}

/* Stores a whole number into a field of any integer type (a Q30 field takes its raw
 * integer), after checking that it fits the type. */
static int store_int(slam_config_t *cfg, const field_t *f, long long v, const char *value,
                     char *err, size_t n)
{
    static const long long lo[] = {0, 0, 0, INT32_MIN, INT32_MIN};
    static const long long hi[] = {UINT8_MAX, UINT16_MAX, UINT32_MAX, INT32_MAX, INT32_MAX};
    if (v < lo[f->type] || v > hi[f->type]) {
        char why[80];
        snprintf(why, sizeof why, "out of range %lld..%lld", lo[f->type], hi[f->type]);
        return bad_value(f->name, value, why, err, n);
    }
    void *dst = (char *)cfg + f->offset;
    switch (f->type) {
    case T_U8: {
        uint8_t x = (uint8_t)v;
        memcpy(dst, &x, sizeof x);
        break;
    }
    case T_U16: {
        uint16_t x = (uint16_t)v;
        memcpy(dst, &x, sizeof x);
        break;
    }
    case T_U32: {
        uint32_t x = (uint32_t)v;
        memcpy(dst, &x, sizeof x);
        break;
    }
    default: {
        int32_t x = (int32_t)v;
        memcpy(dst, &x, sizeof x);
        break;
    }
    }
    return 0;
}

static const field_t *known_field(const char *key, char *err, size_t n)
{
    const field_t *f = find_field(key);
    if (f == NULL) {
        snprintf(err, n, "unknown key '%s'", key);
    }
    return f;
}

int cfgtext_set(slam_config_t *cfg, const char *key, const char *value, char *err, size_t n)
{
    const field_t *f = known_field(key, err, n);
    if (f == NULL) {
        return -1;
    }
    char *end = NULL;
    errno = 0;
    if (f->type == T_Q30) {
        double v = strtod(value, &end);
        if (end == value || *end != '\0' || errno != 0 || !isfinite(v)) {
            return bad_value(key, value, "expected a decimal number such as 0.9901", err, n);
        }
        if (v <= -2.0 || v >= 2.0) {
            return bad_value(key, value, "must lie between -2 and 2", err, n);
        }
        return store_int(cfg, f, lround(v * (double)FIX_Q30_ONE), value, err, n);
    }
    long long v = strtoll(value, &end, 10);
    if (end == value || *end != '\0' || errno != 0) {
        return bad_value(key, value, "expected a whole number", err, n);
    }
    return store_int(cfg, f, v, value, err, n);
}

int cfgtext_set_raw(slam_config_t *cfg, const char *key, long long raw, char *err, size_t n)
{
    const field_t *f = known_field(key, err, n);
    if (f == NULL) {
        return -1;
    }
    char text[32];
    snprintf(text, sizeof text, "%lld", raw);
    return store_int(cfg, f, raw, text, err, n);
}

/* The raw integer of a field. */
static long long field_raw(const slam_config_t *cfg, const field_t *f)
{
    const void *src = (const char *)cfg + f->offset;
    switch (f->type) {
    case T_U8:
        return *(const uint8_t *)src;
    case T_U16:
        return *(const uint16_t *)src;
    case T_U32:
        return *(const uint32_t *)src;
    default:
        return *(const int32_t *)src;
    }
}

void cfgtext_write_raw(FILE *f, const slam_config_t *cfg, const char *prefix)
{
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        fprintf(f, "%s%s %lld\n", prefix, fields[i].name, field_raw(cfg, &fields[i]));
    }
}

void cfgtext_write(FILE *f, const slam_config_t *cfg)
{
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        long long raw = field_raw(cfg, &fields[i]);
        if (fields[i].type == T_Q30) { /* enough digits to read back the same Q30 value */
            fprintf(f, "%s = %.12f\n", fields[i].name, (double)raw / (double)FIX_Q30_ONE);
        } else {
            fprintf(f, "%s = %lld\n", fields[i].name, raw);
        }
    }
}

int cfgtext_load(const char *path, slam_config_t *cfg, cfgtext_other_fn other, void *ctx,
                 char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    slam_config_t work = *cfg;
    char line[512];
    unsigned lineno = 0;
    int rc = 0;
    while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
        lineno++;
        if (strchr(line, '\n') == NULL && !feof(f)) {
            snprintf(err, errlen, "%s:%u: line too long", path, lineno);
            rc = -1;
            break;
        }
        char *hash = strchr(line, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        char *s = cfgtext_trim(line);
        if (*s == '\0') {
            continue;
        }
        char *eq = strchr(s, '=');
        if (eq == NULL) {
            snprintf(err, errlen, "%s:%u: expected 'key = value', got '%s'", path, lineno, s);
            rc = -1;
            break;
        }
        *eq = '\0';
        char *key = cfgtext_trim(s);
        char *value = cfgtext_trim(eq + 1);
        char msg[256];
        int r = cfgtext_set(&work, key, value, msg, sizeof msg);
        if (r == -1 && other != NULL) {
            r = other(ctx, key, value, msg, sizeof msg);
        }
        if (r != 0) {
            snprintf(err, errlen, "%s:%u: %s", path, lineno, msg);
            rc = -1;
        }
    }
    if (rc == 0 && ferror(f)) {
        snprintf(err, errlen, "%s: read error", path);
        rc = -1;
    }
    fclose(f);
    if (rc != 0) {
        return rc;
    }
    const char *bad = NULL;
    if (slam_config_check(&work, &bad) != SLAM_OK) {
        snprintf(err, errlen, "%s: %s is out of its valid range", path, bad);
        return -1;
    }
    *cfg = work;
    return 0;
}
