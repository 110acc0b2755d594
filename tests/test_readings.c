/* SPDX-License-Identifier: MIT */
/* Tests of the readings queue between the tick and robot_idle(): order, a full ring, and
 * when the tick may adopt what the background loop published. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "slam/readings.h"

static readq_t queue;
static slam_config_t cfg;

static int setup(void **state)
{
    (void)state;
    slam_config_default(&cfg);
    readq_init(&queue, &cfg);
    return 0;
}

static readq_reading_t reading(int32_t x_um)
{
    return (readq_reading_t){.ping = {x_um, 0, 0u}, .range_um = 500000u, .servo = 0u, .echo = true};
}

/* A queue that is never drained fills, and every reading beyond it is counted lost. */
static void test_full_queue_drops_and_counts(void **state)
{
    (void)state;
    readq_reading_t rd = reading(0);
    for (unsigned i = 0; i < 20u; i++) {
        assert_int_equal(readq_post(&queue, &rd) != READQ_DROPPED, i < READQ_SLOTS - 1u);
    }
    assert_int_equal(queue.dropped, 20u - (READQ_SLOTS - 1u));
    readq_reading_t out;
    while (readq_take(&queue, &out)) {
        readq_done(&queue);
    }
    assert_int_equal(queue.drained, READQ_SLOTS - 1u);
}

/* Readings come out in the order they went in, each once. */
static void test_readings_come_out_in_order(void **state)
{
    (void)state;
    readq_reading_t out;
    assert_false(readq_take(&queue, &out));
    for (int32_t round = 0; round < 3; round++) { /* round the ring more than once */
        for (int32_t i = 0; i < 5; i++) {
            readq_reading_t rd = reading(round * 10 + i);
            assert_int_not_equal(readq_post(&queue, &rd), READQ_DROPPED);
        }
        for (int32_t i = 0; i < 5; i++) {
            assert_true(readq_take(&queue, &out));
            assert_int_equal(out.ping.x_um, round * 10 + i);
            readq_done(&queue);
        }
        assert_false(readq_take(&queue, &out));
    }
    assert_int_equal(queue.dropped, 0u);
}

/* A reading is current only when the loop has finished every one before it: taken is not
 * enough, since what the loop publishes for a reading is written after it is taken. */
static void test_current_once_every_reading_before_is_done(void **state)
{
    (void)state;
    readq_reading_t rd = reading(0);
    readq_reading_t out;
    assert_int_equal(readq_post(&queue, &rd), READQ_CURRENT); /* nothing before it */
    assert_int_equal(readq_post(&queue, &rd), READQ_LATE);
    assert_true(readq_take(&queue, &out));
    assert_int_equal(readq_post(&queue, &rd), READQ_LATE); /* taken, not finished */
    readq_done(&queue);
    assert_int_equal(readq_post(&queue, &rd), READQ_LATE); /* two more wait */
    while (readq_take(&queue, &out)) {
        readq_done(&queue);
    }
    assert_int_equal(readq_post(&queue, &rd), READQ_CURRENT);
    assert_int_equal(queue.late, 3u);
    assert_int_equal(queue.posted, 5u);
}

/* A lost reading is never finished: once the loop has caught up with every reading the
 * ring took, the next one is current again, and the tick may adopt the correction. */
static void test_current_again_after_a_drop(void **state)
{
    (void)state;
    readq_reading_t rd = reading(0);
    readq_reading_t out;
    for (unsigned i = 0; i < READQ_SLOTS; i++) {
        (void)readq_post(&queue, &rd);
    }
    assert_int_equal(queue.dropped, 1u);
    while (readq_take(&queue, &out)) {
        readq_done(&queue);
    }
    assert_int_equal(readq_post(&queue, &rd), READQ_CURRENT);
}

/* The queue is in use when the pose correction is configured or OM holds free-space
 * evidence; the paper's OM without correction maps every reading in the tick. */
static void test_deferred_by_configuration(void **state)
{
    (void)state;
    assert_true(queue.deferred);
    cfg.localize = 0u;
    readq_init(&queue, &cfg);
    assert_true(queue.deferred);
    cfg.om_mode = OM_MODE_COUNT;
    readq_init(&queue, &cfg);
    assert_false(queue.deferred);
    cfg.localize = 1u;
    readq_init(&queue, &cfg);
    assert_true(queue.deferred);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_full_queue_drops_and_counts, setup),
        cmocka_unit_test_setup(test_readings_come_out_in_order, setup),
        cmocka_unit_test_setup(test_current_once_every_reading_before_is_done, setup),
        cmocka_unit_test_setup(test_current_again_after_a_drop, setup),
        cmocka_unit_test_setup(test_deferred_by_configuration, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
