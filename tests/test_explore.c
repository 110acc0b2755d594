/* SPDX-License-Identifier: MIT */
/* Tests of exploration: the memory, the map's corridor, looking, avoiding, slowing down,
 * backing off along the trail, TM-guided headings, the square, determinism. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "explore_world.h"
#include "slam/error.h"

/* How far apart two binary angles are, either way round. */
static uint32_t angle_off(bam32_t a, bam32_t b)
{
    int64_t d = fix_bam_diff(a, b);
    return (uint32_t)(d < 0 ? -d : d);
}

/* Two passes of the sweep that hear the room's walls 3 m off at every stop (beyond the
 * confidence radius: nothing enters the memory): the robot hears well, and nothing is
 * near. */
static void full_clear_sweep(void)
{
    for (int s = 0; s < 12; s++) {
        tick(s < 6 ? s : 11 - s, 3000.0);
        quiet_tick();
    }
}

/* Ticks without readings until the state leaves `s` (at most n); returns the ticks. */
static unsigned wait_while(uint8_t s, unsigned n)
{
    unsigned t = 0;
    while (ex.machine.state == s && t++ < n) {
        quiet_tick();
    }
    return t;
}

static void test_off_stands_still(void **state)
{
    (void)state;
    setup_mode(EXPLORE_OFF);
    for (int t = 0; t < 1000; t++) {
        tick(t % 6, 100.0);
        assert_int_equal(target[0], 0);
        assert_int_equal(target[1], 0);
    }
}

static void test_look_then_forward(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    for (int t = 0; t < 50; t++) {
        quiet_tick(); /* no readings yet: stand and look */
        assert_int_equal(target[0], 0);
        assert_int_equal(ex.machine.state, EXPLORE_LOOK);
    }
    full_clear_sweep();
    /* Then a pass over the memory and the map that began after the sweep, a slice a tick. */
    unsigned t = wait_while(EXPLORE_LOOK, 100u);
    assert_true(t >= 2u && t <= 20u);
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    quiet_tick();
    assert_int_equal(target[0], 200);
    assert_int_equal(target[1], 200);
}

/* A tick that completes a reading belongs to the map update: the exploration keeps the
 * wheels as they were and takes the reading's point into its memory in the next tick. */
static void test_reading_ticks_only_note(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    quiet_tick();
    assert_int_equal(target[0], 200);
    uint8_t slot = ex.memory.next_point;
    explore_t before = ex;
    tick(2, 200.0); /* 0.2 m, 11° right: in the way */
    assert_int_equal(target[0], 200);
    assert_int_equal(target[1], 200);
    assert_int_equal(ex.memory.pt_seen[slot], before.memory.pt_seen[slot]);
    assert_int_equal(ex.machine.state, before.machine.state);
    quiet_tick();
    assert_int_equal(ex.memory.pt_seen[slot], ex.machine.now);
    assert_int_equal(ex.memory.next_point, (slot + 1u) % EXPLORE_POINTS);
}

static void test_obstacle_ahead_turns_away(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    /* Servo 101°: 11° to the right, 0.2 m from the sonar. */
    tick(2, 200.0);
    wait_while(EXPLORE_FORWARD, 40u);
    assert_int_equal(ex.machine.state, EXPLORE_TURN);
    assert_int_equal(ex.count.avoidances, 1u);
    int32_t turn = fix_bam_diff(ex.moves.target_heading, pose().heading);
    /* The paper's way: away from the right, to the left, by 90..180°. */
    assert_true(turn >= (int32_t)fix_bam_from_mdeg(89000) && turn <= INT32_MAX);
    quiet_tick();
    assert_true(target[0] < 0 && target[1] > 0); /* counter-clockwise */
    wait_while(EXPLORE_TURN, 2000u);
    assert_int_equal(ex.machine.state, EXPLORE_LOOK);
    assert_true(angle_off(ex.moves.target_heading, pose().heading) < fix_bam_from_mdeg(3000));
    /* The obstacle is behind now: looking finds the way clear. */
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
}

/* The robot slows down as the nearest point ahead comes closer: cruise from 0.7 m ahead
 * of the sonar, slower nearer, and it stops and turns at 0.3 m. */
static void test_slows_down_near_an_obstacle(void **state)
{
    (void)state;
    static const struct {
        double range_mm;
        int32_t lo, hi;
    } cases[] = {{900.0, 200, 200}, {600.0, 140, 170}, {400.0, 60, 110}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        setup_mode(EXPLORE_RANDOM);
        full_clear_sweep();
        wait_while(EXPLORE_LOOK, 100u);
        tick(1, cases[c].range_mm); /* 7° to the left */
        for (int t = 0; t < 20; t++) {
            quiet_tick();
        }
        assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
        printf("point %.0f mm ahead: %d mm/s\n", cases[c].range_mm, target[0]);
        assert_true(target[0] >= cases[c].lo && target[0] <= cases[c].hi);
        assert_int_equal(target[0], target[1]);
    }
}

/* A sonar that hears little (pings lost, faces at grazing angles) may not have heard what
 * is ahead: the robot drives no faster than the share of the last sweep it heard, down to
 * a crawl, and at full speed again once it hears. */
static void test_hears_little_slows_down(void **state)
{
    (void)state;
    static const struct {
        unsigned lost;
        int32_t speed;
    } cases[] = {{4, 200}, {6, 165}, {12, 60}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        setup_mode(EXPLORE_RANDOM);
        full_clear_sweep();
        wait_while(EXPLORE_LOOK, 100u);
        for (unsigned k = 0; k < cases[c].lost; k++) {
            tick((int)(k % 6u), EW_TIMEOUT); /* no echo */
            for (int t = 0; t < 5; t++) {
                quiet_tick();
            }
        }
        printf("%u of the last 12 pings lost: %d mm/s\n", cases[c].lost, target[0]);
        assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
        assert_int_equal(target[0], cases[c].speed);
        assert_int_equal(target[1], cases[c].speed);
    }
    full_clear_sweep();
    quiet_tick();
    assert_int_equal(target[0], 200);
}

static void test_corridor_and_memory(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    odom_pose_t p = pose();
    /* Servo 155°: 65° to the right; 0.3 m away the point is 0.13 m ahead of the sonar
     * but 0.27 m to the side: outside the 0.13 m corridor. */
    tick(5, 300.0);
    quiet_tick();
    assert_false(explore_blocked(&ex, &p));
    /* Servo 83°: 7° to the left, 0.25 m: ahead and inside. */
    tick(1, 250.0);
    quiet_tick();
    assert_true(explore_blocked(&ex, &p));
    /* Seen from a pose facing the other way, it is behind: no block. */
    odom_pose_t back = {p.x_um, p.y_um, p.heading + FIX_BAM_HALF};
    assert_false(explore_blocked(&ex, &back));
    /* Beyond the avoidance distance it does not block. */
    odom_pose_t away = {p.x_um - 200000, p.y_um, p.heading};
    assert_false(explore_blocked(&ex, &away));
    /* A point is forgotten after EXPLORE_MEMORY_TICKS... */
    ex.machine.now += EXPLORE_MEMORY_TICKS - 1u;
    assert_true(explore_blocked(&ex, &p));
    ex.machine.now += 2u;
    assert_false(explore_blocked(&ex, &p));
    /* ...or when EXPLORE_POINTS newer points have taken its place. */
    tick(1, 250.0);
    quiet_tick();
    assert_true(explore_blocked(&ex, &p));
    for (unsigned i = 0; i < EXPLORE_POINTS - 1u; i++) {
        tick(5, 300.0);
        quiet_tick();
    }
    assert_true(explore_blocked(&ex, &p));
    tick(5, 300.0);
    quiet_tick();
    assert_false(explore_blocked(&ex, &p));
    /* The point is the reading's own, taken in its tick: the background loop may map an
     * older reading (and change the mapper's last outcome) before the next tick. */
    tick(1, 250.0);
    mapper.last = MAPPER_TIMEOUT;
    mapper.last_x_um = p.x_um - 1000000;
    quiet_tick();
    assert_true(explore_blocked(&ex, &p));
}

/* Marks the cell of a point (m) in OM. */
static void om_at(double x_m, double y_m, uint8_t om)
{
    grid_cell_t c;
    assert_int_equal(
        grid_cell_of(&grid, (int32_t)lround(x_m * 1e6), (int32_t)lround(y_m * 1e6), &c), SLAM_OK);
    grid.om[grid_index(&grid, c)] = om;
}

/* The corridor ahead is read on the map too (what the sonar cannot see now, such as a
 * wall converging from the blind left side, it may have mapped before): two occupied
 * cells 0.15 m ahead stop the robot; a lone one does not (a ghost echo) unless it was hit
 * twice on balance (the end of a thin screen, seen end-on, echoes no more), nor do cells
 * beyond the map's reach. An obstacle that localization holds back from OM counts as they
 * do. */
static void test_map_corridor(void **state)
{
    (void)state;
    /* Cells hit once (a ghost, perhaps) or twice on balance (no ghost); or none, and a hit
     * at (x1, y1) that localization holds back from OM tells it (explore_step()'s held). */
    static const struct {
        double x1, y1, x2, y2;
        unsigned hits;
        bool stops;
    } cases[] = {
        {0.15, 0.0, 0.15, 0.05, 1, true},  /* two cells across the way */
        {0.10, 0.1, 0.15, 0.1, 1, true},   /* two along its left edge */
        {0.15, 0.0, 0.15, 0.0, 1, false},  /* one cell */
        {0.15, 0.0, 0.15, 0.0, 2, true},   /* one cell, but seen twice */
        {0.60, 0.0, 0.60, 0.05, 2, false}, /* beyond 0.25 m */
        {0.15, 0.2, 0.15, 0.25, 2, false}, /* beside the corridor */
        {0.15, 0.0, 0.15, 0.0, 0, true},   /* held back: the robot keeps clear of it */
        {0.15, 0.2, 0.15, 0.2, 0, false},  /* held back, beside the corridor */
        {0.60, 0.0, 0.60, 0.0, 0, false},  /* held back, beyond 0.25 m */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        setup_mode(EXPLORE_RANDOM);
        full_clear_sweep();
        wait_while(EXPLORE_LOOK, 100u);
        assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
        px = py = 0.0;
        uint8_t om = (uint8_t)(GRID_EVIDENCE_ZERO + cases[c].hits * grid.hit);
        om_at(cases[c].x1, cases[c].y1, om);
        om_at(cases[c].x2, cases[c].y2, om);
        world_held[0] = cases[c].hits == 0u ? (int32_t)(cases[c].x1 * 1e6) : LOC_AHEAD_NONE;
        world_held[1] = (int32_t)(cases[c].y1 * 1e6);
        for (int t = 0; t < 10; t++) {
            quiet_tick();
            px = 0.0; /* stand at the origin for the test */
        }
        printf("case %zu: state %u\n", c, ex.machine.state);
        assert_int_equal(ex.machine.state == EXPLORE_TURN, cases[c].stops);
    }
}

/* Random mode, past its first look with nothing seen: driving on, then east to x_um. */
static void drive_to(double x_um)
{
    setup_mode(EXPLORE_RANDOM);
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    while (px < x_um) {
        quiet_tick();
    }
}

/* A stall in one tick; then ticks without readings while the robot stands (at most n). */
static void stall_once(void)
{
    stalled = true;
    quiet_tick();
    stalled = false;
}

static unsigned stand_out(unsigned n)
{
    unsigned t = 0;
    while (ex.machine.state == EXPLORE_HOLD && t++ < n) {
        quiet_tick();
    }
    return t;
}

/* Wheels that stall while driving (something the sonar missed): stand a while, then back
 * off along the path that brought the robot in, newest trail position first, then turn
 * away. The square, an odometry experiment, ignores stalls. */
static void test_stall_backs_off_along_the_trail(void **state)
{
    (void)state;
    /* 0.3 m east, then the robot is turned 90° (as by a turn) and drives 0.1 m north. */
    drive_to(300000.0);
    pth = EW_PI / 2.0;
    while (py < 100000.0) {
        quiet_tick();
    }
    double sx = px;
    double sy = py;
    stall_once();
    /* It stands a while first (the wheels at rest), then backs off. */
    assert_int_equal(ex.machine.state, EXPLORE_HOLD);
    assert_int_equal(ex.count.stalls, 1u);
    quiet_tick();
    assert_int_equal(target[0], 0);
    assert_int_equal(target[1], 0);
    unsigned held = stand_out(1000u) + 1u;
    printf("stood %u ticks\n", held);
    assert_true(held >= 100u && held < 1000u);
    assert_int_equal(ex.machine.state, EXPLORE_BACK);
    unsigned t = 0;
    double worst = 0.0;
    while (ex.machine.state == EXPLORE_BACK && t++ < 3000u) {
        quiet_tick();
        /* Never off the way in: within 25 mm of the L-shaped path, (0, 0) to (sx, 0) to
         * (sx, sy). */
        double a = hypot(px - (px < 0.0 ? 0.0 : (px > sx ? sx : px)), py);
        double b = hypot(px - sx, py - (py < 0.0 ? 0.0 : (py > sy ? sy : py)));
        double off = a < b ? a : b;
        worst = off > worst ? off : worst;
    }
    printf("backed off to (%.0f, %.0f) µm, at most %.1f mm off the path\n", px, py, worst / 1000.0);
    assert_int_equal(ex.machine.state, EXPLORE_TURN);
    assert_true(worst < 25000.0);
    assert_true(hypot(px - sx, py - sy) >= EXPLORE_BACK_UM - 1000.0);
    assert_true(px < sx); /* round the corner, along the first leg */

    setup_mode(EXPLORE_SQUARE);
    stalled = true;
    quiet_tick();
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    assert_int_equal(ex.count.stalls, 0u);
}

/* One wheel stalled while the other turned: nothing touched (that stops both), a wheel or
 * its encoder stopped. The robot stands, remembers no obstacle, then looks: backing off on
 * a count that may be dead would drive it blind. A stall while backing off stands again
 * and then backs off on, a few times at most. */
static void test_one_wheel_stall_stands_and_looks(void **state)
{
    (void)state;
    drive_to(200000.0);
    double sx = px;
    uint8_t next = ex.memory.next_point;
    ex.moves.one_wheel = true;
    stall_once();
    ex.moves.one_wheel = false;
    assert_int_equal(ex.machine.state, EXPLORE_HOLD);
    assert_int_equal(ex.memory.next_point, next); /* no obstacle remembered */
    stand_out(1000u);
    assert_int_equal(ex.machine.state, EXPLORE_LOOK);
    assert_true(fabs(px - sx) < 1.0); /* it never moved */

    /* Both wheels: back off; stalled again while backing, stand again, then back on. */
    for (unsigned t = 0; ex.machine.state != EXPLORE_FORWARD && t < 3000u; t++) {
        tick(t % 6u == 0u ? (int)(t / 6u % 6u) : 0, t % 6u == 0u ? EW_TIMEOUT : EW_NO_READING);
    }
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    while (px < sx + 100000.0) {
        quiet_tick();
    }
    stall_once();
    assert_int_equal(ex.machine.state, EXPLORE_HOLD);
    stand_out(1000u);
    assert_int_equal(ex.machine.state, EXPLORE_BACK);
    quiet_tick();
    stall_once();
    assert_int_equal(ex.machine.state, EXPLORE_HOLD);
    stand_out(1000u);
    assert_int_equal(ex.machine.state, EXPLORE_BACK);
    assert_int_equal(ex.count.stalls, 3u);
}

/* No echo from any stop for a second (an echo line stuck high, pings lost): the robot
 * stands, up to three seconds, and drives on at once when an echo comes back, or after
 * that (open space beyond the sonar's reach is silent too). */
static void test_deaf_robot_stands(void **state)
{
    (void)state;
    setup_mode(EXPLORE_RANDOM);
    tick(2, 3000.0); /* one echo, far ahead */
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    assert_int_equal(ex.machine.state, EXPLORE_FORWARD);
    unsigned moving = 0;
    unsigned still = 0;
    for (unsigned t = 0; t < 600u; t++) {
        tick(t % 6u == 0u ? (int)(t / 6u % 6u) : 0, t % 6u == 0u ? EW_TIMEOUT : EW_NO_READING);
        if (t < 80u) {
            moving += target[0] > 0 && target[1] > 0;
        } else if (t >= 120u && t < 380u) {
            still += target[0] == 0 && target[1] == 0;
        }
    }
    printf("deaf: moving %u of the first 80 ticks, still %u of 260 after a second\n", moving,
           still);
    assert_true(moving > 60u);
    assert_int_equal(still, 260u);
    assert_true(target[0] > 0 && target[1] > 0); /* on again after three seconds */
    /* Deaf again after an echo: stands again, and an echo ends it at once. */
    tick(2, 3000.0);
    for (unsigned t = 0; t < 150u; t++) {
        quiet_tick();
    }
    assert_true(target[0] == 0 && target[1] == 0);
    tick(2, 3000.0);
    quiet_tick();
    quiet_tick();
    assert_true(target[0] > 0 && target[1] > 0);
}

/* Marks the cells along a heading from the origin, from_m .. to_m. */
static void paint_ray(double deg, uint8_t *map, uint8_t value, double from_m, double to_m)
{
    for (double r = from_m; r <= to_m; r += 0.01) {
        grid_cell_t c;
        int32_t x = (int32_t)lround(r * 1e6 * cos(deg * EW_PI / 180.0));
        int32_t y = (int32_t)lround(r * 1e6 * sin(deg * EW_PI / 180.0));
        if (grid_cell_of(&grid, x, y, &c) == SLAM_OK) {
            map[grid_index(&grid, c)] = value;
        }
    }
}

static void decide_all(void)
{
    full_clear_sweep();
    wait_while(EXPLORE_LOOK, 100u);
    assert_int_equal(ex.machine.state, EXPLORE_DECIDE);
    unsigned t = wait_while(EXPLORE_DECIDE, 400u);
    printf("TM decision: %u ticks\n", t);
    assert_true(t <= 200u); /* standing still two seconds at most */
    assert_int_equal(ex.machine.state, EXPLORE_TURN);
}

/* TM mode in an arena visited everywhere but two ways, 90° (visits v90 along it) and
 * 180° (v180); the heading decided is returned. */
static bam32_t tm_decides(uint8_t v90, uint8_t v180, bool wall_at_90)
{
    setup_mode(EXPLORE_TM);
    memset(grid.tm, 30, sizeof grid.tm);
    paint_ray(90.0, grid.tm, v90, 0.03, 1.2);
    paint_ray(180.0, grid.tm, v180, 0.03, 1.2);
    if (v90 != 0u) {
        paint_ray(90.0, grid.om, ew_om_free(), 0.03, 1.2); /* driven along: known free */
    }
    if (wall_at_90) {
        paint_ray(90.0, grid.om, ew_om_occupied(), 0.28, 0.32);
    }
    decide_all();
    return ex.moves.target_heading;
}

static void test_tm_mode_heads_for_the_least_visited(void **state)
{
    (void)state;
    bam32_t h = tm_decides(0u, 5u, false);
    assert_true(angle_off(h, FIX_BAM_QUARTER) < fix_bam_from_mdeg(1000));
    /* An occupied cell (grid_state()) 0.3 m along 90° makes that way the worst. */
    h = tm_decides(0u, 5u, true);
    assert_true(angle_off(h, FIX_BAM_HALF) < fix_bam_from_mdeg(1000));
    /* Among unvisited ways, the one into the unknown beats the known-free one (driven
     * once along 90°). */
    h = tm_decides(1u, 0u, false);
    assert_true(angle_off(h, FIX_BAM_HALF) < fix_bam_from_mdeg(1000));
}

/* TM mode, something ahead: the new way is straight on or up to 150° to the left, so what
 * was ahead ends on the right, where the sweep sees it. */
static void test_tm_avoidance_turns_left(void **state)
{
    (void)state;
    for (uint32_t seed = 1; seed <= 8u; seed++) {
        setup_mode(EXPLORE_TM);
        cfg.explore_seed = seed;
        explore_init(&ex, &cfg);
        memset(grid.tm, 30, sizeof grid.tm);
        paint_ray(-90.0, grid.tm, 0u, 0.03, 1.2); /* the least visited way is to the right */
        for (int s = 0; s < 6; s++) {
            tick(s, s == 2 ? 200.0 : EW_TIMEOUT); /* and something is ahead */
            quiet_tick();
        }
        wait_while(EXPLORE_LOOK, 100u);
        assert_int_equal(ex.machine.state, EXPLORE_DECIDE);
        wait_while(EXPLORE_DECIDE, 400u);
        assert_int_equal(ex.machine.state, EXPLORE_TURN);
        int32_t turn = fix_bam_diff(ex.moves.target_heading, pose().heading);
        assert_true(turn > 0 && turn <= (int32_t)fix_bam_from_mdeg(150500));
    }
}

static void test_square_returns_to_the_start(void **state)
{
    (void)state;
    setup_mode(EXPLORE_SQUARE);
    int t = 0;
    while (ex.machine.state != EXPLORE_STOP && t++ < 20000) {
        tick(t % 6, t % 6 == 0 ? 100.0 : EW_NO_READING); /* readings do not matter to the square */
    }
    assert_int_equal(ex.machine.state, EXPLORE_STOP);
    assert_int_equal(ex.count.turns, 3u);
    /* An ideal robot ends near where it began: each turn stops within 1° of its corner
     * (17 mm off over a 1 m leg), each leg within a tick's travel (2 mm). */
    printf("square: ends %.1f mm from the start\n", hypot(px, py) / 1000.0);
    assert_true(hypot(px, py) < 3.0 * 17500.0 + 4.0 * 2000.0);
    assert_true(fabs(remainder(pth - 1.5 * EW_PI, 2.0 * EW_PI)) < EW_PI / 180.0); /* facing -y */
    quiet_tick();
    assert_int_equal(target[0], 0);
    assert_int_equal(target[1], 0);
}

/* The random exploration in a square box of walls 1 m from the start: returns a
 * fingerprint of its turns, and checks that it never came near the walls. */
static uint64_t random_run(uint32_t seed)
{
    setup_mode(EXPLORE_RANDOM);
    cfg.explore_seed = seed;
    explore_init(&ex, &cfg);
    add_wall(-1.0, -1.0, 1.0, -1.0);
    add_wall(1.0, -1.0, 1.0, 1.0);
    add_wall(1.0, 1.0, -1.0, 1.0);
    add_wall(-1.0, 1.0, -1.0, -1.0);
    uint64_t h = 1469598103934665603ull;
    double closest = HUGE_VAL;
    for (int t = 0; t < 30000; t++) {
        uint8_t before = ex.machine.state;
        world_tick();
        if (ex.machine.state == EXPLORE_TURN && before != EXPLORE_TURN) {
            h = (h ^ ex.moves.target_heading) * 1099511628211ull;
        }
        double c = clearance();
        closest = c < closest ? c : closest;
    }
    printf("seed %u: %u turns, closest %.0f mm\n", seed, ex.count.turns, closest / 1000.0);
    assert_true(ex.count.turns > 10u);
    assert_true(closest > 90000.0 + 30000.0); /* the body (90 mm) kept 30 mm clear */
    return h;
}

static void test_random_is_deterministic_for_a_seed(void **state)
{
    (void)state;
    uint64_t a = random_run(7u);
    uint64_t b = random_run(7u);
    uint64_t c = random_run(8u);
    assert_true(a == b);
    assert_true(a != c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_off_stands_still),
        cmocka_unit_test(test_look_then_forward),
        cmocka_unit_test(test_reading_ticks_only_note),
        cmocka_unit_test(test_obstacle_ahead_turns_away),
        cmocka_unit_test(test_slows_down_near_an_obstacle),
        cmocka_unit_test(test_hears_little_slows_down),
        cmocka_unit_test(test_corridor_and_memory),
        cmocka_unit_test(test_map_corridor),
        cmocka_unit_test(test_stall_backs_off_along_the_trail),
        cmocka_unit_test(test_one_wheel_stall_stands_and_looks),
        cmocka_unit_test(test_deaf_robot_stands),
        cmocka_unit_test(test_tm_mode_heads_for_the_least_visited),
        cmocka_unit_test(test_tm_avoidance_turns_left),
        cmocka_unit_test(test_square_returns_to_the_start),
        cmocka_unit_test(test_random_is_deterministic_for_a_seed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
