/* SPDX-License-Identifier: MIT */
/*
 * Map storage against power cuts, on a model of NOR flash (a write only programs bits, an
 * erase sets them): a save cut at every write, with part of the chunk landed and one byte
 * half-programmed; a header torn at every byte; an erase cut part-way, clean or leaving
 * bits half-erased; two cuts in a row; rotted data in the newest record. After each cut
 * the robot reboots (mapstore_init), and the newest intact map must load.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "fake_hal.h"
#include "slam/error.h"
#include "slam/mapstore.h"

#define DATA_BYTES (2u * SLAM_GRID_CELLS)
#define WRITES ((DATA_BYTES + MAPSTORE_CHUNK - 1u) / MAPSTORE_CHUNK + 1u) /* chunks, header */
#define HEADER_AT ((long)DATA_BYTES) /* bytes a save programs before its header */

static grid_t grid;
static grid_t loaded;
static mapstore_t store;
static uint8_t saved[HAL_STORAGE_SLOTS][FAKE_HAL_STORAGE_SIZE]; /* a scenario's start */

/* The maps of save number v: every version differs in every cell. */
static void draw(unsigned v)
{
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        grid.om[i] = (uint8_t)((i * 7u + v) % 10u);
        grid.tm[i] = (uint8_t)((i * 13u + 3u * v) % 31u);
    }
}

/* Which version the loaded maps are: -1 none loaded, -2 a map that was never saved. */
static int version_loaded(void)
{
    memset(loaded.om, 0xEE, SLAM_GRID_CELLS);
    if (mapstore_load(&loaded, NULL) != SLAM_OK) {
        return -1;
    }
    for (unsigned v = 1; v < 10u; v++) {
        draw(v);
        if (memcmp(loaded.om, grid.om, SLAM_GRID_CELLS) == 0 &&
            memcmp(loaded.tm, grid.tm, SLAM_GRID_CELLS) == 0) {
            return (int)v;
        }
    }
    return -2;
}

static void reboot(void)
{
    fake_hal_power_on();
    mapstore_init(&store, &grid);
}

/* Save version v; with a budget, the power fails after that many bytes. Returns whether
 * the save finished. */
static bool save(unsigned v, long budget, uint8_t bits)
{
    draw(v);
    fake_hal.storage_cut_after = budget;
    fake_hal.storage_cut_bits = bits;
    odom_pose_t pose = {(int32_t)v, 0, 0u};
    mapstore_begin(&store, &grid, &pose, v);
    while (store.active && !fake_hal.storage_powered_off) {
        (void)mapstore_step(&store, &grid);
    }
    bool done = !fake_hal.storage_powered_off && store.saves > 0u && !store.active;
    fake_hal.storage_cut_after = -1;
    return done;
}

/* Two good saves, v1 then v2 (slots 0 and 1), kept to start each case from. */
static int setup(void **state)
{
    (void)state;
    fake_hal_reset();
    fake_hal.storage_nor = true;
    slam_config_t cfg;
    slam_config_default(&cfg);
    grid_init(&grid, &cfg);
    grid_init(&loaded, &cfg);
    mapstore_init(&store, &grid);
    assert_true(save(1u, -1, 0u));
    assert_true(save(2u, -1, 0u));
    memcpy(saved, fake_hal.storage, sizeof saved);
    return 0;
}

static void restart(void)
{
    memcpy(fake_hal.storage, saved, sizeof saved);
    reboot();
}

/* The budgets that cut a save at every write, each with none, one, half and all but one
 * byte of its chunk landed (and the next byte half-programmed), and in the header at every
 * byte. */
static size_t cut_points(long *out)
{
    size_t n = 0;
    for (uint32_t w = 0; w + 1u < WRITES; w++) {
        uint32_t left = DATA_BYTES - w * MAPSTORE_CHUNK;
        long at = (long)(w * MAPSTORE_CHUNK);
        long len = (long)(left < MAPSTORE_CHUNK ? left : MAPSTORE_CHUNK);
        const long part[4] = {0, 1, len / 2, len - 1};
        for (int k = 0; k < 4; k++) {
            out[n++] = at + part[k];
        }
    }
    for (long b = 0; b < (long)sizeof(mapstore_header_t); b++) {
        out[n++] = HEADER_AT + b;
    }
    return n;
}

static long cuts[4u * WRITES + 64u];

/* What must load after a cut save of version v over a store whose newest intact map is
 * `before`: that one, unless the whole header landed (a half-programmed byte may equal
 * its target), in which case the new one. */
static int expected(unsigned v, int before)
{
    mapstore_header_t h;
    if (mapstore_read_header(store.slot, &h) == SLAM_OK && h.seq == store.hdr.seq &&
        memcmp(&h, &store.hdr, sizeof h) == 0) {
        return (int)v;
    }
    return before;
}

/* A save cut at every write: the last good map (v2) survives, and the next save works. */
static void test_cut_at_every_write(void **state)
{
    (void)state;
    size_t n = cut_points(cuts);
    unsigned new_ones = 0;
    for (size_t i = 0; i < n; i++) {
        restart();
        static const uint8_t bits[3] = {0x0Fu, 0xA5u, 0x01u};
        assert_false(save(3u, cuts[i], bits[i % 3u]));
        int want = expected(3u, 2);
        new_ones += want == 3;
        reboot();
        int got = version_loaded();
        if (got != want) {
            fail_msg("cut after %ld bytes: loaded %d, want %d", cuts[i], got, want);
        }
        if (i % 4u == 0u) { /* the next save after the reboot */
            assert_true(save(4u, -1, 0u));
            assert_int_equal(version_loaded(), 4);
        }
    }
    print_message("%zu cuts, %u of them after the header had landed whole\n", n, new_ones);
    assert_true(new_ones <= 3u);
}

/* A cut, a reboot, another cut at any point of the next save: still the last good map. */
static void test_two_cuts_in_a_row(void **state)
{
    (void)state;
    size_t n = cut_points(cuts);
    const long first[] = {0, 1, 300 * 256 / 2, HEADER_AT - 1, HEADER_AT + 20};
    unsigned cases = 0;
    for (size_t f = 0; f < sizeof first / sizeof first[0]; f++) {
        for (size_t i = 0; i < n; i += 6u) {
            restart();
            assert_false(save(3u, first[f], 0x0Fu));
            int want = expected(3u, 2);
            reboot();
            assert_false(save(4u, cuts[i], 0x0Fu));
            want = expected(4u, want);
            reboot();
            int got = version_loaded();
            if (got != want) {
                fail_msg("cuts after %ld then %ld bytes: loaded %d, want %d", first[f], cuts[i],
                         got, want);
            }
            cases++;
        }
    }
    print_message("%u pairs of cuts\n", cases);
}

/* The erase of the slot being rewritten is cut: clean, or leaving bits half-erased; the
 * record in the other slot loads, and the next save works. */
static void test_erase_cut(void **state)
{
    (void)state;
    const uint32_t done[] = {0u,
                             1u,
                             24u,
                             47u,
                             48u,
                             49u,
                             4096u,
                             DATA_BYTES / 2u,
                             DATA_BYTES + 47u,
                             FAKE_HAL_STORAGE_SIZE};
    for (int noise = 0; noise < 2; noise++) {
        for (size_t i = 0; i < sizeof done / sizeof done[0]; i++) {
            restart();
            fake_hal.storage_erase_cut = fake_hal.calls_storage_begin + 1u;
            fake_hal.storage_erase_done = done[i];
            fake_hal.storage_erase_noise = noise != 0;
            assert_false(save(3u, -1, 0u));
            reboot();
            int got = version_loaded();
            if (got != 2) {
                fail_msg("erase cut after %u bytes%s: loaded %d, want 2", done[i],
                         noise ? " (half-erased)" : "", got);
            }
            assert_true(save(4u, -1, 0u));
            assert_int_equal(version_loaded(), 4);
        }
    }
}

/* The newest record's data rots (its header still checks): the older record is the
 * newest intact map, and a save cut anywhere must not take it. */
static void test_rotted_newest_record(void **state)
{
    (void)state;
    size_t n = cut_points(cuts);
    for (size_t i = 0; i < n; i++) {
        restart();
        fake_hal.storage[1][sizeof(mapstore_header_t) + 1000u] ^= 0x10u; /* v2's data */
        reboot();
        assert_int_equal(version_loaded(), 1);
        assert_false(save(3u, cuts[i], 0xF0u));
        int want = expected(3u, 1);
        reboot();
        int got = version_loaded();
        if (got != want) {
            fail_msg("rotted v2, cut after %ld bytes: loaded %d, want %d", cuts[i], got, want);
        }
    }
    /* And with both intact the next save goes where the rotted record was. */
    restart();
    fake_hal.storage[1][sizeof(mapstore_header_t) + 5u] ^= 0x01u;
    reboot();
    assert_true(save(3u, -1, 0u));
    mapstore_header_t h;
    assert_int_equal(mapstore_read_header(1u, &h), SLAM_OK);
    assert_int_equal(h.seq, 2u); /* after v1's seq 1: the rotted seq 2 is replaced */
    assert_int_equal(version_loaded(), 3);
    assert_int_equal(mapstore_read_header(0u, &h), SLAM_OK);
    assert_int_equal(h.seq, 1u);
}

/* Nothing readable at all: no map loads, and the first save still works. */
static void test_both_slots_garbage(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof fake_hal.storage[0]; k++) {
        fake_hal.storage[0][k] = (uint8_t)(k * 31u);
        fake_hal.storage[1][k] = (uint8_t)(k * 17u + 5u);
    }
    reboot();
    assert_int_equal(version_loaded(), -1);
    assert_true(save(5u, -1, 0u));
    assert_int_equal(version_loaded(), 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_cut_at_every_write, setup),
        cmocka_unit_test_setup(test_two_cuts_in_a_row, setup),
        cmocka_unit_test_setup(test_erase_cut, setup),
        cmocka_unit_test_setup(test_rotted_newest_record, setup),
        cmocka_unit_test_setup(test_both_slots_garbage, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
