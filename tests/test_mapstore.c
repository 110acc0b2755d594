/* SPDX-License-Identifier: MIT */
/* Tests of map persistence: round trip, alternating slots, torn saves, damaged data. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "fake_hal.h"
#include "slam/error.h"
#include "slam/mapstore.h"
#include "slam/robot.h"

static grid_t grid;
static grid_t loaded;
static mapstore_t store;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    fake_hal_reset();
    slam_config_default(&cfg);
    grid_init(&grid, &cfg);
    grid_init(&loaded, &cfg); /* a map loads into a grid of its size */
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        grid.om[i] = (uint8_t)(i % 10u);
        grid.tm[i] = (uint8_t)((i * 7u) % 31u);
    }
    return 0;
}

/* Runs a save to the end; returns the number of steps it took. */
static unsigned save(const odom_pose_t *pose, uint32_t ticks)
{
    mapstore_begin(&store, &grid, pose, ticks);
    unsigned steps = 0;
    unsigned writes = fake_hal.calls_storage_write;
    while (store.active) {
        (void)mapstore_step(&store, &grid);
        steps++;
        assert_true(fake_hal.calls_storage_write - writes <= 1u); /* one chunk a step */
        writes = fake_hal.calls_storage_write;
    }
    return steps;
}

static void test_crc32_check_value(void **state)
{
    (void)state;
    assert_int_equal(mapstore_crc32(0u, (const uint8_t *)"123456789", 9u), 0xCBF43926u);
    /* Continuing a CRC is the same as one pass. */
    uint32_t c = mapstore_crc32(0u, (const uint8_t *)"1234", 4u);
    assert_int_equal(mapstore_crc32(c, (const uint8_t *)"56789", 5u), 0xCBF43926u);
}

static void test_round_trip_and_alternating_slots(void **state)
{
    (void)state;
    mapstore_init(&store, &grid);
    assert_true(store.available);
    odom_pose_t pose = {123456, -654321, 0x12345678u};
    unsigned steps = save(&pose, 777u);
    /* 2·160·160 bytes in 256-byte chunks, then the header. */
    assert_int_equal(steps, (2u * SLAM_GRID_CELLS + MAPSTORE_CHUNK - 1u) / MAPSTORE_CHUNK + 1u);
    assert_int_equal(store.saves, 1u);
    assert_true(fake_hal.storage_committed[0]);
    mapstore_header_t h;
    assert_int_equal(mapstore_read_header(0, &h), SLAM_OK);
    assert_int_equal(h.seq, 1u);
    assert_int_equal(h.ticks, 777u);
    assert_int_equal(mapstore_read_header(1, &h), SLAM_EIO);

    odom_pose_t got = {0, 0, 0u};
    assert_int_equal(mapstore_load(&loaded, &got), SLAM_OK);
    assert_memory_equal(loaded.om, grid.om, SLAM_GRID_CELLS);
    assert_memory_equal(loaded.tm, grid.tm, SLAM_GRID_CELLS);
    assert_int_equal(loaded.origin_x_um, grid.origin_x_um);
    assert_int_equal(loaded.cell_um, grid.cell_um);
    assert_memory_equal(&got, &pose, sizeof pose);

    /* The next saves alternate, and the newest wins. */
    grid.om[5] = 9u;
    save(&pose, 800u);
    assert_int_equal(mapstore_read_header(1, &h), SLAM_OK);
    assert_int_equal(h.seq, 2u);
    save(&pose, 900u);
    assert_int_equal(mapstore_read_header(0, &h), SLAM_OK);
    assert_int_equal(h.seq, 3u);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_OK);
    assert_int_equal(loaded.om[5], 9u);

    /* After a restart, saves continue the sequence in the other slot. */
    mapstore_init(&store, &grid);
    assert_int_equal(store.last_seq, 3u);
    save(&pose, 1000u);
    assert_int_equal(mapstore_read_header(1, &h), SLAM_OK);
    assert_int_equal(h.seq, 4u);
}

/* A map saved from a grid of one size (grid_a, grid_b) is the map of a run of that size: a
 * grid of another size refuses it, and a grid of its size loads exactly its A·B cells. */
static void test_map_of_another_size_is_refused(void **state)
{
    (void)state;
    slam_config_t small = cfg;
    small.grid_a = 100u;
    small.grid_b = 60u;
    small.start_cell_a = 50u;
    small.start_cell_b = 30u;
    assert_int_equal(slam_config_check(&small, NULL), SLAM_OK);
    grid_init(&grid, &small);
    for (uint32_t i = 0; i < grid_cells(&grid); i++) {
        grid.om[i] = (uint8_t)(i % 13u);
    }
    mapstore_init(&store, &grid);
    odom_pose_t pose = {1, 2, 3u};
    unsigned steps = save(&pose, 5u);
    assert_int_equal(steps, (2u * 6000u + MAPSTORE_CHUNK - 1u) / MAPSTORE_CHUNK + 1u);
    mapstore_header_t h;
    assert_int_equal(mapstore_read_header(0, &h), SLAM_OK);
    assert_int_equal(h.a, 100u);
    assert_int_equal(h.b, 60u);
    /* The default grid, the capacity: another size. */
    memset(loaded.om, 0xEE, sizeof loaded.om);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_EINVAL);
    assert_int_equal(loaded.om[0], 0xEE);
    grid_init(&loaded, &small);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_OK);
    assert_memory_equal(loaded.om, grid.om, 6000u);
    assert_memory_equal(loaded.tm, grid.tm, 6000u);
}

/* A save that dies half-way (power cut, failing flash) leaves the previous map loadable. */
static void test_torn_save_keeps_the_last_good_map(void **state)
{
    (void)state;
    mapstore_init(&store, &grid);
    odom_pose_t pose = {1, 2, 3u};
    save(&pose, 1u); /* slot 0, seq 1: the good map */
    uint8_t good_om0 = grid.om[0];
    grid.om[0] = 7u; /* the map moves on */
    fake_hal.storage_fail_at = (int)fake_hal.calls_storage_write + 50;
    save(&pose, 2u); /* into slot 1, dies on its 50th write */
    assert_int_equal(store.failures, 1u);
    assert_int_equal(store.saves, 1u);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_OK);
    assert_int_equal(loaded.om[0], good_om0);
    /* The next save retries the same slot, not the good one. */
    fake_hal.storage_fail_at = 0;
    save(&pose, 3u);
    mapstore_header_t h;
    assert_int_equal(mapstore_read_header(1, &h), SLAM_OK);
    assert_int_equal(h.seq, 2u);
    assert_int_equal(mapstore_read_header(0, &h), SLAM_OK);
    assert_int_equal(h.seq, 1u);
}

static void test_damage_is_detected(void **state)
{
    (void)state;
    mapstore_init(&store, &grid);
    odom_pose_t pose = {0, 0, 0u};
    save(&pose, 1u);
    grid.tm[9] = 1u;
    save(&pose, 2u);
    /* A flipped data byte in the newest record: the older one is loaded instead. */
    fake_hal.storage[1][sizeof(mapstore_header_t) + 100u] ^= 0x40u;
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_OK);
    assert_int_equal(loaded.tm[9], (uint8_t)((9u * 7u) % 31u));
    /* Both damaged: nothing loads, and the grid is left alone. */
    fake_hal.storage[0][sizeof(mapstore_header_t) + 5u] ^= 0x01u;
    memset(loaded.om, 0xEE, SLAM_GRID_CELLS);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_EIO);
    assert_int_equal(loaded.om[0], 0xEE);
    /* A damaged header is no header. */
    fake_hal.storage[0][6] ^= 0x01u;
    mapstore_header_t h;
    assert_int_equal(mapstore_read_header(0, &h), SLAM_EIO);
}

static void test_map_changing_during_a_save_stays_consistent(void **state)
{
    (void)state;
    mapstore_init(&store, &grid);
    odom_pose_t pose = {0, 0, 0u};
    mapstore_begin(&store, &grid, &pose, 0u);
    uint32_t k = 0;
    while (mapstore_step(&store, &grid)) {
        grid.om[(k * 7919u) % SLAM_GRID_CELLS] ^= 1u; /* the tick keeps mapping */
        k++;
    }
    assert_int_equal(store.saves, 1u);
    assert_int_equal(mapstore_load(&loaded, NULL), SLAM_OK);
}

static void test_robot_idle_saves_periodically_and_on_request(void **state)
{
    (void)state;
    static robot_t robot;
    cfg.save_period_s = 1u;
    cfg.explore_mode = EXPLORE_OFF;
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    for (int t = 0; t < 99; t++) {
        robot_tick(&robot);
        robot_idle(&robot);
    }
    assert_int_equal(fake_hal.calls_storage_write, 0u); /* not yet: 1 s is 100 ticks */
    for (int i = 0; i < 300; i++) { /* a chunk an idle call, the ticks going on */
        robot_tick(&robot);
        robot_idle(&robot);
    }
    assert_int_equal(robot.store.saves, 1u);
    robot_request_save(&robot);
    for (int i = 0; i < 300; i++) {
        robot_tick(&robot);
        robot_idle(&robot);
    }
    assert_int_equal(robot.store.saves, 2u);
    assert_int_equal(fake_hal.calls_storage_commit, 2u);
}

/* A save begins only with the robot at a stand: the erase may stall an MCU for seconds. */
static void test_save_waits_for_the_robot_to_stop(void **state)
{
    (void)state;
    static robot_t robot;
    cfg.save_period_s = 2u;
    cfg.explore_mode = EXPLORE_SQUARE; /* drives straight from the first tick */
    assert_int_equal(robot_init(&robot, &cfg), SLAM_OK);
    unsigned moving_ticks = 0;
    for (int t = 0; t < 700; t++) {
        /* The wheels turn as commanded: 1 count a tick per 100 duty. */
        fake_hal.encoder[0] = (uint16_t)(fake_hal.encoder[0] + fake_hal.motor[0] / 100);
        fake_hal.encoder[1] = (uint16_t)(fake_hal.encoder[1] + fake_hal.motor[1] / 100);
        robot_tick(&robot);
        robot_idle(&robot);
        moving_ticks += fake_hal.motor[0] != 0;
    }
    assert_true(moving_ticks > 400u);                /* it drove, and drove on after */
    assert_true(fake_hal.calls_storage_begin >= 2u); /* saves every 2 s */
    assert_int_equal(fake_hal.storage_begin_moving, 0u);
    assert_true(robot.store.saves >= 1u);
}

static void test_no_storage_means_no_saves(void **state)
{
    (void)state;
    fake_hal.storage_size = 1000u; /* too small for a record */
    mapstore_init(&store, &grid);
    assert_false(store.available);
    odom_pose_t pose = {0, 0, 0u};
    mapstore_begin(&store, &grid, &pose, 0u);
    assert_false(store.active);
    assert_false(mapstore_step(&store, &grid));
    assert_int_equal(fake_hal.calls_storage_write, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_crc32_check_value, setup),
        cmocka_unit_test_setup(test_round_trip_and_alternating_slots, setup),
        cmocka_unit_test_setup(test_torn_save_keeps_the_last_good_map, setup),
        cmocka_unit_test_setup(test_damage_is_detected, setup),
        cmocka_unit_test_setup(test_map_changing_during_a_save_stays_consistent, setup),
        cmocka_unit_test_setup(test_robot_idle_saves_periodically_and_on_request, setup),
        cmocka_unit_test_setup(test_save_waits_for_the_robot_to_stop, setup),
        cmocka_unit_test_setup(test_no_storage_means_no_saves, setup),
        cmocka_unit_test_setup(test_map_of_another_size_is_refused, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
