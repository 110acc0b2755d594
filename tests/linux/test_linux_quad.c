/* SPDX-License-Identifier: MIT */
/* Tests of the quadrature decoder and of the edge queue that orders A and B by timestamp. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "lhal/edgeq.h"
#include "lhal/quad.h"
#include "test_rng.h"

/* One forward encoder cycle, A leading B: (line, level) per edge. */
static const struct {
    quad_line_t line;
    bool level;
} forward[4] = {{QUAD_A, true}, {QUAD_B, true}, {QUAD_A, false}, {QUAD_B, false}};

static void test_forward_cycle_counts_four(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, false);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(quad_edge(&q, forward[i].line, forward[i].level), 1);
    }
    assert_int_equal(q.count, 4);
    assert_int_equal(q.state, 0);
    assert_int_equal(q.illegal, 0);
    assert_int_equal(q.edges, 4);
}

static void test_backward_cycle_counts_down_and_wraps(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, false);
    for (int i = 3; i >= 0; i--) {
        /* The same edges in reverse order: each undoes the level the forward edge set. */
        assert_int_equal(quad_edge(&q, forward[i].line, !forward[i].level), -1);
    }
    assert_int_equal(q.count, (uint16_t)(0u - 4u));
    assert_int_equal(q.illegal, 0);
}

static void test_every_transition_of_the_table(void **state)
{
    (void)state;
    /* Forward order of states: 00 -> 10 -> 11 -> 01 -> 00. */
    static const uint8_t next[4] = {[0] = 2, [2] = 3, [3] = 1, [1] = 0};
    for (uint8_t from = 0; from < 4; from++) {
        for (uint8_t to = 0; to < 4; to++) {
            quad_t q;
            quad_init(&q, (from & 2u) != 0u, (from & 1u) != 0u, false);
            int want = 0;
            bool illegal = (from ^ to) == 3u;
            if (next[from] == to) {
                want = 1;
            } else if (next[to] == from) {
                want = -1;
            }
            assert_int_equal(quad_step(&q, to), want);
            assert_int_equal(q.count, (uint16_t)want);
            assert_int_equal(q.illegal, illegal ? 1 : 0);
            assert_int_equal(q.state, to);
        }
    }
}

static void test_inverted_wheel_counts_the_other_way(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, true);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(quad_edge(&q, forward[i].line, forward[i].level), -1);
    }
    assert_int_equal(q.count, (uint16_t)(0u - 4u));
}

static void test_repeated_edge_is_counted_as_lost(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, false);
    assert_int_equal(quad_edge(&q, QUAD_A, true), 1);
    /* A rises again: its falling edge was lost. Nothing moves, the loss is counted. */
    assert_int_equal(quad_edge(&q, QUAD_A, true), 0);
    assert_int_equal(q.count, 1);
    assert_int_equal(q.illegal, 1);
    assert_int_equal(q.state, 2);
    /* Decoding goes on from the known state. */
    assert_int_equal(quad_edge(&q, QUAD_B, true), 1);
    assert_int_equal(q.count, 2);
}

/* Ten encoder cycles, forward or backward, with edge `drop` missing (-1: none). */
static quad_t run_cycles(bool backward, bool invert, int drop)
{
    quad_t q;
    quad_init(&q, false, false, invert);
    for (int i = 0; i < 40; i++) {
        int k = backward ? 3 - i % 4 : i % 4;
        bool level = backward ? !forward[k].level : forward[k].level;
        if (i != drop) {
            quad_edge(&q, forward[k].line, level);
        }
    }
    return q;
}

/* The kernel's queue of a line overflowed and one edge is gone: the other line's next edge
 * must not count backwards from the stale level (ten cycles used to count 36). Any edge
 * followed by another edge of its line is reconstructed: the run counts 40. */
static void test_a_lost_edge_is_put_back(void **state)
{
    (void)state;
    for (int backward = 0; backward < 2; backward++) {
        for (int invert = 0; invert < 2; invert++) {
            int sign = (backward ? -1 : 1) * (invert ? -1 : 1);
            for (int drop = 0; drop < 38; drop++) {
                quad_t q = run_cycles(backward, invert, drop);
                if (q.count != (uint16_t)(sign * 40) || q.illegal != 1u) {
                    fail_msg("backward %d invert %d, edge %d dropped: count %d, %u lost", backward,
                             invert, drop, (int16_t)q.count, (unsigned)q.illegal);
                }
            }
            quad_t q = run_cycles(backward, invert, -1);
            assert_int_equal(q.count, (uint16_t)(sign * 40));
            assert_int_equal(q.illegal, 0);
        }
    }
}

/* Between the lost edge and its line's next edge the other line's edge has counted from
 * the stale level; the next edge corrects it, and nothing ever ran backwards overall. */
static void test_the_correction_comes_with_the_next_edge_of_the_line(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, false);
    assert_int_equal(quad_edge(&q, QUAD_A, true), 1); /* 00 -> 10 */
    assert_int_equal(quad_edge(&q, QUAD_B, true), 1); /* 10 -> 11 */
    /* A falls, lost. B falls: from the stale 11 that reads as backward. */
    assert_int_equal(quad_edge(&q, QUAD_B, false), -1);
    /* A rises: A's fall was lost. The B edge is counted again, the two A edges added. */
    assert_int_equal(quad_edge(&q, QUAD_A, true), 4);
    assert_int_equal(q.count, 5);
    assert_int_equal(q.illegal, 1);
    assert_int_equal(quad_edge(&q, QUAD_B, true), 1);
    assert_int_equal(q.count, 6);
}

static void test_start_state_comes_from_the_lines(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, true, true, false);                  /* state 11 */
    assert_int_equal(quad_edge(&q, QUAD_A, false), 1); /* 11 -> 01 is forward */
    assert_int_equal(q.illegal, 0);
}

static void test_counter_wraps_at_16_bits(void **state)
{
    (void)state;
    quad_t q;
    quad_init(&q, false, false, false);
    for (uint32_t i = 0; i < 70000u; i++) {
        quad_edge(&q, forward[i % 4u].line, forward[i % 4u].level);
    }
    assert_int_equal(q.count, 70000u % 65536u);
}

/* ---- edge queue ---------------------------------------------------------------------- */

static edgeq_edge_t edge(uint64_t ts, uint8_t src, bool rising)
{
    return (edgeq_edge_t){.ts_ns = ts, .src = src, .rising = rising};
}

static void test_queue_orders_by_timestamp_and_holds_back(void **state)
{
    (void)state;
    edgeq_t q;
    edgeq_init(&q);
    assert_true(edgeq_empty(&q));
    /* B's reader ran first: its later edges arrive before A's earlier ones. */
    assert_true(edgeq_push(&q, edge(300, 1, true)));
    assert_true(edgeq_push(&q, edge(700, 1, false)));
    assert_true(edgeq_push(&q, edge(100, 0, true)));
    assert_true(edgeq_push(&q, edge(500, 0, false)));
    edgeq_edge_t out[8];
    assert_int_equal(edgeq_pop_until(&q, 500, out, 8), 3);
    assert_int_equal(out[0].ts_ns, 100);
    assert_int_equal(out[1].ts_ns, 300);
    assert_int_equal(out[2].ts_ns, 500);
    assert_false(edgeq_empty(&q)); /* 700 is newer than the cutoff */
    assert_int_equal(edgeq_pop_until(&q, 699, out, 8), 0);
    assert_int_equal(edgeq_pop_until(&q, UINT64_MAX, out, 8), 1);
    assert_int_equal(out[0].ts_ns, 700);
    assert_true(edgeq_empty(&q));
}

static void test_queue_keeps_arrival_order_of_ties_and_limits(void **state)
{
    (void)state;
    edgeq_t q;
    edgeq_init(&q);
    assert_true(edgeq_push(&q, edge(10, 0, true)));
    assert_true(edgeq_push(&q, edge(10, 1, true)));
    edgeq_edge_t out[2];
    assert_int_equal(edgeq_pop_until(&q, UINT64_MAX, out, 1), 1); /* max is honoured */
    assert_int_equal(out[0].src, 0);
    assert_int_equal(edgeq_pop_until(&q, UINT64_MAX, out, 1), 1);
    assert_int_equal(out[0].src, 1);

    for (uint32_t i = 0; i < EDGEQ_MAX; i++) {
        assert_true(edgeq_push(&q, edge(i, 0, true)));
    }
    assert_false(edgeq_push(&q, edge(0, 0, true)));
    assert_int_equal(q.n, EDGEQ_MAX);
}

/* Decodes edges in the order given. */
static uint16_t decode(const edgeq_edge_t *e, size_t n, uint32_t *illegal)
{
    quad_t q;
    quad_init(&q, false, false, false);
    for (size_t i = 0; i < n; i++) {
        quad_edge(&q, (quad_line_t)e[i].src, e[i].rising);
    }
    *illegal = q.illegal;
    return q.count;
}

static void test_reading_lines_one_after_the_other_needs_the_queue(void **state)
{
    (void)state;
    /* Two forward cycles' worth of edges, as each line's descriptor returns them. */
    const edgeq_edge_t a[] = {edge(1, 0, true), edge(5, 0, false)};
    const edgeq_edge_t b[] = {edge(3, 1, true), edge(7, 1, false)};
    edgeq_edge_t seq[4] = {a[0], a[1], b[0], b[1]};
    uint32_t illegal;
    /* Fed line by line, the decoder is wrong (and cannot tell). */
    assert_int_not_equal(decode(seq, 4, &illegal), 4);
    /* Through the queue, in timestamp order, it is right. */
    edgeq_t q;
    edgeq_init(&q);
    for (size_t i = 0; i < 2; i++) {
        edgeq_push(&q, a[i]);
    }
    for (size_t i = 0; i < 2; i++) {
        edgeq_push(&q, b[i]);
    }
    assert_int_equal(edgeq_pop_until(&q, UINT64_MAX, seq, 4), 4);
    assert_int_equal(decode(seq, 4, &illegal), 4);
    assert_int_equal(illegal, 0);
}

static void test_random_walk_through_the_queue_is_exact(void **state)
{
    (void)state;
    test_rng_t rng = {.s = 5};
    for (int trial = 0; trial < 200; trial++) {
        /* A random walk of the encoder, split into the two lines' edge streams. */
        edgeq_edge_t line_edges[2][400];
        size_t nl[2] = {0, 0};
        int32_t pos = 0;
        uint8_t st = 0;
        static const uint8_t fwd[4] = {[0] = 2, [2] = 3, [3] = 1, [1] = 0};
        static const uint8_t back[4] = {[2] = 0, [3] = 2, [1] = 3, [0] = 1};
        for (uint64_t t = 1; t <= 400; t++) {
            bool up = test_rng_range(&rng, 0, 2) != 0;
            uint8_t nx = up ? fwd[st] : back[st];
            uint8_t src = (uint8_t)(((st ^ nx) & 2u) ? 0u : 1u);
            line_edges[src][nl[src]++] =
                edge(t * 1000u, src, src == 0u ? (nx & 2u) != 0u : (nx & 1u) != 0u);
            pos += up ? 1 : -1;
            st = nx;
        }
        /* Pushed in batches, a line at a time, as the events thread reads them. */
        edgeq_t q;
        edgeq_init(&q);
        quad_t dec;
        quad_init(&dec, false, false, false);
        size_t next[2] = {0, 0};
        while (next[0] < nl[0] || next[1] < nl[1]) {
            for (uint8_t src = 0; src < 2; src++) {
                size_t batch = (size_t)test_rng_range(&rng, 0, 9);
                for (size_t k = 0; k < batch && next[src] < nl[src]; k++) {
                    assert_true(edgeq_push(&q, line_edges[src][next[src]++]));
                }
            }
            /* Release what both lines have been read past. */
            uint64_t ta = next[0] < nl[0] ? line_edges[0][next[0]].ts_ns : UINT64_MAX;
            uint64_t tb = next[1] < nl[1] ? line_edges[1][next[1]].ts_ns : UINT64_MAX;
            uint64_t cutoff = (ta < tb ? ta : tb);
            cutoff = cutoff == UINT64_MAX ? cutoff : cutoff - 1u;
            edgeq_edge_t out[64];
            size_t n;
            while ((n = edgeq_pop_until(&q, cutoff, out, 64)) > 0) {
                for (size_t k = 0; k < n; k++) {
                    quad_edge(&dec, (quad_line_t)out[k].src, out[k].rising);
                }
            }
        }
        assert_true(edgeq_empty(&q));
        assert_int_equal(dec.count, (uint16_t)pos);
        assert_int_equal(dec.illegal, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forward_cycle_counts_four),
        cmocka_unit_test(test_backward_cycle_counts_down_and_wraps),
        cmocka_unit_test(test_every_transition_of_the_table),
        cmocka_unit_test(test_inverted_wheel_counts_the_other_way),
        cmocka_unit_test(test_repeated_edge_is_counted_as_lost),
        cmocka_unit_test(test_a_lost_edge_is_put_back),
        cmocka_unit_test(test_the_correction_comes_with_the_next_edge_of_the_line),
        cmocka_unit_test(test_start_state_comes_from_the_lines),
        cmocka_unit_test(test_counter_wraps_at_16_bits),
        cmocka_unit_test(test_queue_orders_by_timestamp_and_holds_back),
        cmocka_unit_test(test_queue_keeps_arrival_order_of_ties_and_limits),
        cmocka_unit_test(test_reading_lines_one_after_the_other_needs_the_queue),
        cmocka_unit_test(test_random_walk_through_the_queue_is_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
