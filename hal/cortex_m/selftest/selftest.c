/* SPDX-License-Identifier: MIT */
/* The self-test run and its report, the same code on the emulated MCU and on the host. */
#include "selftest.h"

#include "hal/hal.h"
#include "hal_replay.h"
#include "slam/error.h"
#include "text.h"

/* GCC's noipa: no inlining, cloning or interprocedural register allocation, so that every
 * caller sees the same body; clang has no such attribute, and noinline is its nearest. */
#if defined(__clang__)
#define SELFTEST_OPAQUE __attribute__((noinline))
#else
#define SELFTEST_OPAQUE __attribute__((noipa))
#endif

#define CELLS_PER_LINE 64u
#define COSTS_PER_LINE 16u

/* An empty function, measured the same way as robot_tick() to learn the overhead. */
SELFTEST_OPAQUE static void selftest_nop(robot_t *r)
{
    (void)r;
}
/* Instructions in selftest_nop(): a lone return. */
#define SELFTEST_NOP_INSTRUCTIONS 1u

/* Opaque: one body for every fn, so the overhead measured with the nop is the same. */
SELFTEST_OPAQUE static uint32_t selftest_measure(void (*fn)(robot_t *), robot_t *r)
{
    uint32_t t0 = selftest_counter();
    fn(r);
    uint32_t t1 = selftest_counter();
    return t1 - t0;
}

int selftest_begin(selftest_t *st, robot_t *r, uint16_t *costs, uint32_t costs_max)
{
    *st = (selftest_t){.robot = r, .costs = costs, .costs_max = costs_max};
    replay_start(&replay_scenario);
    slam_config_t cfg;
    replay_scenario.config(&cfg);
    if (robot_init(r, &cfg) != SLAM_OK) {
        st->done = true;
        return -1;
    }
    st->started = true;
    st->nop_cost = selftest_measure(selftest_nop, r);
    return 0;
}

void selftest_step(void *ctx)
{
    selftest_t *st = ctx;
    if (st->done) {
        return;
    }
    if (replay_next(NULL) != 0) {
        st->done = true;
        return;
    }
    uint32_t delta = selftest_measure(robot_tick, st->robot);
    replay_check();
    uint32_t tick = replay_status().ticks - 1u;
    uint32_t cost = delta - st->nop_cost + SELFTEST_NOP_INSTRUCTIONS;
    st->cost_sum = cost > UINT32_MAX - st->cost_sum ? UINT32_MAX : st->cost_sum + cost;
    if (cost > st->cost_worst) {
        st->cost_worst = cost;
        st->worst_tick = tick;
    }
    if (tick < st->costs_max) {
        st->costs[tick] = (uint16_t)(cost > UINT16_MAX ? UINT16_MAX : cost);
    }
    if (tick + 1u == replay_scenario.ticks) {
        /* -1 when the stream ends exactly here; -2 marks a stream with bytes left over. */
        (void)replay_next(NULL);
        st->done = true;
    }
}

static void print_line(text_line_t *l);

void selftest_idle(selftest_t *st)
{
    uint32_t cost =
        selftest_measure(robot_idle, st->robot) - st->nop_cost + SELFTEST_NOP_INSTRUCTIONS;
    if (cost > st->idle_worst) {
        st->idle_worst = cost;
        st->idle_worst_after = replay_status().ticks;
    }
}

/* The reading selftest_reading_costs() measures, for a measured function's one argument. */
static struct {
    odom_pose_t pose;
    bam32_t servo;
    uint32_t range_um;
} reading_args;

SELFTEST_OPAQUE static void selftest_one_reading(robot_t *r)
{
    (void)mapper_reading(&r->mapper, &r->grid, &reading_args.pose, reading_args.servo,
                         reading_args.range_um);
}

void selftest_reading_costs(selftest_t *st)
{
    robot_t *r = st->robot;
    const uint32_t ranges[2] = {r->cfg.confidence_radius_um - 1u, 3u * r->cfg.confidence_radius_um};
    uint32_t worst = 0u;
    uint32_t sum = 0u;
    uint32_t n = 0u;
    for (int32_t h = 0; h < 360000; h += 15000) {
        for (uint8_t stop = 0; stop < r->sweep.stops; stop++) {
            for (unsigned k = 0; k < 2u; k++) {
                reading_args.pose =
                    (odom_pose_t){r->cfg.start_x_um, r->cfg.start_y_um, fix_bam_from_mdeg(h)};
                reading_args.servo = r->sweep.stop_bam[stop];
                reading_args.range_um = ranges[k];
                uint32_t cost = selftest_measure(selftest_one_reading, r) - st->nop_cost +
                                SELFTEST_NOP_INSTRUCTIONS;
                worst = cost > worst ? cost : worst;
                sum += cost;
                n++;
            }
        }
    }
    text_line_t l;
    text_clear(&l);
    text_str(&l, "cost reading worst ");
    text_u32(&l, worst);
    text_str(&l, " mean ");
    text_u32(&l, n != 0u ? sum / n : 0u);
    text_str(&l, " of ");
    text_u32(&l, n);
    print_line(&l);
}

bool selftest_done(const selftest_t *st)
{
    return *(volatile const bool *)&st->done;
}

bool selftest_passed(const selftest_t *st)
{
    replay_status_t rs = replay_status();
    return st->started && !rs.corrupt && rs.mismatches == 0u && rs.ticks == replay_scenario.ticks;
}

static void print_line(text_line_t *l)
{
    text_str(l, "\n");
    selftest_print(l->buf);
    text_clear(l);
}

static uint32_t crc32(const uint8_t *p, uint32_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (uint32_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (unsigned k = 0; k < 8u; k++) {
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
        }
    }
    return ~crc;
}

static void report_map(text_line_t *l, const char *name, const uint8_t *map)
{
    text_str(l, name);
    text_str(l, " crc32 ");
    text_hex(l, crc32(map, SLAM_GRID_CELLS), 8u);
    text_str(l, " bytes ");
    text_u32(l, SLAM_GRID_CELLS);
    print_line(l);
    for (uint32_t i = 0; i < SLAM_GRID_CELLS; i += CELLS_PER_LINE) {
        text_str(l, name);
        text_str(l, " ");
        for (uint32_t k = i; k < i + CELLS_PER_LINE && k < SLAM_GRID_CELLS; k++) {
            text_hex(l, map[k], 2u);
        }
        print_line(l);
    }
}

static const char *const mismatch_names[] = {"-", "poll", "trigger", "duty_l", "duty_r", "servo"};

void selftest_report(const selftest_t *st, bool with_costs)
{
    const robot_t *r = st->robot;
    replay_status_t rs = replay_status();
    text_line_t l;
    text_clear(&l);
    text_str(&l, "sonarslam-selftest 1");
    print_line(&l);
    text_str(&l, "scenario ");
    text_str(&l, replay_scenario.name);
    text_str(&l, " ticks ");
    text_u32(&l, replay_scenario.ticks);
    print_line(&l);
    text_str(&l, "grid ");
    text_u32(&l, SLAM_GRID_A);
    text_str(&l, " ");
    text_u32(&l, SLAM_GRID_B);
    print_line(&l);
    text_str(&l, "replay ticks ");
    text_u32(&l, rs.ticks);
    text_str(&l, " mismatches ");
    text_u32(&l, rs.mismatches);
    text_str(&l, " first ");
    if (!st->started) {
        text_str(&l, "config-refused");
    } else if (rs.corrupt) {
        text_str(&l, "corrupt-stream");
    } else if (rs.mismatches == 0u) {
        text_str(&l, "-");
    } else {
        text_str(&l, mismatch_names[rs.first]);
        text_str(&l, " tick ");
        text_u32(&l, rs.first_tick);
        text_str(&l, " expected ");
        text_i32(&l, rs.first_expected);
        text_str(&l, " got ");
        text_i32(&l, rs.first_got);
    }
    print_line(&l);
    text_str(&l, "robot ticks ");
    text_u32(&l, r->ticks);
    text_str(&l, " pings ");
    text_u32(&l, r->sweep.pings);
    text_str(&l, " echoes ");
    text_u32(&l, r->sweep.echoes);
    text_str(&l, " timeouts ");
    text_u32(&l, r->sweep.timeouts);
    text_str(&l, " hits ");
    text_u32(&l, r->mapper.hits);
    text_str(&l, " far ");
    text_u32(&l, r->mapper.far);
    text_str(&l, " near ");
    text_u32(&l, r->mapper.near);
    text_str(&l, " outside ");
    text_u32(&l, r->mapper.outside);
    text_str(&l, " rejected ");
    text_u32(&l, r->grid.rejected);
    text_str(&l, " ping_errors ");
    text_u32(&l, r->ping_errors);
    print_line(&l);
    text_str(&l, "localize tried ");
    text_u32(&l, r->loc.match.tried);
    text_str(&l, " applied ");
    text_u32(&l, r->loc.match.applied);
    text_str(&l, " refused ");
    text_u32(&l, r->loc.match.refused);
    print_line(&l);
    text_str(&l, "pose ");
    text_i32(&l, r->pose.x_um);
    text_str(&l, " ");
    text_i32(&l, r->pose.y_um);
    text_str(&l, " ");
    text_u32(&l, r->pose.heading);
    print_line(&l);
    text_str(&l, "uart bytes ");
    text_u32(&l, rs.uart_bytes);
    text_str(&l, " crc32 ");
    text_hex(&l, rs.uart_crc32, 8u);
    print_line(&l);
    report_map(&l, "om", r->grid.om);
    report_map(&l, "tm", r->grid.tm);
    text_str(&l, "end");
    print_line(&l);

    if (!with_costs) {
        return;
    }
    text_str(&l, "cost nop ");
    text_u32(&l, st->nop_cost);
    print_line(&l);
    text_str(&l, "cost idle worst ");
    text_u32(&l, st->idle_worst);
    text_str(&l, " after ");
    text_u32(&l, st->idle_worst_after);
    print_line(&l);
    text_str(&l, "cost ticks ");
    text_u32(&l, rs.ticks);
    text_str(&l, " sum ");
    text_u32(&l, st->cost_sum);
    text_str(&l, " worst ");
    text_u32(&l, st->cost_worst);
    text_str(&l, " at ");
    text_u32(&l, st->worst_tick);
    print_line(&l);
    uint32_t n = rs.ticks < st->costs_max ? rs.ticks : st->costs_max;
    for (uint32_t i = 0; i < n; i += COSTS_PER_LINE) {
        text_str(&l, "cost");
        for (uint32_t k = i; k < i + COSTS_PER_LINE && k < n; k++) {
            text_str(&l, " ");
            text_hex(&l, st->costs[k], 4u);
        }
        print_line(&l);
    }
}
