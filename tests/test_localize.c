/* SPDX-License-Identifier: MIT */
/* Tests of the pose correction's behaviour on drives past known walls with drifting odometry,
 * and of how held-back hits enter OM (test_loc_kf.c tests its filter). */
#include <setjmp.h>
#include <stdarg.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "world_origin.h"
#include "localize/loc_filter.h"
#include "localize/loc_hold.h"
#include "localize/loc_match.h"
#include "localize/loc_walls.h"
#include "slam/error.h"
#include "slam/localize.h"
#include "slam/readings.h"
#include "test_rng.h"

#define PI 3.14159265358979323846

/* ---- drives past walls -------------------------------------------------------------------- */

static grid_t grid;
static mapper_t mapper;
static loc_t loc;
static readq_t queue;
static slam_config_t cfg;

/* The robot's queue and correction afresh, for cfg. */
static void loc_start(void)
{
    readq_init(&queue, &cfg);
    loc_init(&loc, &cfg);
}

static int setup(void **state)
{
    (void)state;
    test_config_default(&cfg);
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    loc_start();
    return 0;
}

/* A reading as the robot's tick posts it, adopting the correction published for the
 * reading before when the background loop is done with it. False: the queue was full. */
static bool post(const readq_reading_t *rd)
{
    readq_post_t out = readq_post(&queue, rd);
    if (out == READQ_CURRENT) {
        loc_adopt(&loc);
    }
    return out != READQ_DROPPED;
}

/* The queue drained as robot_idle() drains it. */
static void idle(void)
{
    readq_reading_t rd;
    while (readq_take(&queue, &rd)) {
        if (loc.on) {
            loc_reading(&loc, &mapper, &grid, &rd);
        } else {
            readq_map(&rd, &mapper, &grid);
        }
        readq_done(&queue);
    }
}

/* Walls drawn as strong obstacle evidence, as a map built earlier would hold them. */
static void paint_line(double x0, double y0, double x1, double y1)
{
    for (int k = 0; k <= 2000; k++) {
        double t = k / 2000.0;
        int32_t x = (int32_t)lround((x0 + (x1 - x0) * t) * 1e6);
        int32_t y = (int32_t)lround((y0 + (y1 - y0) * t) * 1e6);
        grid_cell_t c;
        if (grid_cell_of(&grid, x, y, &c) == SLAM_OK) {
            grid.om[grid_index(&grid, c)] = 255u;
        }
    }
}

typedef struct {
    double x0, y0, x1, y1;
} seg_t;

/* Distance along a ray to the nearest wall, or -1. */
static double ray(const seg_t *w, size_t n, double ox, double oy, double th)
{
    double best = -1.0;
    double dx = cos(th);
    double dy = sin(th);
    for (size_t i = 0; i < n; i++) {
        double ex = w[i].x1 - w[i].x0;
        double ey = w[i].y1 - w[i].y0;
        double den = dx * ey - dy * ex;
        if (fabs(den) < 1e-12) {
            continue;
        }
        double t = ((w[i].x0 - ox) * ey - (w[i].y0 - oy) * ex) / den;
        double u = ((w[i].x0 - ox) * dy - (w[i].y0 - oy) * dx) / den;
        if (t > 0.0 && u >= 0.0 && u <= 1.0 && (best < 0.0 || t < best)) {
            best = t;
        }
    }
    return best;
}

typedef struct {
    double x, y, th;    /* true pose */
    double ox, oy, oth; /* odometry's */
} drive_t;

/* Drives back and forth along a line at heading `heading` (rad, world) for `metres`,
 * with odometry whose heading drifts by `drift` rad per metre; every 12 mm (a reading's
 * spacing at 0.2 m/s) a reading at the sweep's next stop, mapped through the queue. The
 * robot turns round at each end of a 1.2 m leg. Returns the final poses. */
static drive_t drive(const seg_t *w, size_t nw, double x, double y, double heading, double metres,
                     double drift, unsigned idle_every)
{
    drive_t d = {x, y, heading, x, y, heading};
    const double step = 0.012;
    double leg = 0.0;
    unsigned k = 0;
    for (double s = 0.0; s < metres; s += step, k++) {
        /* Both frames move by the same wheel travel, odometry with its own heading. */
        d.x += step * cos(d.th);
        d.y += step * sin(d.th);
        d.ox += step * cos(d.oth);
        d.oy += step * sin(d.oth);
        d.oth -= drift * step;
        leg += step;
        if (leg >= 1.2) {
            leg = 0.0;
            d.th += PI;
            d.oth += PI;
        }
        /* The sweep: stops 65°..155° and back. */
        unsigned seq = k % 12u;
        unsigned stop = seq < 6u ? seq : 11u - seq;
        double servo = 65.0 + 18.0 * stop;
        double sx = d.x + 0.05 * cos(d.th);
        double sy = d.y + 0.05 * sin(d.th);
        double range = ray(w, nw, sx, sy, d.th + (90.0 - servo) * PI / 180.0);
        readq_reading_t rd = {
            .ping = {(int32_t)lround(d.ox * 1e6), (int32_t)lround(d.oy * 1e6),
                     (bam32_t)(int64_t)llround(d.oth / (2.0 * PI) * 4294967296.0)},
            .range_um = range > 0.0 && range < 3.5 ? (uint32_t)lround(range * 1e6) : 0u,
            .servo = fix_bam_from_mdeg((int32_t)lround(servo * 1000.0)),
            .echo = range > 0.0 && range < 3.5,
        };
        (void)post(&rd);
        if (k % idle_every == idle_every - 1u) {
            idle();
        }
    }
    idle();
    return d;
}

static void pose_error(const drive_t *d, double *pos_m, double *th_deg)
{
    odom_pose_t o = {(int32_t)lround(d->ox * 1e6), (int32_t)lround(d->oy * 1e6),
                     (bam32_t)(int64_t)llround(d->oth / (2.0 * PI) * 4294967296.0)};
    odom_pose_t m = loc_apply(&loc.filter.corr, &o);
    double th = (double)(int32_t)(m.heading -
                                  (bam32_t)(int64_t)llround(d->th / (2.0 * PI) * 4294967296.0)) /
                4294967296.0 * 360.0;
    *pos_m = hypot(m.x_um * 1e-6 - d->x, m.y_um * 1e-6 - d->y);
    *th_deg = th;
}

/* A corner of two known walls, odometry drifting 0.2° per metre for 12 m: the corrected
 * pose ends within 0.3° and 2 cm of the truth, where odometry alone is 2.4° off, and the
 * filter has learned a drift the right way round. */
static void test_corner_holds_the_heading(void **state)
{
    (void)state;
    const seg_t walls[2] = {{1.0, -2.0, 1.0, 0.8}, {-2.0, 0.8, 1.0, 0.8}};
    paint_line(1.0, -2.0, 1.0, 0.8);
    paint_line(-2.0, 0.8, 1.0, 0.8);
    drive_t d = drive(walls, 2, -0.6, 0.1, 30.0 * PI / 180.0, 12.0, 0.2 * PI / 180.0, 1u);
    double pos;
    double th;
    pose_error(&d, &pos, &th);
    print_message("corner: %u matches applied of %u, final error %.3f m, %.2f deg (odometry alone "
                  "%.2f deg), drift learned %d nrad/mm (true 3491)\n",
                  loc.match.applied, loc.match.tried, pos, th, 12.0 * 0.2,
                  (int)(loc.filter.kappa_prad_per_mm / 1000));
    assert_true(loc.match.applied > 60u);
    assert_true(fabs(th) < 0.3);
    assert_true(pos < 0.02);
    assert_true(loc.filter.kappa_prad_per_mm > 0);
    assert_int_equal(queue.dropped, 0u);
}

/* One wall only, odometry drifting: the heading and the distance across the wall are held,
 * while nothing pulls the pose along the wall (the correction does not slide on it). */
static void test_one_wall_never_slides_along_it(void **state)
{
    (void)state;
    const seg_t walls[1] = {{-3.0, 0.8, 3.0, 0.8}};
    paint_line(-3.0, 0.8, 3.0, 0.8);
    drive_t d = drive(walls, 1, -0.6, 0.2, 0.0, 8.0, 0.3 * PI / 180.0, 1u);
    double pos;
    double th;
    pose_error(&d, &pos, &th);
    odom_pose_t o = {(int32_t)lround(d.ox * 1e6), (int32_t)lround(d.oy * 1e6), 0u};
    odom_pose_t m = loc_apply(&loc.filter.corr, &o);
    double across = m.y_um * 1e-6 - d.y;
    double along_fix = (m.x_um - o.x_um) * 1e-6; /* what the correction moved along x */
    print_message("one wall: heading %.2f deg, across %.3f m, moved along %.3f m\n", th, across,
                  along_fix);
    assert_true(fabs(th) < 1.5); /* of 2.4° drifted: one wall fixes the heading only slowly */
    assert_true(fabs(across) < 0.03);
    assert_true(fabs(along_fix) < 0.005); /* nothing moved the pose along the wall */
}

/* The same readings give the same map and the same correction whenever the background
 * loop runs, as long as it keeps up (on an MCU it runs after every tick; here after every
 * reading, or every third). */
static void test_timing_changes_nothing(void **state)
{
    (void)state;
    const seg_t walls[2] = {{1.0, -2.0, 1.0, 0.8}, {-2.0, 0.8, 1.0, 0.8}};
    static uint8_t om_a[SLAM_GRID_CELLS];
    loc_corr_t ca;
    for (int run = 0; run < 2; run++) {
        setup(NULL);
        paint_line(1.0, -2.0, 1.0, 0.8);
        paint_line(-2.0, 0.8, 1.0, 0.8);
        (void)drive(walls, 2, -0.6, 0.1, 30.0 * PI / 180.0, 4.0, 0.5 * PI / 180.0,
                    run == 0 ? 1u : 3u);
        loc_flush(&loc, &mapper, &grid);
        if (run == 0) {
            memcpy(om_a, grid.om, sizeof om_a);
            ca = loc.filter.corr;
            assert_int_equal(queue.late, 0u);
        } else {
            assert_memory_equal(grid.om, om_a, sizeof om_a);
            assert_memory_equal(&loc.filter.corr, &ca, sizeof ca);
            assert_true(queue.late > 0u); /* the tick noticed, and kept its correction */
        }
    }
}

/* With localization off the readings still reach OM through the queue, exactly as the
 * mapper alone would map them, and the correction stays zero. */
static void test_off_maps_as_the_mapper(void **state)
{
    (void)state;
    cfg.localize = 0u;
    loc_start();
    assert_true(queue.deferred); /* OM_MODE_EVIDENCE: the rays are the background's work */
    static grid_t direct;
    mapper_t m2;
    grid_init(&direct, &cfg);
    mapper_init(&m2, &cfg);
    test_rng_t rng = {5u};
    for (int i = 0; i < 3000; i++) {
        readq_reading_t rd = {
            .ping = {test_rng_range(&rng, -500000, 500000), test_rng_range(&rng, -500000, 500000),
                     (bam32_t)test_rng_u64(&rng)},
            .range_um = (uint32_t)test_rng_range(&rng, 10000, 2000000),
            .servo = fix_bam_from_mdeg(test_rng_range(&rng, 65000, 155000)),
            .echo = test_rng_range(&rng, 0, 9) != 0,
        };
        assert_true(post(&rd));
        idle();
        if (rd.echo) {
            (void)mapper_reading(&m2, &direct, &rd.ping, rd.servo, rd.range_um);
        } else {
            mapper_timeout(&m2, &direct, &rd.ping);
        }
    }
    assert_memory_equal(grid.om, direct.om, sizeof direct.om);
    assert_int_equal(mapper.hits, m2.hits);
    assert_int_equal(loc.filter.corr.th, 0u);
    assert_int_equal(loc.filter.corr.tx_um, 0);
    assert_int_equal(loc.match.tried, 0u);
}

/* Odometry that jumps 10 m (only a corrupt log does that) between hits on a wall, with the
 * heading as uncertain as the filter lets it be (10°): the hits held back from before the
 * jump lie 10 m from where the robot now is, beyond the 8 m lever that keeps the filter's
 * products within 64 bits. They are not matched (without the bound five of these matches
 * turn the pose about them), and the hits since the jump, off the 8 m grid, find no wall:
 * every match is refused, the correction stays. A jump of a kilometre puts the hits
 * beyond what a held-back point reaches, and they are not held at all
 * (test_far_hits_are_not_held). */
static void test_a_jump_of_odometry_is_not_matched(void **state)
{
    (void)state;
    paint_line(-1.0, 0.8, 1.0, 0.8);
    for (unsigned i = 0; i < LOC_WINDOW + 4u * LOC_EVERY; i++) {
        bool jumped = i >= LOC_WINDOW - LOC_EVERY;
        if (i == LOC_WINDOW - LOC_EVERY) {
            loc.filter.cov.p[LKF_T][LKF_T] = LKF_VAR_TH_MAX;
        }
        /* Facing +x, the beam turned to the left (+y) onto the wall. */
        readq_reading_t rd = {
            .ping = {(int32_t)(i % 20u) * 50000 - 500000 + (jumped ? 10000000 : 0), 0, 0u},
            .range_um = 700000u,
            .servo = 0u,
            .echo = true};
        assert_true(post(&rd));
        idle();
    }
    assert_true(loc.match.tried > 0u);
    assert_int_equal(loc.match.applied, 0u);
    assert_int_equal(loc.filter.corr.th, 0u);
    assert_int_equal(loc.filter.corr.tx_um, 0);
    assert_int_equal(loc.filter.corr.ty_um, 0);
}

/* Where a ping from the origin facing +x, the beam turned to the left (+y), 700 mm long,
 * puts its hit. */
static void hit_of_the_origin(int32_t *hx, int32_t *hy)
{
    odom_pose_t at = {0, 0, 0u};
    sonar_obstacle(&mapper.sonar, &at, 0u, 700000u, hx, hy);
}

/* A hit enters OM only when LOC_HOLD more have come in, in its own cell: 0.6 mm inside a
 * cell's edge still lands in that cell (a held-back point is kept to 2^point_shift µm,
 * rounded: 1.024 mm for 50 mm cells, so within 0.512 mm). Nothing is matched: the map
 * around it is empty. */
static void test_hits_enter_om_after_the_hold(void **state)
{
    (void)state;
    assert_int_equal(loc.hold.point_shift, 10u); /* 512 cells · 50 mm = 25.6 m in 2^15 units */
    int32_t hx;
    int32_t hy;
    hit_of_the_origin(&hx, &hy);
    /* Pings whose hits lie 600 µm inside the lower x edge of a cell, every other cell. */
    int32_t edge = grid.origin_x_um + 100 * (int32_t)grid.cell_um;
    for (unsigned i = 0; i < LOC_HOLD + 5u; i++) {
        int32_t x = edge + (int32_t)(i % 20u) * 2 * (int32_t)grid.cell_um + 600 - hx;
        readq_reading_t rd = {.ping = {x, 0, 0u}, .range_um = 700000u, .servo = 0u, .echo = true};
        assert_true(post(&rd));
        idle();
        assert_int_equal(mapper.hits, i < LOC_HOLD ? 0u : i + 1u - LOC_HOLD);
    }
    for (unsigned k = 0; k < 5u; k++) {
        grid_cell_t c;
        int32_t x = edge + (int32_t)k * 2 * (int32_t)grid.cell_um;
        assert_int_equal(grid_cell_of(&grid, x + 600, hy, &c), SLAM_OK);
        assert_int_equal(grid_state(&grid, grid_index(&grid, c)), GRID_OCCUPIED);
        assert_int_equal(grid_cell_of(&grid, x - 600, hy, &c), SLAM_OK);
        assert_int_not_equal(grid_state(&grid, grid_index(&grid, c)), GRID_OCCUPIED);
    }
    assert_int_equal(loc.match.applied, 0u);
}

/* Half of a hit's log-odds step enters OM when it leaves the matched window (so that
 * exploration, which reads OM, knows the walls just seen), the rest when it leaves the
 * hold; it counts as one hit, then. The first hit lies in a cell of its own. */
static void test_half_a_hit_enters_early(void **state)
{
    (void)state;
    int32_t hx;
    int32_t hy;
    hit_of_the_origin(&hx, &hy);
    grid_cell_t first;
    assert_int_equal(grid_cell_of(&grid, hx, hy, &first), SLAM_OK);
    uint32_t k = grid_index(&grid, first);
    for (unsigned i = 0; i < LOC_HOLD + 1u; i++) {
        /* The first at x = 0, the others 1 m further along, in cells of their own. */
        readq_reading_t rd = {.ping = {i == 0u ? 0 : 1000000 + (int32_t)(i % 8u) * 100000, 0, 0u},
                              .range_um = 700000u,
                              .servo = 0u,
                              .echo = true};
        assert_true(post(&rd));
        idle();
        uint8_t want = i < LOC_WINDOW ? GRID_EVIDENCE_ZERO
                       : i < LOC_HOLD ? (uint8_t)(GRID_EVIDENCE_ZERO + grid.hit / 2u)
                                      : (uint8_t)(GRID_EVIDENCE_ZERO + grid.hit);
        assert_int_equal(grid.om[k], want);
        assert_int_equal(mapper.hits, i < LOC_HOLD ? 0u : 1u);
    }
}

/* A match sees OM without the halves of the hits it still holds back: the minute just seen
 * would hold the pose where it drew them. A robot that drives to and fro along a wall no map
 * holds yet: its window's hits lie on the cells of the halves, which exploration sees as
 * occupied, and no match finds a wall. */
static void test_a_match_does_not_see_the_halves(void **state)
{
    (void)state;
    int32_t hx;
    int32_t hy;
    hit_of_the_origin(&hx, &hy);
    for (unsigned i = 0; i < 200u; i++) {
        /* Along 1 m of the wall, 20 mm a reading, then back to its start. */
        readq_reading_t rd = {.ping = {(int32_t)(i % 50u) * 20000, 0, 0u},
                              .range_um = 700000u,
                              .servo = 0u,
                              .echo = true};
        assert_true(post(&rd));
        idle();
    }
    assert_true(loc.match.tried >= 30u);
    assert_int_equal(loc.match.last_points, 0u);
    assert_int_equal(loc.match.applied, 0u);
    assert_int_equal(mapper.hits, 0u); /* every hit still held */
    for (int32_t x = 0; x < 1000000; x += 50000) {
        grid_cell_t c;
        assert_int_equal(grid_cell_of(&grid, hx + x, hy, &c), SLAM_OK);
        assert_int_equal(grid_state(&grid, grid_index(&grid, c)), GRID_OCCUPIED);
    }
}

/* The far face of a thin wall: the map holds the wall's west face (x 1.00-1.05 m) as seen
 * from the room west of it; the robot, east of the wall, hears its east face at x 1.10 m.
 * Those hits lie a wall's thickness from the mapped face, with the wall's inside between,
 * never seen: no match uses them, nor when one beam has passed the cells between (a wall
 * the beam grazed). Had the beams cleared them (the face is where the map says, and the pose
 * is off), they would pull the pose onto it. */
static void test_the_far_face_of_a_thin_wall_is_not_matched(void **state)
{
    (void)state;
    for (int passes = 0; passes <= 2; passes++) {
        bool seen = passes == 2;
        grid_init(&grid, &cfg);
        mapper_init(&mapper, &cfg);
        loc_start();
        paint_line(1.025, -1.5, 1.025, 1.5);
        if (passes > 0) {
            for (double y = -1.5; y <= 1.5; y += 0.025) {
                grid_cell_t c;
                assert_int_equal(grid_cell_of(&grid, 1075000, (int32_t)lround(y * 1e6), &c),
                                 SLAM_OK);
                /* Beams passed through: one, or many (known free). */
                grid.om[grid_index(&grid, c)] = seen ? 1u : GRID_EVIDENCE_ZERO - cfg.om_miss;
            }
        }
        /* Facing west from x = 1.8 m, the beam starts 50 mm ahead: 648 mm ends at 1.102 m. */
        for (unsigned i = 0; i < LOC_WINDOW + 4u; i++) {
            int32_t y = -500000 + (int32_t)i * 15000;
            readq_reading_t rd = {.ping = {1800000, y, FIX_BAM_HALF},
                                  .range_um = 648000u,
                                  .servo = fix_bam_from_mdeg(90000),
                                  .echo = true};
            assert_true(post(&rd));
            idle();
        }
        assert_true(loc.match.tried >= 1u);
        if (seen) {
            assert_true(loc.match.last_points >= LOC_MIN_POINTS);
            assert_true(loc.match.applied >= 1u);
            print_message("seen: %u matches applied, correction x %d um\n", loc.match.applied,
                          loc.filter.corr.tx_um);
            assert_true(loc.filter.corr.tx_um < 0); /* pulled west, toward the mapped face */
        } else {
            assert_int_equal(loc.match.last_points, 0u);
            assert_int_equal(loc.match.applied, 0u);
        }
    }
}

/* A hit a kilometre off (a corrupt log) lies beyond what a held-back point reaches: it is
 * not held, and OM counts it outside the grid at once. */
static void test_far_hits_are_not_held(void **state)
{
    (void)state;
    readq_reading_t rd = {
        .ping = {1000000000, 0, 0u}, .range_um = 700000u, .servo = 0u, .echo = true};
    assert_true(post(&rd));
    idle();
    assert_int_equal(loc.hold.count, 0u);
    assert_int_equal(mapper.outside, 1u);
    assert_int_equal(mapper.hits, 0u);
    rd.ping.x_um = 0;
    assert_true(post(&rd));
    idle();
    assert_int_equal(loc.hold.count, 1u); /* one near the grid is */
}

/* A hit just behind a wall the map holds is matched but never mapped (it says the pose is
 * off, not that the wall is thicker); one on the wall's face is mapped, and with the
 * correction off both are, as the mapper alone maps them. */
static void test_shadowed_hit_is_not_mapped(void **state)
{
    (void)state;
    uint32_t face = grid_index(&grid, (grid_cell_t){87, 80});
    uint32_t back = grid_index(&grid, (grid_cell_t){88, 80});
    for (int on = 1; on >= 0; on--) {
        cfg.localize = (uint8_t)on;
        grid_init(&grid, &cfg);
        mapper_init(&mapper, &cfg);
        loc_start();
        grid.om[face] = 200u; /* a wall 350 mm ahead of the robot's cell centre */
        /* From (0, 0) facing +x the beam starts 50 mm ahead: 300 mm ends on the face (cell
         * 87), 350 mm just behind it (cell 88). */
        readq_reading_t on_face = {.ping = {0, 0, 0u},
                                   .range_um = 300000u,
                                   .servo = fix_bam_from_mdeg(90000),
                                   .echo = true};
        readq_reading_t behind = on_face;
        behind.range_um = 350000u;
        assert_true(post(&behind));
        assert_true(post(&on_face));
        idle();
        loc_flush(&loc, &mapper, &grid);
        assert_int_equal(grid.om[face], 203u); /* the far echo's beam passed it: -1, +4 */
        assert_int_equal(grid.om[back], on ? GRID_EVIDENCE_ZERO : GRID_EVIDENCE_ZERO + 4u - 1u);
        assert_int_equal(mapper.hits, on ? 1u : 2u);
    }
}

/* Two readings straight ahead of the robot facing +x, from (0, 0) and then (0, y2) mm (the
 * beam starts 50 mm ahead of the axle: a range of 200 mm is a hit 250 mm ahead), OM at the
 * second hit's cell set to om2 first unless it is 0: what is published for exploration. */
static int32_t ahead_of_two(int32_t y2_mm, uint32_t range2_mm, uint8_t om2)
{
    grid_init(&grid, &cfg);
    mapper_init(&mapper, &cfg);
    loc_start();
    grid_cell_t c;
    assert_int_equal(grid_cell_of(&grid, 50000 + (int32_t)range2_mm * 1000, y2_mm * 1000, &c),
                     SLAM_OK);
    if (om2 != 0u) {
        grid.om[grid_index(&grid, c)] = om2;
    }
    for (int i = 0; i < 2; i++) {
        readq_reading_t rd = {.ping = {0, i == 0 ? 0 : y2_mm * 1000, 0u},
                              .range_um = i == 0 ? 200000u : range2_mm * 1000u,
                              .servo = fix_bam_from_mdeg(90000),
                              .echo = true};
        assert_true(post(&rd));
        idle();
        if (i == 0) {
            assert_int_equal(loc.tick.pub_ahead[0], LOC_AHEAD_NONE); /* one cell: a ghost, maybe */
        }
    }
    return loc.tick.pub_ahead[0];
}

/* Exploration is told of the held-back hits, which OM does not hold yet, as of its map's
 * corridor: the nearest hit ahead in a second cell, within LOC_AHEAD_REACH_UM of the axle
 * and clearance_um to either side, none in a cell OM holds free by more than one beam's
 * pass. The tick adopts it with the correction. */
static void test_the_obstacle_ahead_among_held_hits(void **state)
{
    (void)state;
    /* Held-back points are kept to 1.024 mm (loc_point_t). */
    assert_in_range(ahead_of_two(60, 230, 0u), 279000, 281000); /* 280 mm, a cell to the left */
    assert_in_range(loc.tick.pub_ahead[1], 59000, 61000);
    assert_int_equal(loc.tick.ahead[0], LOC_AHEAD_NONE);
    readq_reading_t next = {.ping = {0, 0, 0u}, .echo = false};
    assert_true(post(&next));
    assert_int_equal(loc.tick.ahead[0], loc.tick.pub_ahead[0]);
    assert_int_equal(loc.tick.ahead[1], loc.tick.pub_ahead[1]);
    assert_int_equal(ahead_of_two(10, 210, 0u), LOC_AHEAD_NONE); /* the first hit's cell */
    assert_int_equal(ahead_of_two(60, 230, 1u), LOC_AHEAD_NONE); /* known free */
    assert_in_range(ahead_of_two(60, 230, GRID_EVIDENCE_ZERO - 1u), 279000, 281000); /* a pass */
    assert_int_equal(ahead_of_two(60, 320, 0u), LOC_AHEAD_NONE);  /* 370 mm ahead */
    assert_int_equal(ahead_of_two(300, 230, 0u), LOC_AHEAD_NONE); /* the first 300 mm aside */
    cfg.localize = 0u;
    assert_int_equal(ahead_of_two(60, 230, 0u), LOC_AHEAD_NONE); /* nothing held back */
}

/* The obstacle ahead as first written: every held-back hit of the window through the
 * correction, its cell, then the corridor. */
static void ahead_reference(const loc_hold_t *h, const grid_t *g, const loc_corr_t *corr,
                            const odom_pose_t *ping, int32_t pt[2])
{
    odom_pose_t at = loc_apply(corr, ping);
    q1_30_t c = fix_cos(at.heading);
    q1_30_t s = fix_sin(at.heading);
    int32_t near[2] = {INT32_MAX, INT32_MAX};
    int32_t near_pt[2][2] = {{LOC_AHEAD_NONE, 0}, {LOC_AHEAD_NONE, 0}};
    uint32_t k1 = UINT32_MAX;
    unsigned first = h->count > LOC_WINDOW ? h->count - LOC_WINDOW : 0u;
    for (unsigned i = first; i < h->count; i++) {
        unsigned slot = (h->first + i) % LOC_HOLD;
        if ((h->shadowed[slot / 32u] >> (slot % 32u)) & 1u) {
            continue;
        }
        int32_t x;
        int32_t y;
        uint32_t cell;
        loc_hold_point(h, g, corr, i, &x, &y);
        if (loc_known_free(g, x, y, &cell)) {
            continue;
        }
        int32_t dx = x - at.x_um;
        int32_t dy = y - at.y_um;
        int32_t ahead = (int32_t)(((int64_t)dx * c + (int64_t)dy * s) >> 30);
        int32_t side = (int32_t)(((int64_t)dy * c - (int64_t)dx * s) >> 30);
        if (ahead <= 0 || ahead >= LOC_AHEAD_REACH_UM || side <= -h->clear_um ||
            side >= h->clear_um || (cell == k1 ? ahead >= near[0] : ahead >= near[1])) {
            continue;
        }
        if (ahead < near[0]) {
            if (cell != k1) {
                near[1] = near[0];
                near_pt[1][0] = near_pt[0][0];
                near_pt[1][1] = near_pt[0][1];
            }
            k1 = cell;
            near[0] = ahead;
            near_pt[0][0] = x;
            near_pt[0][1] = y;
        } else {
            near[1] = ahead;
            near_pt[1][0] = x;
            near_pt[1][1] = y;
        }
    }
    pt[0] = near_pt[1][0];
    pt[1] = near_pt[1][1];
}

/* loc_hold_ahead() leaves most hits out before the correction and the map are asked
 * (far in the odometry frame, outside the corridor, behind the second nearest): the same
 * answer as asking them for every hit, on windows scattered about the corridor's edges,
 * under any correction and heading, corridor width and map. */
static void test_the_obstacle_ahead_skips_nothing_it_needs(void **state)
{
    (void)state;
    test_rng_t rng = {31u};
    unsigned found = 0;
    for (int trial = 0; trial < 6000; trial++) {
        cfg.clearance_um = 60000u + (uint32_t)(test_rng_u64(&rng) % 300000u);
        grid_init(&grid, &cfg);
        loc_start();
        for (uint32_t k = 0; k < SLAM_GRID_CELLS; k += 1u + (uint32_t)(test_rng_u64(&rng) % 3u)) {
            grid.om[k] = (uint8_t)test_rng_u64(&rng);
        }
        bam32_t th = (bam32_t)test_rng_u64(&rng);
        loc_corr_t corr = {(int32_t)(test_rng_u64(&rng) % 1000001u) - 500000,
                           (int32_t)(test_rng_u64(&rng) % 1000001u) - 500000, th, fix_cos(th),
                           fix_sin(th)};
        odom_pose_t ping = {(int32_t)(test_rng_u64(&rng) % 4000001u) - 2000000,
                            (int32_t)(test_rng_u64(&rng) % 4000001u) - 2000000,
                            (bam32_t)test_rng_u64(&rng)};
        loc_hold_t *h = &loc.hold;
        h->first = (uint16_t)(test_rng_u64(&rng) % LOC_HOLD);
        /* Half the windows of a few hits, so that one at the corridor's far corners decides. */
        h->count = (uint16_t)(1u + test_rng_u64(&rng) % (trial % 2 ? 8u : LOC_HOLD));
        double hc = cos(ping.heading * (2.0 * PI / 4294967296.0));
        double hs = sin(ping.heading * (2.0 * PI / 4294967296.0));
        for (unsigned i = 0; i < LOC_HOLD; i++) {
            /* About the corridor, in the odometry frame: ahead -0.1 .. 0.7 m, ±0.5 m aside,
             * or within 3 mm of a far corner. */
            double a = (double)(test_rng_u64(&rng) % 800001u) - 100000.0;
            double sd = (double)(test_rng_u64(&rng) % 1000001u) - 500000.0;
            if (test_rng_u64(&rng) % 2u) {
                a = LOC_AHEAD_REACH_UM + (double)(test_rng_u64(&rng) % 6001u) - 3000.0;
                sd = (test_rng_u64(&rng) % 2u ? 1.0 : -1.0) *
                     ((double)cfg.clearance_um + (double)(test_rng_u64(&rng) % 6001u) - 3000.0);
            }
            double x = ping.x_um + a * hc - sd * hs - grid.origin_x_um;
            double y = ping.y_um + a * hs + sd * hc - grid.origin_y_um;
            h->win[i] = (loc_point_t){(int16_t)lround(x / (1 << h->point_shift)),
                                      (int16_t)lround(y / (1 << h->point_shift))};
        }
        for (unsigned w = 0; w < LOC_HOLD / 32u; w++) {
            h->shadowed[w] = (uint32_t)(test_rng_u64(&rng) & test_rng_u64(&rng));
        }
        int32_t want[2];
        int32_t got[2];
        ahead_reference(h, &grid, &corr, &ping, want);
        loc_hold_ahead(h, &grid, &corr, &ping, got);
        assert_int_equal(got[0], want[0]);
        assert_int_equal(got[1], want[1]);
        found += want[0] != LOC_AHEAD_NONE;
    }
    assert_true(found > 1000u); /* the corridor was often found, not always empty */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_corner_holds_the_heading, setup),
        cmocka_unit_test_setup(test_one_wall_never_slides_along_it, setup),
        cmocka_unit_test_setup(test_timing_changes_nothing, setup),
        cmocka_unit_test_setup(test_off_maps_as_the_mapper, setup),
        cmocka_unit_test_setup(test_shadowed_hit_is_not_mapped, setup),
        cmocka_unit_test_setup(test_a_jump_of_odometry_is_not_matched, setup),
        cmocka_unit_test_setup(test_hits_enter_om_after_the_hold, setup),
        cmocka_unit_test_setup(test_far_hits_are_not_held, setup),
        cmocka_unit_test_setup(test_half_a_hit_enters_early, setup),
        cmocka_unit_test_setup(test_a_match_does_not_see_the_halves, setup),
        cmocka_unit_test_setup(test_the_far_face_of_a_thin_wall_is_not_matched, setup),
        cmocka_unit_test_setup(test_the_obstacle_ahead_among_held_hits, setup),
        cmocka_unit_test_setup(test_the_obstacle_ahead_skips_nothing_it_needs, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
