/* SPDX-License-Identifier: MIT */
/* Bounded text lines with decimal and hex numbers, for the banner, status and fault reports. */
#include "text.h"

static void put(text_line_t *l, char c)
{
    if (l->len + 1u < sizeof l->buf) {
        l->buf[l->len++] = c;
        l->buf[l->len] = '\0';
    }
}

void text_clear(text_line_t *l)
{
    l->len = 0u;
    l->buf[0] = '\0';
}

void text_str(text_line_t *l, const char *s)
{
    while (*s != '\0') {
        put(l, *s++);
    }
}

void text_u32(text_line_t *l, uint32_t v)
{
    char digits[10];
    unsigned n = 0;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0u) {
        put(l, digits[--n]);
    }
}

void text_i32(text_line_t *l, int32_t v)
{
    if (v < 0) {
        put(l, '-');
        text_u32(l, 0u - (uint32_t)v);
    } else {
        text_u32(l, (uint32_t)v);
    }
}

void text_hex(text_line_t *l, uint32_t v, unsigned digits)
{
    while (digits > 0u) {
        digits--;
        put(l, "0123456789abcdef"[(v >> (4u * digits)) & 0xFu]);
    }
}
