/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The telemetry byte stream: a serial device, a pseudo-terminal, or nothing.
 *
 * Writes never block: the descriptor is non-blocking, and bytes that do not fit in the
 * kernel's buffer (no reader on the pty, a slow UART) are dropped and counted. With "pty"
 * the program opens a pseudo-terminal and reports the name of its other end for a viewer
 * to open; it keeps that end open itself too, so a viewer may come and go.
 */
#ifndef LHAL_SERIAL_H
#define LHAL_SERIAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** A telemetry stream. */
typedef struct {
    int fd;           /**< -1 when there is none */
    int peer_fd;      /**< our own hold on the pty's other end, or -1 */
    char name[128];   /**< the device, or the pty's other end */
    uint64_t sent;    /**< bytes written */
    uint64_t dropped; /**< bytes that did not fit */
} serial_t;

/** Whether a baud rate is one serial_open() can set. */
bool serial_baud_supported(uint32_t baud);

/**
 * Open the stream.
 * @param spec  "none", "pty", or a device path such as /dev/serial0
 * @param baud  for a device: a rate serial_baud_supported() accepts
 * @return 0, or -1 with err naming the device and the reason
 */
int serial_open(serial_t *s, const char *spec, uint32_t baud, char *err, size_t errlen);

/** Write what fits without blocking; the rest is dropped and counted. @return bytes written */
size_t serial_write(serial_t *s, const uint8_t *data, size_t len);

/** Read what is there without blocking. @return bytes read */
size_t serial_read(serial_t *s, uint8_t *data, size_t len);

/** Close the stream (safe on one that was never opened after serial_open failed). */
void serial_close(serial_t *s);

#endif /* LHAL_SERIAL_H */
