/* SPDX-License-Identifier: MIT */
/* Tests of map storage files: atomic commits, erased reads, an interrupted rewrite. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "lhal/store.h"
#include "tmptree.h"

#define SIZE 10000u /* not a multiple of the 4 KiB erase buffer */

static char root[TMPTREE_PATH_MAX];
static char dir[TMPTREE_PATH_MAX + 16];
static store_t st;

static int setup(void **state)
{
    (void)state;
    tmptree_make(root, "store");
    snprintf(dir, sizeof dir, "%s/slots", root);
    char err[256] = "";
    assert_int_equal(store_open(&st, dir, SIZE, err, sizeof err), 0);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    store_close(&st);
    tmptree_remove(root);
    return 0;
}

static void expect_bytes(uint8_t slot, uint32_t off, uint8_t value, size_t len)
{
    uint8_t buf[SIZE];
    assert_int_equal(store_read(&st, slot, off, buf, len), HAL_OK);
    for (size_t i = 0; i < len; i++) {
        if (buf[i] != value) {
            fail_msg("slot %u byte %zu is 0x%02x, not 0x%02x", slot, off + i, buf[i], value);
        }
    }
}

static void test_open_creates_the_directory(void **state)
{
    (void)state;
    struct stat s;
    assert_int_equal(stat(dir, &s), 0);
    assert_true(S_ISDIR(s.st_mode));
    assert_int_equal(st.size, SIZE);
}

static void test_never_written_slot_reads_erased(void **state)
{
    (void)state;
    expect_bytes(0, 0, 0xFF, SIZE);
    expect_bytes(1, SIZE - 1u, 0xFF, 1u);
}

static void test_commit_makes_the_slot_durable(void **state)
{
    (void)state;
    const char msg[] = "occupancy grid";
    assert_int_equal(store_begin(&st, 1), HAL_OK);
    assert_int_equal(store_write(&st, 1, 100, msg, sizeof msg), HAL_OK);
    assert_int_equal(store_commit(&st, 1), HAL_OK);
    char buf[sizeof msg];
    assert_int_equal(store_read(&st, 1, 100, buf, sizeof buf), HAL_OK);
    assert_memory_equal(buf, msg, sizeof msg);
    expect_bytes(1, 0, 0xFF, 100u); /* the rest of the slot is erased */
    expect_bytes(0, 0, 0xFF, SIZE); /* the other slot is untouched */
    assert_true(tmptree_exists(root, "slots/slot1.bin"));
    assert_false(tmptree_exists(root, "slots/slot1.tmp"));
    struct stat s;
    char bin[TMPTREE_PATH_MAX + 32];
    snprintf(bin, sizeof bin, "%s/slot1.bin", dir);
    assert_int_equal(stat(bin, &s), 0);
    assert_int_equal(s.st_size, SIZE);
}

static void test_rewrite_without_commit_keeps_the_old_slot(void **state)
{
    (void)state;
    uint8_t old[64];
    memset(old, 0x11, sizeof old);
    assert_int_equal(store_begin(&st, 0), HAL_OK);
    assert_int_equal(store_write(&st, 0, 0, old, sizeof old), HAL_OK);
    assert_int_equal(store_commit(&st, 0), HAL_OK);

    /* A new map is half written when the power goes. */
    uint8_t fresh[64];
    memset(fresh, 0x22, sizeof fresh);
    assert_int_equal(store_begin(&st, 0), HAL_OK);
    assert_int_equal(store_write(&st, 0, 0, fresh, 32), HAL_OK);
    expect_bytes(0, 0, 0x11, 64u); /* readers see the last good one meanwhile */
    assert_true(tmptree_exists(root, "slots/slot0.tmp"));

    /* Next start: the leftover copy goes, the old slot stays whole. */
    store_t again;
    char err[256];
    assert_int_equal(store_open(&again, dir, SIZE, err, sizeof err), 0);
    assert_false(tmptree_exists(root, "slots/slot0.tmp"));
    uint8_t buf[64];
    assert_int_equal(store_read(&again, 0, 0, buf, sizeof buf), HAL_OK);
    assert_memory_equal(buf, old, sizeof old);
}

static void test_close_drops_uncommitted_rewrites(void **state)
{
    (void)state;
    assert_int_equal(store_begin(&st, 1), HAL_OK);
    assert_true(tmptree_exists(root, "slots/slot1.tmp"));
    store_close(&st);
    assert_false(tmptree_exists(root, "slots/slot1.tmp"));
    assert_false(tmptree_exists(root, "slots/slot1.bin"));
    assert_int_equal(store_commit(&st, 1), HAL_EINVAL);
}

static void test_bad_arguments_are_refused(void **state)
{
    (void)state;
    uint8_t b[16] = {0};
    assert_int_equal(store_begin(&st, HAL_STORAGE_SLOTS), HAL_EINVAL);
    assert_int_equal(store_write(&st, 0, 0, b, sizeof b), HAL_EINVAL); /* not begun */
    assert_int_equal(store_commit(&st, 0), HAL_EINVAL);
    assert_int_equal(store_begin(&st, 0), HAL_OK);
    assert_int_equal(store_write(&st, 0, SIZE - 8u, b, 16), HAL_EINVAL); /* past the end */
    assert_int_equal(store_write(&st, 0, SIZE + 1u, b, 0), HAL_EINVAL);
    assert_int_equal(store_write(&st, 0, SIZE - 16u, b, 16), HAL_OK); /* up to the end */
    assert_int_equal(store_write(&st, 2, 0, b, 1), HAL_EINVAL);
    assert_int_equal(store_read(&st, 0, SIZE, b, 1), HAL_EINVAL);
    assert_int_equal(store_read(&st, 9, 0, b, 1), HAL_EINVAL);
}

static void test_shorter_file_reads_erased_beyond_its_end(void **state)
{
    (void)state;
    tmptree_file(root, "slots/slot0.bin", "abc");
    uint8_t buf[6];
    assert_int_equal(store_read(&st, 0, 0, buf, sizeof buf), HAL_OK);
    assert_memory_equal(buf, "abc\xFF\xFF\xFF", sizeof buf);
}

static void test_unusable_directory_is_named(void **state)
{
    (void)state;
    store_t s2;
    char err[256] = "";
    tmptree_file(root, "plainfile", "x");
    char bad[TMPTREE_PATH_MAX + 32];
    snprintf(bad, sizeof bad, "%s/plainfile/slots", root);
    assert_int_equal(store_open(&s2, bad, SIZE, err, sizeof err), -1);
    assert_non_null(strstr(err, "storage_dir"));
    assert_non_null(strstr(err, "plainfile/slots"));

    char note[256];
    assert_int_equal(store_probe(bad, note, sizeof note), -1);
    assert_non_null(strstr(note, "cannot be created"));
    assert_int_equal(store_probe(dir, note, sizeof note), 0);
    assert_string_equal(note, "exists");
    char later[TMPTREE_PATH_MAX + 32];
    snprintf(later, sizeof later, "%s/later", root);
    assert_int_equal(store_probe(later, note, sizeof note), 0);
    assert_string_equal(note, "will be created");
    assert_false(tmptree_exists(root, "later")); /* a probe creates nothing */
}

static void test_write_file_replaces_atomically(void **state)
{
    (void)state;
    assert_int_equal(store_write_file(dir, "map.pgm", "first", 5), 0);
    assert_string_equal(tmptree_read(root, "slots/map.pgm"), "first");
    assert_int_equal(store_write_file(dir, "map.pgm", "2nd", 3), 0);
    assert_string_equal(tmptree_read(root, "slots/map.pgm"), "2nd");
    assert_false(tmptree_exists(root, "slots/map.pgm.tmp"));
    char missing[TMPTREE_PATH_MAX + 32];
    snprintf(missing, sizeof missing, "%s/nowhere", root);
    assert_int_equal(store_write_file(missing, "map.pgm", "x", 1), -ENOENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_open_creates_the_directory, setup, teardown),
        cmocka_unit_test_setup_teardown(test_never_written_slot_reads_erased, setup, teardown),
        cmocka_unit_test_setup_teardown(test_commit_makes_the_slot_durable, setup, teardown),
        cmocka_unit_test_setup_teardown(test_rewrite_without_commit_keeps_the_old_slot, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_close_drops_uncommitted_rewrites, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_arguments_are_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_shorter_file_reads_erased_beyond_its_end, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_unusable_directory_is_named, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_file_replaces_atomically, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
