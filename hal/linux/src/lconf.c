/* SPDX-License-Identifier: MIT */
/* robot.conf's backend keys: one table of keys, value parsing, and the checks of the whole. */
#include "lhal/lconf.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "hal_common/number.h"
#include "lhal/serial.h"

typedef enum {
    K_LINE,
    K_OPT_LINE,
    K_PWM,
    K_OPT_PWM,
    K_U32,
    K_BAUD,
    K_BOOL,
    K_STR,
    K_BIAS
} key_type_t;

typedef struct {
    const char *name;
    key_type_t type;
    size_t offset;
    size_t size;     /* K_STR: the buffer */
    uint32_t lo, hi; /* K_U32 */
    bool zero_ok;    /* K_U32: 0 is accepted besides lo..hi (it means "off") */
    bool required;
} lkey_t;

#define KEY(n, t, field, req)                                                                      \
    {                                                                                              \
        n, t, offsetof(lconf_t, field), sizeof(((lconf_t *)0)->field), 0u, 0u, false, req          \
    }
#define KEY_U32(n, field, lo, hi, zero_ok)                                                         \
    {                                                                                              \
        n, K_U32, offsetof(lconf_t, field), sizeof(uint32_t), lo, hi, zero_ok, false               \
    }
static const lkey_t keys[] = {
    KEY("gpio_chip", K_STR, gpio_chip, false),
    KEY("encoder_left_a", K_LINE, enc_a[0], true),
    KEY("encoder_left_b", K_LINE, enc_b[0], true),
    KEY("encoder_right_a", K_LINE, enc_a[1], true),
    KEY("encoder_right_b", K_LINE, enc_b[1], true),
    KEY("encoder_left_invert", K_BOOL, enc_invert[0], false),
    KEY("encoder_right_invert", K_BOOL, enc_invert[1], false),
    KEY("encoder_bias", K_BIAS, enc_bias, false),
    KEY("sonar_trigger", K_LINE, sonar_trigger, true),
    KEY("sonar_echo", K_LINE, sonar_echo, true),
    KEY("sonar1_trigger", K_OPT_LINE, sonar1_trigger, false),
    KEY("sonar1_echo", K_OPT_LINE, sonar1_echo, false),
    KEY_U32("sonar_timeout_us", sonar_timeout_us, 1000u, 100000u, false),
    KEY("pwm_root", K_STR, pwm_root, false),
    KEY("servo_pwm_chip", K_PWM, servo_pwm.chip, true),
    KEY("servo_pwm_channel", K_PWM, servo_pwm.channel, true),
    KEY("servo1_pwm_chip", K_OPT_PWM, servo1_pwm.chip, false),
    KEY("servo1_pwm_channel", K_OPT_PWM, servo1_pwm.channel, false),
    KEY("motor_left_pwm_chip", K_PWM, motor_pwm[0].chip, true),
    KEY("motor_left_pwm_channel", K_PWM, motor_pwm[0].channel, true),
    KEY("motor_right_pwm_chip", K_PWM, motor_pwm[1].chip, true),
    KEY("motor_right_pwm_channel", K_PWM, motor_pwm[1].channel, true),
    KEY_U32("motor_pwm_period_ns", motor_period_ns, 10000u, 50000000u, false),
    KEY("motor_left_in1", K_LINE, motor_in1[0], true),
    KEY("motor_left_in2", K_OPT_LINE, motor_in2[0], true),
    KEY("motor_right_in1", K_LINE, motor_in1[1], true),
    KEY("motor_right_in2", K_OPT_LINE, motor_in2[1], true),
    KEY("motor_left_invert", K_BOOL, motor_invert[0], false),
    KEY("motor_right_invert", K_BOOL, motor_invert[1], false),
    KEY("motor_standby", K_OPT_LINE, motor_standby, false),
    KEY("bump0", K_OPT_LINE, bump[0], false),
    KEY("bump1", K_OPT_LINE, bump[1], false),
    KEY("bump2", K_OPT_LINE, bump[2], false),
    KEY("bump3", K_OPT_LINE, bump[3], false),
    KEY("bump_bias", K_BIAS, bump_bias, false),
    KEY("bump_active_low", K_BOOL, bump_active_low, false),
    KEY("telemetry", K_STR, telemetry, false),
    KEY("telemetry_baud", K_BAUD, telemetry_baud, false),
    KEY("storage_dir", K_STR, storage_dir, false),
    KEY_U32("storage_bytes", storage_bytes, 4096u, 16777216u, false),
    KEY_U32("tick_priority", tick_priority, 0u, 98u, false),
    KEY_U32("watchdog_idle_ms", watchdog_idle_ms, 100u, 60000u, true),
};
#undef KEY
#undef KEY_U32
#define NKEYS (sizeof keys / sizeof keys[0])
_Static_assert(NKEYS <= LCONF_KEYS_MAX, "lconf_t.seen has one bit per key");

/* The line of the file that set a key (0: not set, or not from a file). */
static unsigned key_line(const lconf_t *c, const char *name)
{
    for (size_t i = 0u; i < NKEYS; i++) {
        if (strcmp(keys[i].name, name) == 0) {
            return c->line[i];
        }
    }
    return 0u;
}

/* "KEY" or "KEY (line N)". */
static const char *where(const lconf_t *c, const char *name, char *buf, size_t n)
{
    unsigned line = key_line(c, name);
    if (line != 0u) {
        snprintf(buf, n, "%s (line %u)", name, line);
    } else {
        snprintf(buf, n, "%s", name);
    }
    return buf;
}

static const char *const bias_names[] = {"as-is", "disable", "pull-up", "pull-down"};

void lconf_default(lconf_t *c)
{
    memset(c, 0, sizeof *c);
    snprintf(c->gpio_chip, sizeof c->gpio_chip, "gpiochip0");
    c->enc_a[0] = c->enc_a[1] = c->enc_b[0] = c->enc_b[1] = LCONF_NO_LINE;
    c->sonar_trigger = c->sonar_echo = LCONF_NO_LINE;
    c->sonar1_trigger = c->sonar1_echo = LCONF_NO_LINE;
    c->sonar_timeout_us = 30000u;
    snprintf(c->pwm_root, sizeof c->pwm_root, "/sys/class/pwm");
    c->servo_pwm = (lconf_pwm_t){-1, -1};
    c->servo1_pwm = (lconf_pwm_t){-1, -1};
    c->motor_pwm[0] = c->motor_pwm[1] = (lconf_pwm_t){-1, -1};
    c->motor_period_ns = 50000u;
    c->motor_in1[0] = c->motor_in1[1] = LCONF_NO_LINE;
    c->motor_in2[0] = c->motor_in2[1] = LCONF_NO_LINE;
    c->motor_standby = LCONF_NO_LINE;
    for (unsigned i = 0u; i < LCONF_BUMPS; i++) {
        c->bump[i] = LCONF_NO_LINE;
    }
    c->bump_bias = LCONF_BIAS_PULL_UP;
    c->bump_active_low = true;
    snprintf(c->telemetry, sizeof c->telemetry, "none");
    c->telemetry_baud = 115200u;
    snprintf(c->storage_dir, sizeof c->storage_dir, ".");
    c->storage_bytes = 65536u;
    c->tick_priority = 50u;
    c->watchdog_idle_ms = 2000u;
}

static int bad(const char *key, const char *value, const char *why, char *err, size_t n)
{
    snprintf(err, n, "%s = '%s': %s", key, value, why);
    return -2;
}

/* A whole number in [lo, hi], by the rule of hal_common/number.h. */
static bool parse_int(const char *s, long long lo, long long hi, long long *out)
{
    return num_int(s, lo, hi, out) == NUM_OK;
}

static int set_value(lconf_t *c, const lkey_t *k, const char *v, char *err, size_t n)
{
    void *dst = (char *)c + k->offset;
    long long x = 0;
    char why[96];
    switch (k->type) {
    case K_LINE:
    case K_OPT_LINE: {
        long long lo = k->type == K_OPT_LINE ? LCONF_NO_LINE : 0;
        if (!parse_int(v, lo, LCONF_LINE_MAX, &x)) {
            snprintf(why, sizeof why, "expected a line offset 0..%d%s", LCONF_LINE_MAX,
                     k->type == K_OPT_LINE ? ", or -1 when not wired" : "");
            return bad(k->name, v, why, err, n);
        }
        int32_t line = (int32_t)x;
        memcpy(dst, &line, sizeof line);
        return 0;
    }
    case K_PWM:
    case K_OPT_PWM: {
        long long lo = k->type == K_OPT_PWM ? -1 : 0;
        if (!parse_int(v, lo, LCONF_PWM_MAX, &x)) {
            snprintf(why, sizeof why, "expected a number 0..%d%s", LCONF_PWM_MAX,
                     k->type == K_OPT_PWM ? ", or -1 when not wired" : "");
            return bad(k->name, v, why, err, n);
        }
        int32_t num = (int32_t)x;
        memcpy(dst, &num, sizeof num);
        return 0;
    }
    case K_U32: {
        if (!(k->zero_ok && strcmp(v, "0") == 0) && !parse_int(v, k->lo, k->hi, &x)) {
            snprintf(why, sizeof why, "expected a whole number %s%u..%u",
                     k->zero_ok ? "0 (off) or " : "", (unsigned)k->lo, (unsigned)k->hi);
            return bad(k->name, v, why, err, n);
        }
        uint32_t u = strcmp(v, "0") == 0 ? 0u : (uint32_t)x;
        memcpy(dst, &u, sizeof u);
        return 0;
    }
    case K_BAUD: {
        if (!parse_int(v, 1, UINT32_MAX, &x) || !serial_baud_supported((uint32_t)x)) {
            return bad(k->name, v,
                       "expected 9600, 19200, 38400, 57600, 115200, 230400, 460800 or 921600", err,
                       n);
        }
        uint32_t u = (uint32_t)x;
        memcpy(dst, &u, sizeof u);
        return 0;
    }
    case K_BOOL: {
        bool b;
        if (strcmp(v, "1") == 0 || strcmp(v, "yes") == 0 || strcmp(v, "true") == 0) {
            b = true;
        } else if (strcmp(v, "0") == 0 || strcmp(v, "no") == 0 || strcmp(v, "false") == 0) {
            b = false;
        } else {
            return bad(k->name, v, "expected 0 or 1 (also no/yes, false/true)", err, n);
        }
        memcpy(dst, &b, sizeof b);
        return 0;
    }
    case K_BIAS:
        for (uint8_t i = 0u; i < sizeof bias_names / sizeof bias_names[0]; i++) {
            if (strcmp(v, bias_names[i]) == 0) {
                memcpy(dst, &i, sizeof i);
                return 0;
            }
        }
        return bad(k->name, v, "expected as-is, disable, pull-up or pull-down", err, n);
    default: /* K_STR */
        if (v[0] == '\0') {
            return bad(k->name, v, "must not be empty", err, n);
        }
        for (const char *p = v; *p != '\0'; p++) {
            if ((unsigned char)*p < 0x20u || *p == 0x7F) { /* a name or path, never a control */
                return bad(k->name, v, "holds a control character", err, n);
            }
        }
        if (strlen(v) >= k->size) {
            snprintf(why, sizeof why, "longer than %u characters", (unsigned)(k->size - 1u));
            return bad(k->name, v, why, err, n);
        }
        memcpy(dst, v, strlen(v) + 1u);
        return 0;
    }
}

int lconf_set(void *ctx, const char *key, const char *value, unsigned line, char *err,
              size_t errlen)
{
    lconf_t *c = ctx;
    for (size_t i = 0u; i < NKEYS; i++) {
        if (strcmp(keys[i].name, key) != 0) {
            continue;
        }
        if (c->seen & (1ull << i)) {
            if (c->line[i] != 0u) {
                snprintf(err, errlen, "%s is given twice (first on line %u)", key, c->line[i]);
            } else {
                snprintf(err, errlen, "%s is given twice", key);
            }
            return -2;
        }
        int rc = set_value(c, &keys[i], value, err, errlen);
        if (rc == 0) {
            c->seen |= 1ull << i;
            c->line[i] = line;
        }
        return rc;
    }
    snprintf(err, errlen, "unknown key '%s'", key);
    return -1;
}

void lconf_lines(const lconf_t *c, lconf_line_t out[LCONF_LINES])
{
    const int8_t enc = (int8_t)c->enc_bias;
    const int8_t bump = (int8_t)c->bump_bias;
    const lconf_line_t lines[LCONF_LINES] = {
        [LCONF_ENC_LEFT_A] = {"encoder_left_a", c->enc_a[0], enc},
        [LCONF_ENC_LEFT_B] = {"encoder_left_b", c->enc_b[0], enc},
        [LCONF_ENC_RIGHT_A] = {"encoder_right_a", c->enc_a[1], enc},
        [LCONF_ENC_RIGHT_B] = {"encoder_right_b", c->enc_b[1], enc},
        [LCONF_SONAR_TRIGGER] = {"sonar_trigger", c->sonar_trigger, LCONF_OUTPUT},
        [LCONF_SONAR_ECHO] = {"sonar_echo", c->sonar_echo, LCONF_BIAS_AS_IS},
        [LCONF_MOTOR_LEFT_IN1] = {"motor_left_in1", c->motor_in1[0], LCONF_OUTPUT},
        [LCONF_MOTOR_LEFT_IN2] = {"motor_left_in2", c->motor_in2[0], LCONF_OUTPUT},
        [LCONF_MOTOR_RIGHT_IN1] = {"motor_right_in1", c->motor_in1[1], LCONF_OUTPUT},
        [LCONF_MOTOR_RIGHT_IN2] = {"motor_right_in2", c->motor_in2[1], LCONF_OUTPUT},
        [LCONF_MOTOR_STANDBY] = {"motor_standby", c->motor_standby, LCONF_OUTPUT},
        [LCONF_SONAR1_TRIGGER] = {"sonar1_trigger", c->sonar1_trigger, LCONF_OUTPUT},
        [LCONF_SONAR1_ECHO] = {"sonar1_echo", c->sonar1_echo, LCONF_BIAS_AS_IS},
        [LCONF_BUMP0] = {"bump0", c->bump[0], bump},
        [LCONF_BUMP0 + 1] = {"bump1", c->bump[1], bump},
        [LCONF_BUMP0 + 2] = {"bump2", c->bump[2], bump},
        [LCONF_BUMP0 + 3] = {"bump3", c->bump[3], bump},
    };
    _Static_assert(LCONF_BUMPS == 4u, "one line a bump switch above");
    memcpy(out, lines, sizeof lines);
}

static unsigned later(unsigned a, unsigned b)
{
    return a > b ? a : b;
}

static bool pwm_wired(lconf_pwm_t p)
{
    return p.chip >= 0 && p.channel >= 0;
}

unsigned lconf_sonars(const lconf_t *c)
{
    return c->sonar1_trigger != LCONF_NO_LINE ? 2u : 1u;
}

unsigned lconf_servos(const lconf_t *c)
{
    return pwm_wired(c->servo1_pwm) ? 2u : 1u;
}

unsigned lconf_bumps(const lconf_t *c)
{
    unsigned n = 0u;
    while (n < LCONF_BUMPS && c->bump[n] != LCONF_NO_LINE) {
        n++;
    }
    return n;
}

/* Keys that make an instance only together: both given, or neither. */
static int check_pairs(const lconf_t *c, unsigned *blame, char *err, size_t errlen)
{
    const struct {
        const char *a, *b;
        bool has_a, has_b;
    } pairs[] = {
        {"sonar1_trigger", "sonar1_echo", c->sonar1_trigger != LCONF_NO_LINE,
         c->sonar1_echo != LCONF_NO_LINE},
        {"servo1_pwm_chip", "servo1_pwm_channel", c->servo1_pwm.chip >= 0,
         c->servo1_pwm.channel >= 0},
    };
    for (size_t i = 0u; i < sizeof pairs / sizeof pairs[0]; i++) {
        if (pairs[i].has_a != pairs[i].has_b) {
            const char *given = pairs[i].has_a ? pairs[i].a : pairs[i].b;
            const char *missing = pairs[i].has_a ? pairs[i].b : pairs[i].a;
            snprintf(err, errlen, "%s is given without %s (an instance needs both)", given,
                     missing);
            *blame = key_line(c, given);
            return -1;
        }
    }
    for (unsigned i = 1u; i < LCONF_BUMPS; i++) {
        if (c->bump[i] != LCONF_NO_LINE && c->bump[i - 1u] == LCONF_NO_LINE) {
            char name[8];
            snprintf(name, sizeof name, "bump%u", i);
            snprintf(err, errlen, "%s is given without bump%u (switches are numbered from 0)", name,
                     i - 1u);
            *blame = key_line(c, name);
            return -1;
        }
    }
    return 0;
}

/* lconf_check(), and the line to blame: the later of two keys that clash (0: none). */
static int check(const lconf_t *c, unsigned *blame, char *err, size_t errlen)
{
    *blame = 0u;
    for (size_t i = 0u; i < NKEYS; i++) {
        if (keys[i].required && !(c->seen & (1ull << i))) {
            snprintf(err, errlen, "missing key '%s' (required; see robot-rpi.conf)", keys[i].name);
            return -1;
        }
    }
    if (check_pairs(c, blame, err, errlen) != 0) {
        return -1;
    }
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(c, lines);
    char a[64];
    char b[64];
    for (size_t i = 0u; i < LCONF_LINES; i++) {
        for (size_t j = i + 1u; j < LCONF_LINES; j++) {
            if (lines[i].offset != LCONF_NO_LINE && lines[i].offset == lines[j].offset) {
                snprintf(err, errlen, "%s and %s both use line %d",
                         where(c, lines[i].name, a, sizeof a), where(c, lines[j].name, b, sizeof b),
                         (int)lines[i].offset);
                *blame = later(key_line(c, lines[i].name), key_line(c, lines[j].name));
                return -1;
            }
        }
    }
    const struct {
        const char *name;
        const char *chip_key;
        const char *channel_key;
        lconf_pwm_t pwm;
    } pwms[] = {{"servo", "servo_pwm_chip", "servo_pwm_channel", c->servo_pwm},
                {"motor_left", "motor_left_pwm_chip", "motor_left_pwm_channel", c->motor_pwm[0]},
                {"motor_right", "motor_right_pwm_chip", "motor_right_pwm_channel", c->motor_pwm[1]},
                {"servo1", "servo1_pwm_chip", "servo1_pwm_channel", c->servo1_pwm}};
    enum { NPWM = sizeof pwms / sizeof pwms[0] };
    unsigned pwm_line[NPWM];
    for (size_t i = 0u; i < NPWM; i++) {
        pwm_line[i] = later(key_line(c, pwms[i].chip_key), key_line(c, pwms[i].channel_key));
    }
    for (size_t i = 0u; i < NPWM; i++) {
        for (size_t j = i + 1u; j < NPWM; j++) {
            if (pwm_wired(pwms[j].pwm) && pwms[i].pwm.chip == pwms[j].pwm.chip &&
                pwms[i].pwm.channel == pwms[j].pwm.channel) {
                snprintf(err, errlen,
                         "%s and %s both use PWM channel pwmchip%d/pwm%d (lines %u and %u)",
                         pwms[i].name, pwms[j].name, (int)pwms[i].pwm.chip,
                         (int)pwms[i].pwm.channel, pwm_line[i], pwm_line[j]);
                *blame = later(pwm_line[i], pwm_line[j]);
                return -1;
            }
        }
    }
    return 0;
}

int lconf_check(const lconf_t *c, char *err, size_t errlen)
{
    unsigned blame;
    return check(c, &blame, err, errlen);
}

int lconf_load(const char *path, slam_config_t *core, lconf_t *lc, char *err, size_t errlen)
{
    slam_config_t core_work = *core;
    lconf_t lc_work = *lc;
    /* The wiring and devices are read from [linux]; the core's keys come before it. */
    if (cfgtext_load_in(path, "linux", &core_work, lconf_set, &lc_work, NULL, err, errlen) != 0) {
        return -1;
    }
    char msg[200];
    unsigned blame;
    if (check(&lc_work, &blame, msg, sizeof msg) != 0) {
        if (blame != 0u) {
            snprintf(err, errlen, "%s:%u: %s", path, blame, msg);
        } else {
            snprintf(err, errlen, "%s: %s", path, msg);
        }
        return -1;
    }
    *core = core_work;
    *lc = lc_work;
    return 0;
}
