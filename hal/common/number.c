/* SPDX-License-Identifier: MIT */
/* Numbers in text by the one rule of hal_common/number.h: the syntax checked here, the
 * value then converted by the C library, which agrees with Python on every decimal. */
#include "hal_common/number.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

static int is_digit(char c)
{
    return c >= '0' && c <= '9'; /* isdigit() may take a locale's other digits */
}

/* The digits of a whole number after an optional sign; NULL when there are none. */
static const char *skip_digits(const char *p)
{
    if (!is_digit(*p)) {
        return NULL;
    }
    while (is_digit(*p)) {
        p++;
    }
    return p;
}

static const char *skip_sign(const char *p)
{
    return *p == '+' || *p == '-' ? p + 1 : p;
}

static int is_whole(const char *s)
{
    const char *p = skip_digits(skip_sign(s));
    return p != NULL && *p == '\0';
}

int num_is_real(const char *s)
{
    const char *p = skip_sign(s);
    const char *q = skip_digits(p);
    if (q != NULL) {
        p = q;
        if (*p == '.') {
            p++;
            while (is_digit(*p)) {
                p++;
            }
        }
    } else if (*p == '.' && (q = skip_digits(p + 1)) != NULL) {
        p = q;
    } else {
        return 0;
    }
    if (*p == 'e' || *p == 'E') {
        p = skip_digits(skip_sign(p + 1));
        if (p == NULL) {
            return 0;
        }
    }
    return *p == '\0';
}

num_status_t num_int(const char *s, long long lo, long long hi, long long *out)
{
    if (!is_whole(s)) {
        return NUM_BAD;
    }
    errno = 0;
    long long v = strtoll(s, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi) {
        return NUM_RANGE;
    }
    *out = v;
    return NUM_OK;
}

num_status_t num_uint(const char *s, unsigned long long lo, unsigned long long hi,
                      unsigned long long *out)
{
    if (!is_whole(s)) {
        return NUM_BAD;
    }
    if (*s == '-') { /* strtoull would wrap "-1" to 2^64 - 1; "-0" is 0 */
        for (const char *p = s + 1; *p != '\0'; p++) {
            if (*p != '0') {
                return NUM_RANGE;
            }
        }
    }
    errno = 0;
    unsigned long long v = strtoull(s, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi) {
        return NUM_RANGE;
    }
    *out = v;
    return NUM_OK;
}

num_status_t num_real(const char *s, double lo, double hi, double *out)
{
    if (!num_is_real(s)) {
        return NUM_BAD;
    }
    errno = 0;
    double v = strtod(s, NULL);
    /* ERANGE with a tiny result is an underflow: the number reads as (nearly) 0. */
    if ((errno == ERANGE && fabs(v) > 1.0) || !isfinite(v) || v < lo || v > hi) {
        return NUM_RANGE;
    }
    *out = v;
    return NUM_OK;
}
