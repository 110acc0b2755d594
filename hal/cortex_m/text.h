/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Building short text lines without printf (newlib-nano's would cost kilobytes of flash):
 * strings, decimal and hex numbers appended to a bounded line; too long a line is cut.
 */
#ifndef CM_TEXT_H
#define CM_TEXT_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    char buf[192]; /**< always NUL-terminated */
    size_t len;
} text_line_t;

void text_clear(text_line_t *l);
void text_str(text_line_t *l, const char *s);
void text_u32(text_line_t *l, uint32_t v);
void text_i32(text_line_t *l, int32_t v);
/** @p digits hex digits of v, most significant first, without a prefix. */
void text_hex(text_line_t *l, uint32_t v, unsigned digits);

struct cm_fault;

/** "FAULT exception N: why pc 0x.. lr 0x.. cfsr 0x.. hfsr 0x.. bfar 0x..", after @p l's
 *  text (in startup.c: MCU images only). */
void text_fault(text_line_t *l, const struct cm_fault *f);

#endif /* CM_TEXT_H */
