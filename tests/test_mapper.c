/* SPDX-License-Identifier: MIT */
/* Tests of Algorithm C.1: a scripted run increments exactly the expected cells. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "slam/config.h"
#include "slam/grid.h"
#include "slam/mapper.h"

static slam_config_t cfg;
static grid_t grid;
static mapper_t mapper;

/* One tick of the script: the pose, and what the sweep did. */
typedef struct {
    int32_t x_um;
    int32_t y_um;
    int32_t heading_deg;
    enum { NOTHING, PING, ECHO, TIMEOUT, ECHO_AND_PING } event;
    int32_t servo_deg;
    uint32_t echo_us;
} script_tick_t;

/* An expected cell of a map. */
typedef struct {
    uint16_t a;
    uint16_t b;
    uint8_t value;
} cell_value_t;

static int setup(void **state)
{
    (void)state;
    test_config_default(&cfg);
    slam_config_paper(&cfg); /* these tests hold the paper's Eq. 6 */
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    return 0;
}

static void play(const script_tick_t *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        odom_pose_t pose = {s[i].x_um, s[i].y_um, fix_bam_from_mdeg(s[i].heading_deg * 1000)};
        sweep_out_t out = {0};
        out.trigger = s[i].event == PING || s[i].event == ECHO_AND_PING;
        out.reading_ready =
            s[i].event == ECHO || s[i].event == TIMEOUT || s[i].event == ECHO_AND_PING;
        out.reading.echo = s[i].event != TIMEOUT;
        out.reading.servo_mdeg = s[i].servo_deg * 1000;
        out.reading.servo = fix_bam_from_mdeg(s[i].servo_deg * 1000);
        out.reading.echo_us = s[i].echo_us;
        mapper_tick(&mapper, &grid, &pose, &out);
    }
}

/* Asserts that a map holds exactly the listed cells, every other one untouched (0 for
 * counts, log-odds 0 for evidence). */
static void expect_exactly(const uint8_t *map, const cell_value_t *cells, size_t n)
{
    uint8_t want[SLAM_GRID_CELLS];
    memset(want, map == grid.om && grid.mode == OM_MODE_EVIDENCE ? (int)GRID_EVIDENCE_ZERO : 0,
           sizeof want);
    for (size_t i = 0; i < n; i++) {
        want[grid_index(&grid, (grid_cell_t){cells[i].a, cells[i].b})] = cells[i].value;
    }
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        if (map[i] != want[i]) {
            fail_msg("cell a=%u b=%u holds %u, expected %u", (unsigned)(i % SLAM_GRID_A),
                     (unsigned)(i / SLAM_GRID_A), map[i], want[i]);
        }
    }
}

/* The default grid: start (0, 0) at the centre of cell (80, 80), cells of 50 mm, so world
 * x lies in cell 80 + floor((x + 25 mm) / 50 mm). The sonar axis is 50 mm ahead of the
 * robot; 1749 µs of echo is 299 954 µm. */
static void test_scripted_run_hits_exactly_the_expected_cells(void **state)
{
    (void)state;
    static const script_tick_t script[] = {
        /* Ping straight ahead from the start, echo one tick later after moving 100 mm:
         * the obstacle is at x = 50 mm + 299.954 mm from the pose of the ping, in cell 87
         * (from the pose of the echo it would have been cell 89). */
        {0, 0, 0, PING, 90, 0},
        {100000, 0, 0, ECHO, 90, 1749},
        /* Facing +y, servo 180° looks along +x: axis at (0.1 m, 0.05 m), obstacle at
         * (0.4 m, 0.05 m): cell (88, 81). */
        {100000, 0, 90, PING, 180, 0},
        {100000, 0, 90, NOTHING, 0, 0},
        {100000, 0, 90, ECHO_AND_PING, 180, 1749},
        /* ... and the same reading again from that second ping: the cell counts 2. */
        {100000, 0, 90, ECHO, 180, 1749},
        /* Beyond rc (5831 µs = 1.000017 m), a timeout, too close (100 µs = 17 mm): nothing. */
        {-200000, 0, 180, PING, 90, 0},
        {-200000, 0, 180, ECHO, 90, 5831},
        {-200000, 0, 180, PING, 90, 0},
        {-200000, 0, 180, TIMEOUT, 90, 0},
        {-200000, 0, 180, PING, 90, 0},
        {-200000, 0, 180, ECHO, 90, 100},
        /* Facing -x from (-0.2 m, 0), servo 0° looks to the left of -x, along -y:
         * axis (-0.25 m, 0), obstacle (-0.25 m, -0.299954 m): cell (75, 74). */
        {-200000, 0, 180, PING, 0, 0},
        {-200000, 0, 180, ECHO, 0, 1749},
    };
    play(script, sizeof script / sizeof script[0]);

    static const cell_value_t om[] = {{87, 80, 1}, {88, 81, 2}, {75, 74, 1}};
    expect_exactly(grid.om, om, sizeof om / sizeof om[0]);
    assert_int_equal(mapper.hits, 4u);
    assert_int_equal(mapper.far, 1u);
    assert_int_equal(mapper.near, 1u);
    assert_int_equal(mapper.timeouts, 1u);
    assert_int_equal(mapper.outside, 0u);

    /* TM: one count a tick at the robot's cell; x = 100 mm is cell 82, -200 mm cell 76. */
    static const cell_value_t tm[] = {{80, 80, 1}, {82, 80, 5}, {76, 80, 8}};
    expect_exactly(grid.tm, tm, sizeof tm / sizeof tm[0]);
}

static void test_tm_counts_one_per_tick(void **state)
{
    (void)state;
    /* 5000 ticks scattered over many cells, none reaching TMmax: the sum of TM is the
     * number of ticks at every point. */
    for (uint32_t t = 0; t < 5000; t++) {
        odom_pose_t pose = {(int32_t)(t * 300u) - 750000, (int32_t)((t * 7919u) % 1000000u), 0u};
        sweep_out_t out = {0};
        mapper_tick(&mapper, &grid, &pose, &out);
        if (t % 500u == 0u || t == 4999u) {
            uint32_t sum = 0;
            uint8_t max = 0;
            for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
                sum += grid.tm[i];
                max = grid.tm[i] > max ? grid.tm[i] : max;
            }
            assert_int_equal(sum, t + 1u);
            assert_true(max < cfg.tm_max);
        }
    }
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(grid.om[i], 0);
    }
}

static void test_outside_points_are_counted_not_written(void **state)
{
    (void)state;
    /* From the grid's last column, a 0.9 m reading straight ahead leaves the grid. */
    int32_t x_edge = grid.origin_x_um + (int32_t)(SLAM_GRID_A * cfg.cell_um) - 1;
    odom_pose_t pose = {x_edge, 0, 0u};
    assert_int_equal(mapper_reading(&mapper, &grid, &pose, fix_bam_from_mdeg(90000), 900000u),
                     MAPPER_OUTSIDE);
    assert_int_equal(mapper.outside, 1u);
    assert_int_equal(grid.rejected, 1u);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(grid.om[i], 0);
    }
}

static int setup_evidence(void **state)
{
    (void)state;
    test_config_default(&cfg);
    assert_int_equal(cfg.om_mode, OM_MODE_EVIDENCE);
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    return 0;
}

/* The free-space evidence of one reading, cell by cell. From the start cell (80, 80) facing
 * +x the beam starts 50 mm ahead (cell 81): a 299 954 µm echo hits cell 87 (+4) and clears
 * cells 81..86 (up to 249 954 µm, one cell short) and the robot's cell 80 (-1 each). */
static void test_evidence_reading_clears_its_beam(void **state)
{
    (void)state;
    static const script_tick_t script[] = {
        {0, 0, 0, PING, 90, 0},
        {0, 0, 0, ECHO, 90, 1749},
    };
    play(script, sizeof script / sizeof script[0]);
    static const cell_value_t om[] = {
        {80, 80, 127}, {81, 80, 127}, {82, 80, 127}, {83, 80, 127},
        {84, 80, 127}, {85, 80, 127}, {86, 80, 127}, {87, 80, 132},
    };
    expect_exactly(grid.om, om, sizeof om / sizeof om[0]);
    assert_int_equal(mapper.cleared, 7u);
    assert_int_equal(grid_state(&grid, grid_index(&grid, (grid_cell_t){87, 80})), GRID_OCCUPIED);
    assert_int_equal(grid_state(&grid, grid_index(&grid, (grid_cell_t){84, 80})), GRID_FREE);
    assert_int_equal(grid_state(&grid, grid_index(&grid, (grid_cell_t){88, 80})), GRID_UNKNOWN);
}

/* The faces of walls, along the beam of the reading above (robot's cell 80, echo in 87).
 * An echo from a cell already held as a wall lowers the cell behind it (88) by om_miss, to
 * unknown at most and never to free, and leaves the one beyond (89) alone; an echo from 87
 * with a wall in 86, the cell just nearer, is `shadowed`, and mapper_free() maps no hit. */
static void test_evidence_faces(void **state)
{
    (void)state;
    odom_pose_t p = {0, 0, 0u};
    bam32_t ahead = fix_bam_from_mdeg(90000);
    uint32_t face = grid_index(&grid, (grid_cell_t){87, 80});
    uint32_t back = grid_index(&grid, (grid_cell_t){88, 80});
    uint32_t beyond = grid_index(&grid, (grid_cell_t){89, 80});
    grid.om[face] = 132u;
    grid.om[back] = 130u;
    grid.om[beyond] = 140u;
    for (int i = 0; i < 4; i++) {
        assert_int_equal(mapper_reading(&mapper, &grid, &p, ahead, 299954u), MAPPER_HIT);
        assert_false(mapper.shadowed);
    }
    assert_int_equal(grid.om[face], 148u);
    assert_int_equal(grid.om[back], GRID_EVIDENCE_ZERO); /* 130, 129, 128, 128 */
    assert_int_equal(grid_state(&grid, back), GRID_UNKNOWN);
    assert_int_equal(grid.om[beyond], 140u);

    setup_evidence(NULL);
    uint32_t front = grid_index(&grid, (grid_cell_t){86, 80});
    grid.om[front] = 140u;
    int32_t x;
    int32_t y;
    assert_int_equal(mapper_free(&mapper, &grid, &p, ahead, 299954u, &x, &y), MAPPER_HIT);
    assert_true(mapper.shadowed);
    assert_int_equal(grid.om[face], GRID_EVIDENCE_ZERO);
    assert_int_equal(grid.om[front], 139u); /* the beam still passed it */
    grid.om[front] = GRID_EVIDENCE_ZERO - 1u;
    assert_int_equal(mapper_free(&mapper, &grid, &p, ahead, 299954u, &x, &y), MAPPER_HIT);
    assert_false(mapper.shadowed);

    /* Hit counts (the paper's Eq. 6) know no faces. */
    setup(NULL);
    grid.om[face] = 3u;
    grid.om[back] = 5u;
    grid_om_behind(&grid, (grid_cell_t){88, 80});
    (void)mapper_reading(&mapper, &grid, &p, ahead, 299954u);
    assert_int_equal(grid.om[face], 4u);
    assert_int_equal(grid.om[back], 5u);
    assert_false(mapper.shadowed);
}

/* An echo beyond rc clears the last 0.5 m of the beam before rc and the robot's cell, and
 * marks nothing occupied; a timeout clears only the robot's cell; a reading clears and
 * marks at most 0.5 m / L + 3 cells, whatever its angle (and lowers one behind a face). */
static void test_evidence_far_and_timeout(void **state)
{
    (void)state;
    odom_pose_t p = {0, 0, 0u};
    assert_int_equal(mapper_reading(&mapper, &grid, &p, fix_bam_from_mdeg(90000), 2500000u),
                     MAPPER_FAR);
    /* The beam from x = 50 mm reaches rc at 1050 mm: cells 91..101 (from 550 mm), and the
     * robot's cell 80. */
    uint32_t lowered = 0;
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_true(grid.om[i] == GRID_EVIDENCE_ZERO || grid.om[i] == 127u);
        lowered += grid.om[i] != GRID_EVIDENCE_ZERO;
    }
    assert_int_equal(lowered, 12u);
    assert_int_equal(grid.om[grid_index(&grid, (grid_cell_t){80, 80})], 127);
    assert_int_equal(grid.om[grid_index(&grid, (grid_cell_t){90, 80})], GRID_EVIDENCE_ZERO);
    assert_int_equal(grid.om[grid_index(&grid, (grid_cell_t){91, 80})], 127);
    assert_int_equal(grid.om[grid_index(&grid, (grid_cell_t){101, 80})], 127);
    assert_int_equal(grid.om[grid_index(&grid, (grid_cell_t){102, 80})], GRID_EVIDENCE_ZERO);

    setup_evidence(NULL);
    mapper_timeout(&mapper, &grid, &p);
    assert_int_equal(mapper.timeouts, 1u);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i++) {
        assert_int_equal(grid.om[i],
                         i == grid_index(&grid, (grid_cell_t){80, 80}) ? 127u : GRID_EVIDENCE_ZERO);
    }

    uint32_t bound = 500000u / cfg.cell_um + 3u;
    for (int h = 0; h < 360; h += 7) {
        for (int s = 65; s <= 155; s += 18) {
            uint32_t before = mapper.cleared;
            odom_pose_t q = {h * 1234, -h * 777, fix_bam_from_mdeg(h * 1000)};
            (void)mapper_reading(&mapper, &grid, &q, fix_bam_from_mdeg(s * 1000), 999999u);
            assert_true(mapper.cleared - before + 1u <= bound);
            before = mapper.cleared;
            (void)mapper_reading(&mapper, &grid, &q, fix_bam_from_mdeg(s * 1000), 3000000u);
            assert_true(mapper.cleared - before <= bound);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_scripted_run_hits_exactly_the_expected_cells, setup),
        cmocka_unit_test_setup(test_tm_counts_one_per_tick, setup),
        cmocka_unit_test_setup(test_outside_points_are_counted_not_written, setup),
        cmocka_unit_test_setup(test_evidence_reading_clears_its_beam, setup_evidence),
        cmocka_unit_test_setup(test_evidence_far_and_timeout, setup_evidence),
        cmocka_unit_test_setup(test_evidence_faces, setup_evidence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
