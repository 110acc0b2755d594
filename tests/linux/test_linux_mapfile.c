/* SPDX-License-Identifier: MIT */
/* Tests of the map images: PGM layout (north up), grey levels, the ROS YAML. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "lhal/mapfile.h"
#include "tmptree.h"

static void test_pgm_is_flipped_and_scaled(void **state)
{
    (void)state;
    char root[TMPTREE_PATH_MAX];
    tmptree_make(root, "map");
    /* 3 × 2 cells; row b = 0 is the southern one. */
    const uint8_t cells[6] = {0, 3, 9, /* b = 0 */ 12, 1, 0 /* b = 1 */};
    const mapfile_geometry_t geo = {50000u, -4000000, -25000};
    assert_int_equal(mapfile_write(root, "om", cells, 3, 2, 9, &geo), 0);

    const char *pgm = tmptree_read(root, "om.pgm");
    const char header[] = "P5\n3 2\n255\n";
    assert_memory_equal(pgm, header, sizeof header - 1u);
    const uint8_t *px = (const uint8_t *)pgm + sizeof header - 1u;
    /* First image row: b = 1 (north up); 12 saturates at 9 = black. */
    const uint8_t want[6] = {0, 255 - 255 / 9, 255, /* b = 0 */ 255, 255 - 3 * 255 / 9, 0};
    assert_memory_equal(px, want, sizeof want);

    assert_string_equal(tmptree_read(root, "om.yaml"),
                        "image: om.pgm\n"
                        "resolution: 0.050000\n"
                        "origin: [-4.000000, -0.025000, 0.0]\n"
                        "negate: 0\n"
                        "occupied_thresh: 0.65\n"
                        "free_thresh: 0.196\n");
    assert_false(tmptree_exists(root, "om.pgm.tmp"));
    tmptree_remove(root);
}

static void test_unwritable_directory_fails(void **state)
{
    (void)state;
    const uint8_t cells[9] = {0};
    const mapfile_geometry_t geo = {50000u, 0, 0};
    assert_int_not_equal(mapfile_write("/nonexistent/dir", "tm", cells, 3, 3, 30, &geo), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pgm_is_flipped_and_scaled),
        cmocka_unit_test(test_unwritable_directory_fails),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
