/* SPDX-License-Identifier: MIT */
/* slam_config_t as `key = value` text: the fields' names and words, parsing and writing. */
#include "hal_common/config_text.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/number.h"
#include "slam/config_fields.h"
#include "slam/error.h"

typedef enum { T_U8, T_U16, T_U32, T_I32, T_Q30 } field_type_t;

typedef struct {
    const char *name;
    size_t offset;
    field_type_t type;
    const char *words;    /* what slam_config_check() accepts, for messages (NULL: the modes) */
    const char *partners; /* the fields its rule compares it with, space-separated, or NULL */
} field_t;

/* The other fields each rule of config_fields.h compares a field with: when the rule
 * fails, the one set last may be the one to blame. */
#define PARTNERS_NONE NULL
#define PARTNERS_CELL NULL
#define PARTNERS_ABOVE_MIN "range_min_um"
#define PARTNERS_STOPS "sweep_first_mdeg sweep_last_mdeg"
#define PARTNERS_PULSES "servo_pulse_0deg_us"
#define PARTNERS_THRESHOLD "om_max om_mode"
#define PARTNERS_TOP_SPEED "top_speed_mm_s"
#define PARTNERS_ABOVE_CLEARANCE "clearance_um"
#define PARTNERS_CORRIDOR "cell_um"
#define PARTNERS_GRID NULL
#define PARTNERS_IN_GRID_A "grid_a"
#define PARTNERS_IN_GRID_B "grid_b"

/* The rows of config_fields.h. Their words are the only place the firmware's ranges are
 * said in words: the firmware names only the field. A leading "lo..hi" is the field's
 * whole range (tests/test_config_text.c holds these to slam_config_check(), so they cannot
 * drift from it unnoticed). */
static const field_t fields[] = {
#define F(name, type, dflt, lo, hi, rule, id, live, words)                                         \
    {#name, offsetof(slam_config_t, name), T_##type, words, PARTNERS_##rule},
    SLAM_CONFIG_FIELDS(F)
#undef F
};
#define NFIELDS (sizeof fields / sizeof fields[0])
_Static_assert(NFIELDS <= CFGTEXT_MAX_KEYS, "cfgtext_where_t has a line per field");

/* explore_mode's words: its range and the names of explore_modes.h, in their order. */
static const char *mode_words(void)
{
#define MODE_NAME(id, value, name, ...) ", " #name
    static const char names[] = SLAM_EXPLORE_MODES(MODE_NAME);
#undef MODE_NAME
    static _Thread_local char text[sizeof names + 16u];
    snprintf(text, sizeof text, "0..%d (%s)", EXPLORE_MODES - 1, names + 2);
    return text;
}

static int field_index(const char *key)
{
    for (size_t i = 0; i < NFIELDS; i++) {
        if (strcmp(fields[i].name, key) == 0) {
            return (int)i;
        }
    }
    return -1;
}

const char *cfgtext_rule(const char *key)
{
    int i = field_index(key);
    if (i < 0) {
        return NULL;
    }
    return fields[i].words != NULL ? fields[i].words : mode_words();
}

const char *cfgtext_partners(const char *key)
{
    int i = field_index(key);
    return i >= 0 ? fields[i].partners : NULL;
}

unsigned cfgtext_where_line(const cfgtext_where_t *w, const char *key)
{
    int i = field_index(key);
    return w != NULL && i >= 0 ? w->line[i] : 0u;
}

static int bad_value(const char *key, const char *value, const char *why, char *err, size_t n)
{
    snprintf(err, n, "%s = '%.40s': %s", key, value, why);
    return -2;
}

static const long long type_lo[] = {0, 0, 0, INT32_MIN, INT32_MIN};
static const long long type_hi[] = {UINT8_MAX, UINT16_MAX, UINT32_MAX, INT32_MAX, INT32_MAX};

static int out_of_range(const field_t *f, const char *value, char *err, size_t n)
{
    /* The field's own range: its type's would tell a negative wheel base 0..4294967295. */
    const char *rule = cfgtext_rule(f->name);
    char why[160];
    if (rule != NULL) {
        snprintf(why, sizeof why, "out of its valid range: %s", rule);
    } else {
        snprintf(why, sizeof why, "out of range %lld..%lld", type_lo[f->type], type_hi[f->type]);
    }
    return bad_value(f->name, value, why, err, n);
}

/* Stores a whole number into a field of any integer type (a Q30 field takes its raw
 * integer), after checking that it fits the type. */
static int store_int(slam_config_t *cfg, const field_t *f, long long v, const char *value,
                     char *err, size_t n)
{
    if (v < type_lo[f->type] || v > type_hi[f->type]) {
        return out_of_range(f, value, err, n);
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
    int i = field_index(key);
    if (i < 0) {
        snprintf(err, n,
                 "unknown key '%.64s' (the keys are the fields of "
                 "firmware/include/slam/config_fields.h; a run's config.txt lists them all)",
                 key);
        return NULL;
    }
    return &fields[i];
}

static int set_text(slam_config_t *cfg, const char *key, const char *value, char *err, size_t n)
{
    const field_t *f = known_field(key, err, n);
    if (f == NULL) {
        return -1;
    }
    if (f->type == T_Q30) {
        double v;
        num_status_t r = num_real(value, -2.0, 2.0, &v);
        if (r == NUM_BAD) {
            return bad_value(key, value, "expected a decimal number such as 0.9901", err, n);
        }
        if (r == NUM_RANGE || v == -2.0 || v == 2.0) {
            return bad_value(key, value, "must lie between -2 and 2", err, n);
        }
        return store_int(cfg, f, lround(v * (double)FIX_Q30_ONE), value, err, n);
    }
    long long v;
    num_status_t r = num_int(value, type_lo[f->type], type_hi[f->type], &v);
    if (r == NUM_BAD) {
        return bad_value(key, value, "expected a whole number (decimal digits)", err, n);
    }
    if (r == NUM_RANGE) {
        return out_of_range(f, value, err, n);
    }
    return store_int(cfg, f, v, value, err, n);
}

int cfgtext_set(slam_config_t *cfg, const char *key, const char *value, char *err, size_t n)
{
    int rc = set_text(cfg, key, value, err, n);
    if (rc != 0) {
        cfgtext_escape(err, n);
    }
    return rc;
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

/* A field's value as the text a file would hold. */
static void field_text(const slam_config_t *cfg, const field_t *f, char *out, size_t n)
{
    long long raw = field_raw(cfg, f);
    if (f->type == T_Q30) { /* enough digits to read back the same Q30 value */
        snprintf(out, n, "%.12f", (double)raw / (double)FIX_Q30_ONE);
    } else {
        snprintf(out, n, "%lld", raw);
    }
}

void cfgtext_write_raw(FILE *f, const slam_config_t *cfg, const char *prefix)
{
    for (size_t i = 0; i < NFIELDS; i++) {
        fprintf(f, "%s%s %lld\n", prefix, fields[i].name, field_raw(cfg, &fields[i]));
    }
}

void cfgtext_write(FILE *f, const slam_config_t *cfg)
{
    for (size_t i = 0; i < NFIELDS; i++) {
        char value[40];
        field_text(cfg, &fields[i], value, sizeof value);
        fprintf(f, "%s = %s\n", fields[i].name, value);
    }
}

int cfgtext_check(const slam_config_t *cfg, const char **key, char *err, size_t errlen)
{
    const char *bad = NULL;
    if (slam_config_check(cfg, &bad) == SLAM_OK) {
        return 0;
    }
    int i = field_index(bad);
    char value[40] = "?";
    if (i >= 0) {
        field_text(cfg, &fields[i], value, sizeof value);
    }
    const char *rule = cfgtext_rule(bad);
    /* The values of the fields its rule compares it with: "(range_min_um = 1000000)". */
    char others[160] = "";
    const char *partners = i >= 0 ? fields[i].partners : NULL;
    for (const char *p = partners; p != NULL && *p != '\0';) {
        size_t n = strcspn(p, " ");
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)n, p);
        int k = field_index(name);
        char v[40] = "?";
        if (k >= 0) {
            field_text(cfg, &fields[k], v, sizeof v);
        }
        size_t len = strlen(others);
        snprintf(others + len, sizeof others - len, "%s%s = %s", len == 0u ? " (" : ", ", name, v);
        p += n + (p[n] == ' ' ? 1u : 0u);
    }
    if (others[0] != '\0') {
        size_t len = strlen(others);
        snprintf(others + len, sizeof others - len, ")");
    }
    snprintf(err, errlen, "%s = %s is out of its valid range%s%s%s", bad, value,
             rule != NULL ? ": " : "", rule != NULL ? rule : "", others);
    if (key != NULL) {
        *key = bad;
    }
    return -1;
}

/* The sections of cfgtext_sections[]: a program's own keys under [name]. */
const char *const cfgtext_sections[] = {"linux", NULL};

/* A "[name]" line: 1 and the section's index in *index (-1: not a known one), or 0 when
 * the line is not a section header. */
static int section_header(char *s, int *index)
{
    size_t n = strlen(s);
    if (s[0] != '[' || s[n - 1u] != ']') {
        return 0;
    }
    s[n - 1u] = '\0';
    const char *id = cfgtext_trim(s + 1);
    *index = -1;
    for (int i = 0; cfgtext_sections[i] != NULL; i++) {
        if (strcmp(cfgtext_sections[i], id) == 0) {
            *index = i;
        }
    }
    return 1;
}

/* A key in the wrong part of the file: the message says where it belongs. Core keys go
 * before the first section (every program reads them there); a program's own keys in its
 * section (the others skip it), so that both agree on whose each key is. */
static int misplaced(const char *key, const char *section, int in_own, char *err, size_t n)
{
    if (in_own) {
        snprintf(err, n,
                 "%.64s is a key of the robot's core (slam_config_t): it belongs before the "
                 "first [section], where every program reads it, not in [%s]",
                 key, section);
    } else if (section != NULL) {
        snprintf(err, n,
                 "unknown key '%.64s' (the robot's core keys are the fields of "
                 "firmware/include/slam/config_fields.h; this program's own keys belong "
                 "under [%s])",
                 key, section);
    } else {
        snprintf(err, n,
                 "unknown key '%.64s' (the robot's core keys are the fields of "
                 "firmware/include/slam/config_fields.h; a program's own keys, such as the "
                 "Linux robot's wiring, belong under its section, [%s])",
                 key, cfgtext_sections[0]);
    }
    return -1;
}

static int parse_in(const char *name, const char *text, size_t len, const char *section,
                    slam_config_t *cfg, cfgtext_other_fn other, void *ctx, cfgtext_where_t *where,
                    char *err, size_t errlen)
{
    /* -1 before the first section header, else the index of the section in force. */
    int in = -1;
    int own = -2; /* the index of the caller's section (-2: it has none) */
    for (int i = 0; section != NULL && cfgtext_sections[i] != NULL; i++) {
        own = strcmp(cfgtext_sections[i], section) == 0 ? i : own;
    }
    slam_config_t work = *cfg;
    cfgtext_where_t seen;
    memset(&seen, 0, sizeof seen);
    unsigned lineno = 0;
    size_t pos = 0;
    while (pos < len) {
        lineno++;
        const char *nl = memchr(text + pos, '\n', len - pos);
        size_t n = nl != NULL ? (size_t)(nl - (text + pos)) : len - pos;
        if (memchr(text + pos, '\0', n) != NULL) {
            snprintf(err, errlen, "%s:%u: a NUL byte: not a text file", name, lineno);
            return -1;
        }
        if (n >= CFGTEXT_LINE_MAX) {
            snprintf(err, errlen, "%s:%u: line longer than %u characters", name, lineno,
                     (unsigned)CFGTEXT_LINE_MAX - 1u);
            return -1;
        }
        char line[CFGTEXT_LINE_MAX];
        memcpy(line, text + pos, n);
        line[n] = '\0';
        pos += n + (nl != NULL ? 1u : 0u);
        char *hash = strchr(line, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        char *s = cfgtext_trim(line);
        if (*s == '\0') {
            continue;
        }
        if (section_header(s, &in)) {
            if (in < 0) {
                snprintf(err, errlen, "%s:%u: unknown section [%.40s] (the sections: [%s])", name,
                         lineno, s + 1, cfgtext_sections[0]);
                return -1;
            }
            continue;
        }
        char *eq = strchr(s, '=');
        if (eq == NULL) {
            snprintf(err, errlen, "%s:%u: expected 'key = value', got '%.60s'", name, lineno, s);
            return -1;
        }
        *eq = '\0';
        char *key = cfgtext_trim(s);
        char *value = cfgtext_trim(eq + 1);
        char msg[256];
        int i = field_index(key);
        if (i >= 0 && seen.line[i] != 0u) {
            snprintf(err, errlen, "%s:%u: %s is given twice (first on line %u)", name, lineno, key,
                     seen.line[i]);
            return -1;
        }
        int r;
        if (in >= 0 && i >= 0) {
            r = misplaced(key, cfgtext_sections[in], 1, msg, sizeof msg);
        } else if (in >= 0 && in != own) {
            continue; /* another program's key: its own reader checks it */
        } else if (in >= 0) {
            r = other != NULL ? other(ctx, key, value, lineno, msg, sizeof msg) : -1;
        } else {
            r = cfgtext_set(&work, key, value, msg, sizeof msg);
            if (r == -1 && other != NULL && section == NULL) {
                r = other(ctx, key, value, lineno, msg, sizeof msg);
            } else if (r == -1) {
                r = misplaced(key, section, 0, msg, sizeof msg);
            }
        }
        if (r != 0) {
            snprintf(err, errlen, "%s:%u: %s", name, lineno, msg);
            return -1;
        }
        if (i >= 0) {
            seen.line[i] = lineno;
        }
    }
    const char *bad = NULL;
    char msg[256];
    if (cfgtext_check(&work, &bad, msg, sizeof msg) != 0) {
        unsigned at = cfgtext_where_line(&seen, bad);
        for (const char *p = cfgtext_partners(bad); at == 0u && p != NULL && *p != '\0';) {
            size_t n = strcspn(p, " "); /* the rule's other field, set by this file */
            char partner[64];
            snprintf(partner, sizeof partner, "%.*s", (int)n, p);
            at = cfgtext_where_line(&seen, partner);
            p += n + (p[n] == ' ' ? 1u : 0u);
        }
        if (at != 0u) {
            snprintf(err, errlen, "%s:%u: %s", name, at, msg);
        } else {
            snprintf(err, errlen, "%s: %s (not set in the file)", name, msg);
        }
        return -1;
    }
    *cfg = work;
    if (where != NULL) {
        *where = seen;
    }
    return 0;
}

int cfgtext_parse_in(const char *name, const char *text, size_t len, const char *section,
                     slam_config_t *cfg, cfgtext_other_fn other, void *ctx, cfgtext_where_t *where,
                     char *err, size_t errlen)
{
    int rc = parse_in(name, text, len, section, cfg, other, ctx, where, err, errlen);
    if (rc != 0) {
        cfgtext_escape(err, errlen); /* a line of the file, a value or a key may be quoted */
    }
    return rc;
}

int cfgtext_parse(const char *name, const char *text, size_t len, slam_config_t *cfg,
                  cfgtext_other_fn other, void *ctx, cfgtext_where_t *where, char *err,
                  size_t errlen)
{
    return cfgtext_parse_in(name, text, len, NULL, cfg, other, ctx, where, err, errlen);
}

int cfgtext_load(const char *path, slam_config_t *cfg, cfgtext_other_fn other, void *ctx,
                 cfgtext_where_t *where, char *err, size_t errlen)
{
    return cfgtext_load_in(path, NULL, cfg, other, ctx, where, err, errlen);
}

int cfgtext_load_in(const char *path, const char *section, slam_config_t *cfg,
                    cfgtext_other_fn other, void *ctx, cfgtext_where_t *where, char *err,
                    size_t errlen)
{
    size_t len = 0u;
    char *text = cfgtext_read_file(path, CFGTEXT_FILE_MAX, &len, err, errlen);
    if (text == NULL) {
        return -1;
    }
    int rc = cfgtext_parse_in(path, text, len, section, cfg, other, ctx, where, err, errlen);
    free(text);
    return rc;
}
