/* SPDX-License-Identifier: MIT */
/* Tests of the telemetry stream: a pseudo-terminal, a file, none; writes that never block. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "lhal/serial.h"
#include "tmptree.h"

static void test_none_sends_nothing_and_counts_it(void **state)
{
    (void)state;
    serial_t s;
    char err[256] = "";
    assert_int_equal(serial_open(&s, "none", 115200u, err, sizeof err), 0);
    const uint8_t data[3] = {1, 2, 3};
    assert_int_equal(serial_write(&s, data, sizeof data), 0);
    assert_int_equal(s.dropped, 3);
    uint8_t buf[4];
    assert_int_equal(serial_read(&s, buf, sizeof buf), 0);
    serial_close(&s);
}

static void test_pty_carries_bytes_both_ways_unchanged(void **state)
{
    (void)state;
    serial_t s;
    char err[256] = "";
    assert_int_equal(serial_open(&s, "pty", 115200u, err, sizeof err), 0);
    assert_int_equal(strncmp(s.name, "/dev/pts/", 9), 0);
    /* Binary bytes, including ones a terminal would translate or echo. */
    const uint8_t frame[6] = {0x7E, '\n', '\r', 0x03, 0x00, 0xFF};
    assert_int_equal(serial_write(&s, frame, sizeof frame), sizeof frame);
    int viewer = open(s.name, O_RDWR | O_NOCTTY | O_NONBLOCK);
    assert_true(viewer >= 0);
    uint8_t buf[16];
    ssize_t n = read(viewer, buf, sizeof buf);
    assert_int_equal(n, sizeof frame);
    assert_memory_equal(buf, frame, sizeof frame);
    /* Nothing came back to our side (no echo). */
    assert_int_equal(serial_read(&s, buf, sizeof buf), 0);
    /* The viewer's bytes reach hal_uart_read(). */
    assert_int_equal(write(viewer, "go", 2), 2);
    size_t got = 0;
    for (int tries = 0; tries < 1000 && got < 2u; tries++) {
        got += serial_read(&s, buf + got, sizeof buf - got);
    }
    assert_int_equal(got, 2);
    assert_memory_equal(buf, "go", 2);
    close(viewer);
    assert_int_equal(s.sent, sizeof frame);
    assert_int_equal(s.dropped, 0);
    serial_close(&s);
}

static void test_full_pty_drops_instead_of_blocking(void **state)
{
    (void)state;
    serial_t s;
    char err[256] = "";
    assert_int_equal(serial_open(&s, "pty", 115200u, err, sizeof err), 0);
    static uint8_t chunk[4096];
    memset(chunk, 0x55, sizeof chunk);
    uint64_t offered = 0;
    size_t last = sizeof chunk;
    /* Nobody reads: the kernel's buffer fills and then writes come back short. */
    for (int i = 0; i < 1024 && last == sizeof chunk; i++) {
        last = serial_write(&s, chunk, sizeof chunk);
        offered += sizeof chunk;
    }
    assert_true(last < sizeof chunk);
    assert_true(s.dropped > 0u);
    assert_int_equal(s.sent + s.dropped, offered);
    /* Still not blocking. The kernel may have moved a few bytes on toward the reader's
     * side since the short write, so this byte may go; either way it is counted. */
    (void)serial_write(&s, chunk, 1);
    assert_int_equal(s.sent + s.dropped, offered + 1u);
    serial_close(&s);
}

static void test_plain_file_records_the_stream(void **state)
{
    (void)state;
    char root[TMPTREE_PATH_MAX];
    tmptree_make(root, "serial");
    tmptree_file(root, "log", "");
    char path[TMPTREE_PATH_MAX + 8];
    snprintf(path, sizeof path, "%s/log", root);
    serial_t s;
    char err[256] = "";
    assert_int_equal(serial_open(&s, path, 115200u, err, sizeof err), 0);
    assert_int_equal(serial_write(&s, (const uint8_t *)"abc", 3), 3);
    serial_close(&s);
    assert_string_equal(tmptree_read(root, "log"), "abc");
    tmptree_remove(root);
}

static void test_missing_device_is_named(void **state)
{
    (void)state;
    serial_t s;
    char err[256] = "";
    assert_int_equal(serial_open(&s, "/dev/ttyNOSUCH9", 115200u, err, sizeof err), -1);
    assert_non_null(strstr(err, "telemetry '/dev/ttyNOSUCH9': cannot open"));
    assert_int_equal(s.fd, -1);
    assert_int_equal(serial_write(&s, (const uint8_t *)"x", 1), 0);
}

static void test_supported_rates(void **state)
{
    (void)state;
    assert_true(serial_baud_supported(9600u));
    assert_true(serial_baud_supported(115200u));
    assert_true(serial_baud_supported(921600u));
    assert_false(serial_baud_supported(0u));
    assert_false(serial_baud_supported(115201u));
    assert_false(serial_baud_supported(1000000u));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_none_sends_nothing_and_counts_it),
        cmocka_unit_test(test_pty_carries_bytes_both_ways_unchanged),
        cmocka_unit_test(test_full_pty_drops_instead_of_blocking),
        cmocka_unit_test(test_plain_file_records_the_stream),
        cmocka_unit_test(test_missing_device_is_named),
        cmocka_unit_test(test_supported_rates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
