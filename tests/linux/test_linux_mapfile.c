/* SPDX-License-Identifier: MIT */
/* Tests of the map images: PGM layout (north up), grey levels, the ROS YAML. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "hal_common/mapexport.h"
#include "lhal/mapfile.h"
#include "slam/config.h"
#include "tmptree.h"

static void test_pgm_is_flipped_and_trinary(void **state)
{
    (void)state;
    char root[TMPTREE_PATH_MAX];
    tmptree_make(root, "map");
    /* 3 × 2 cells of an evidence map; row b = 0 is the southern one: unknown (log-odds 0),
     * free, occupied, then occupied, free at the floor, free. */
    const uint8_t cells[6] = {128, 100, 140, /* b = 0 */ 255, 0, 1 /* b = 1 */};
    uint8_t img[6];
    mapx_trinary(OM_MODE_EVIDENCE, cells, NULL, NULL, 3, 2, img);
    const mapfile_geometry_t geo = {50000u, -4000000, -25000};
    assert_int_equal(mapfile_write(root, "om", img, 3, 2, true, &geo), 0);

    const char *pgm = tmptree_read(root, "om.pgm");
    const char header[] = "P5\n3 2\n255\n";
    assert_memory_equal(pgm, header, sizeof header - 1u);
    const uint8_t *px = (const uint8_t *)pgm + sizeof header - 1u;
    /* First image row: b = 1 (north up). */
    const uint8_t want[6] = {0, 254, 254, /* b = 0 */ 205, 254, 0};
    assert_memory_equal(px, want, sizeof want);

    assert_string_equal(tmptree_read(root, "om.yaml"), "image: om.pgm\n"
                                                       "mode: trinary\n"
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
    assert_int_not_equal(mapfile_write("/nonexistent/dir", "tm", cells, 3, 3, false, &geo), 0);
}

/* TM is an image of visit counts and has no YAML: no map loader reads it as obstacles. */
static void test_tm_has_no_yaml(void **state)
{
    (void)state;
    char root[TMPTREE_PATH_MAX];
    tmptree_make(root, "tm");
    const uint8_t tm[2] = {0, 30};
    uint8_t img[2];
    mapx_counts(tm, 30, 2, 1, img);
    const mapfile_geometry_t geo = {50000u, 0, 0};
    assert_int_equal(mapfile_write(root, "tm", img, 2, 1, false, &geo), 0);
    const uint8_t *px = (const uint8_t *)tmptree_read(root, "tm.pgm") + 11;
    assert_int_equal(px[0], 255);
    assert_int_equal(px[1], 0);
    assert_false(tmptree_exists(root, "tm.yaml"));
    tmptree_remove(root);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pgm_is_flipped_and_trinary),
        cmocka_unit_test(test_tm_has_no_yaml),
        cmocka_unit_test(test_unwritable_directory_fails),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
