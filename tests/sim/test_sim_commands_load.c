/* SPDX-License-Identifier: MIT */
/* host_sim's --commands reader (host_sim/commands.c): its work bounded by counts, and what
 * it makes of a long file. */
#define _POSIX_C_SOURCE 200809L /* getpid */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "host_sim.h"

/* N12: 100 000 lines grew the arrays one element a line, each growth a copy of all so far
 * (quadratic: over 120 s and 926 MB under ASan). Doubling makes it a few dozen. */
static void test_a_long_file_grows_its_arrays_geometrically(void **state)
{
    (void)state;
    char path[64];
    snprintf(path, sizeof path, "/tmp/slam-commands-%ld.txt", (long)getpid());
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    const size_t lines = 100000u;
    for (size_t i = 0; i < lines; i++) {
        fprintf(f, "%zu.%02zu %s\n", i / 100u, i % 100u, i % 2u ? "stop" : "set cruise_mm_s 150");
    }
    fclose(f);
    commands_t c;
    assert_int_equal(commands_load(path, &c), 0);
    unlink(path);
    assert_int_equal(c.n, lines);
    /* Both arrays double: at most log2 of their final size each, whatever the count. */
    assert_true(c.grows <= 2u * 24u);
    assert_true(c.lines_cap >= c.n && c.lines_cap < 2u * c.n + 64u);
    assert_true(c.bytes_cap >= c.nbytes && c.bytes_cap < 2u * c.nbytes + 1024u);
    /* The lines kept their order and bytes: the last is a STOP frame at 999.99 s. */
    const command_line_t *last = &c.lines[c.n - 1u];
    assert_int_equal(last->tick, 99999u);
    assert_int_equal(c.bytes[last->offset + 2u], TELEM_CMD_STOP);
    assert_int_equal(last->offset + last->len, c.nbytes);
    commands_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_long_file_grows_its_arrays_geometrically),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
