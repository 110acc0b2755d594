/* SPDX-License-Identifier: MIT */
/* Messages that quote input shown safely: control bytes escaped so a file cannot drive the
 * terminal that prints its error. */
#define _POSIX_C_SOURCE 200809L /* strnlen */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"

/* The length of a UTF-8 sequence at p that a terminal shows as a character (a code point
 * from U+00A0, not a surrogate, shortest form), or 0. C1 controls (U+0080..U+009F) are
 * excluded: some terminals act on them as on ESC sequences. */
static size_t utf8_printable(const unsigned char *p)
{
    uint32_t cp;
    size_t n;
    if (p[0] >= 0xC2u && p[0] <= 0xDFu) {
        n = 2u;
        cp = p[0] & 0x1Fu;
    } else if (p[0] >= 0xE0u && p[0] <= 0xEFu) {
        n = 3u;
        cp = p[0] & 0x0Fu;
    } else if (p[0] >= 0xF0u && p[0] <= 0xF4u) {
        n = 4u;
        cp = p[0] & 0x07u;
    } else {
        return 0u;
    }
    for (size_t i = 1u; i < n; i++) {
        if ((p[i] & 0xC0u) != 0x80u) {
            return 0u;
        }
        cp = cp << 6 | (p[i] & 0x3Fu);
    }
    static const uint32_t shortest[5] = {0u, 0u, 0x80u, 0x800u, 0x10000u};
    if (cp < shortest[n] || cp < 0xA0u || (cp >= 0xD800u && cp <= 0xDFFFu) || cp > 0x10FFFFu) {
        return 0u;
    }
    return n;
}

void cfgtext_escape(char *s, size_t cap)
{
    if (cap == 0u) {
        return;
    }
    size_t len = strnlen(s, cap - 1u);
    s[len] = '\0';
    size_t plain = 0u; /* the common case: nothing to escape, nothing to copy */
    while (plain < len && (unsigned char)s[plain] >= 0x20u && (unsigned char)s[plain] < 0x7Fu) {
        plain++;
    }
    if (plain == len) {
        return;
    }
    char *out = malloc(4u * len + 1u);
    if (out == NULL) { /* no memory for a copy: cut the message where it stopped being plain */
        s[plain] = '\0';
        return;
    }
    static const char hex[] = "0123456789abcdef";
    size_t o = 0u;
    const unsigned char *p = (const unsigned char *)s;
    for (size_t i = 0u; i < len;) {
        size_t n = 0u;
        if (p[i] >= 0x20u && p[i] < 0x7Fu) {
            n = 1u;
        } else if (p[i] >= 0x80u) {
            n = utf8_printable(p + i);
        }
        if (n > 0u) {
            memcpy(out + o, p + i, n);
            o += n;
            i += n;
        } else {
            out[o++] = '\\';
            out[o++] = 'x';
            out[o++] = hex[p[i] >> 4];
            out[o++] = hex[p[i] & 0x0Fu];
            i++;
        }
        if (o + 1u > cap) { /* keep what fits: whole characters and whole escapes */
            break;
        }
    }
    /* Cut back to the last whole piece that fits in cap - 1 bytes. */
    size_t keep = o;
    if (keep > cap - 1u) {
        keep = 0u;
        for (size_t i = 0u; i < o;) {
            size_t n = out[i] == '\\' ? 4u : 1u;
            if ((unsigned char)out[i] >= 0xC0u) {
                n = (unsigned char)out[i] >= 0xF0u ? 4u : (unsigned char)out[i] >= 0xE0u ? 3u : 2u;
            }
            if (i + n > cap - 1u) {
                break;
            }
            i += n;
            keep = i;
        }
    }
    memcpy(s, out, keep);
    s[keep] = '\0';
    free(out);
}
