/* SPDX-License-Identifier: MIT */
/* Tests of the configuration: the paper's defaults, and every bad field named. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "slam/config.h"
#include "slam/config_fields.h"
#include "slam/error.h"
#include "slam/grid.h"

static void test_defaults_are_the_papers(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    /* The default map holds free-space evidence, with every post-processing step off
     * (each lowered F1 on it); the paper's method is one call away. */
    assert_int_equal(c.om_mode, OM_MODE_EVIDENCE);
    assert_int_equal(c.post_threshold, 0);
    assert_int_equal(c.post_template_k, 0);
    assert_int_equal(c.post_insert, 0);
    slam_config_paper(&c);
    assert_int_equal(c.om_mode, OM_MODE_COUNT);         /* Eq. 6 */
    assert_int_equal(c.om_max, 9);                      /* OMmax, Eq. 6 */
    assert_int_equal(c.tm_max, 30);                     /* TMmax, Eq. 7 */
    assert_int_equal(c.confidence_radius_um, 1000000u); /* rc = 1 m */
    assert_int_equal(c.post_threshold, 3);              /* TH */
    assert_int_equal(c.post_insert, 1);
    assert_int_equal(c.sweep_first_mdeg, 65000); /* 65° ... */
    assert_int_equal(c.sweep_last_mdeg, 155000); /* ... 155° */
    assert_int_equal(c.sweep_stops, 6);          /* six stops, 18° apart */
    assert_int_equal((c.sweep_last_mdeg - c.sweep_first_mdeg) / (c.sweep_stops - 1), 18000);
    assert_int_equal(SLAM_TICK_US, 10000u);             /* 10 ms control period */
    assert_int_equal(c.start_cell_a, SLAM_GRID_A / 2u); /* start at the centre */
    assert_int_equal(c.start_cell_b, SLAM_GRID_B / 2u);
    /* A stop lasts about 60 ms: 30 ms settling, then up to 38 ms for the echo, and pings
     * at least 60 ms apart (the HC-SR04 datasheet). */
    assert_int_equal(c.settle_ticks, 3);
    assert_true(c.echo_timeout_ticks * SLAM_TICK_US >= 38000u);
    assert_true(c.ping_interval_ticks * SLAM_TICK_US >= 60000u);
    const char *field = "unset";
    assert_int_equal(slam_config_check(&c, &field), SLAM_OK);
    assert_null(field);
    assert_int_equal(slam_config_check(&c, NULL), SLAM_OK);
}

typedef struct {
    const char *field;
    void (*mutate)(slam_config_t *c);
} bad_case_t;

#define BAD(name, body)                                                                            \
    static void bad_##name(slam_config_t *c)                                                       \
    {                                                                                              \
        body;                                                                                      \
    }
BAD(diam_l_small, c->wheel_diameter_left_um = 9999u)
BAD(diam_r_big, c->wheel_diameter_right_um = 300001u)
BAD(base_zero, c->wheel_base_um = 0u)
BAD(counts_few, c->encoder_counts_per_rev = 15u)
BAD(counts_many, c->encoder_counts_per_rev = 65536u)
BAD(cal_l, c->cal_left = 0)
BAD(cal_r, c->cal_right = FIX_Q30_ONE + FIX_Q30_ONE / 2 + 1)
BAD(cal_b, c->cal_base = FIX_Q30_ONE / 2 - 1)
BAD(start_x, c->start_x_um = 1000000001)
BAD(start_y, c->start_y_um = -1000000001)
BAD(start_h, c->start_heading_mdeg = 360001)
BAD(cell_zero, c->cell_um = 0u)
BAD(cell_huge, c->cell_um = 1000001u)
BAD(cell_small, c->cell_um = 19999u)
/* 20 mm cells: 15 rows of the corridor, 16 columns at most (a clearance below 160 mm). */
BAD(corridor, c->cell_um = 20000u; c->clearance_um = 160000u; c->follow_um = 400000u)
BAD(start_a, c->start_cell_a = (uint16_t)SLAM_GRID_A)
/* The grid's size: within the capacity, 3 cells at least, and the start cell inside it. */
BAD(grid_a_big, c->grid_a = (uint16_t)(SLAM_GRID_A + 1u))
BAD(grid_b_big, c->grid_b = (uint16_t)(SLAM_GRID_B + 1u))
BAD(grid_a_two, c->grid_a = 2u; c->start_cell_a = 1u)
BAD(grid_b_one, c->grid_b = 1u; c->start_cell_b = 0u)
BAD(start_a_in_grid, c->grid_a = (uint16_t)(SLAM_GRID_A / 2u))
BAD(start_b_in_grid, c->grid_a = 100u; c->start_cell_a = 50u; c->grid_b = 10u)
BAD(start_b, c->start_cell_b = 0xFFFFu)
BAD(om_max, c->om_max = 0u)
BAD(tm_max, c->tm_max = 0u)
BAD(rc_small, c->confidence_radius_um = c->range_min_um)
BAD(rc_zero, c->confidence_radius_um = 0u)
BAD(range_min, c->range_min_um = 1000001u; c->confidence_radius_um = 2000000u)
BAD(sound, c->sound_speed_mm_per_s = 299999u)
BAD(mount_x, c->mount_x_um = 1000001)
BAD(mount_y, c->mount_y_um = -1000001)
BAD(mount_yaw, c->mount_yaw_mdeg = 180001)
BAD(first, c->sweep_first_mdeg = -1)
BAD(last, c->sweep_last_mdeg = 180001)
BAD(stops_zero, c->sweep_stops = 0u)
BAD(stops_many, c->sweep_stops = SLAM_SWEEP_STOPS_MAX + 1u)
BAD(stops_one, c->sweep_stops = 1u)
BAD(settle, c->settle_ticks = 0u)
BAD(echo_to, c->echo_timeout_ticks = 0u)
BAD(ping_interval, c->ping_interval_ticks = 0u)
BAD(pulse0, c->servo_pulse_0deg_us = 399u)
BAD(pulse180, c->servo_pulse_180deg_us = 2601u)
BAD(pulse_same, c->servo_pulse_180deg_us = c->servo_pulse_0deg_us)
BAD(threshold, c->post_threshold = GRID_EVIDENCE_MAX)
BAD(threshold_count, slam_config_paper(c); c->post_threshold = c->om_max)
BAD(template_k, c->post_template_k = 9u)
BAD(insert, c->post_insert = 2u)
BAD(om_mode, c->om_mode = OM_MODES)
BAD(om_hit, c->om_hit = 0u)
BAD(om_miss, c->om_miss = GRID_EVIDENCE_MAX + 1u)

static void test_every_bad_field_is_named(void **state)
{
    (void)state;
    static const bad_case_t cases[] = {
        {"wheel_diameter_left_um", bad_diam_l_small},
        {"grid_a", bad_grid_a_big},
        {"grid_b", bad_grid_b_big},
        {"grid_a", bad_grid_a_two},
        {"grid_b", bad_grid_b_one},
        {"start_cell_a", bad_start_a_in_grid},
        {"start_cell_b", bad_start_b_in_grid},
        {"wheel_diameter_right_um", bad_diam_r_big},
        {"wheel_base_um", bad_base_zero},
        {"encoder_counts_per_rev", bad_counts_few},
        {"encoder_counts_per_rev", bad_counts_many},
        {"cal_left", bad_cal_l},
        {"cal_right", bad_cal_r},
        {"cal_base", bad_cal_b},
        {"start_x_um", bad_start_x},
        {"start_y_um", bad_start_y},
        {"start_heading_mdeg", bad_start_h},
        {"cell_um", bad_cell_zero},
        {"cell_um", bad_cell_huge},
        {"cell_um", bad_cell_small},
        {"clearance_um", bad_corridor},
        {"start_cell_a", bad_start_a},
        {"start_cell_b", bad_start_b},
        {"om_max", bad_om_max},
        {"tm_max", bad_tm_max},
        {"confidence_radius_um", bad_rc_small},
        {"confidence_radius_um", bad_rc_zero},
        {"range_min_um", bad_range_min},
        {"sound_speed_mm_per_s", bad_sound},
        {"mount_x_um", bad_mount_x},
        {"mount_y_um", bad_mount_y},
        {"mount_yaw_mdeg", bad_mount_yaw},
        {"sweep_first_mdeg", bad_first},
        {"sweep_last_mdeg", bad_last},
        {"sweep_stops", bad_stops_zero},
        {"sweep_stops", bad_stops_many},
        {"sweep_stops", bad_stops_one},
        {"settle_ticks", bad_settle},
        {"echo_timeout_ticks", bad_echo_to},
        {"ping_interval_ticks", bad_ping_interval},
        {"servo_pulse_0deg_us", bad_pulse0},
        {"servo_pulse_180deg_us", bad_pulse180},
        {"servo_pulse_180deg_us", bad_pulse_same},
        {"post_threshold", bad_threshold},
        {"post_template_k", bad_template_k},
        {"post_threshold", bad_threshold_count},
        {"post_insert", bad_insert},
        {"om_mode", bad_om_mode},
        {"om_hit", bad_om_hit},
        {"om_miss", bad_om_miss},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        slam_config_t c;
        slam_config_default(&c);
        cases[i].mutate(&c);
        slam_config_t copy = c;
        const char *field = NULL;
        assert_int_equal(slam_config_check(&c, &field), SLAM_EINVAL);
        assert_non_null(field);
        assert_string_equal(field, cases[i].field);
        assert_memory_equal(&c, &copy, sizeof c); /* the check changes nothing */
    }
}

static void test_edges_of_valid_ranges_pass(void **state)
{
    (void)state;
    slam_config_t c;
    slam_config_default(&c);
    c.wheel_diameter_left_um = 10000u;
    c.wheel_diameter_right_um = 300000u;
    c.wheel_base_um = 1000000u;
    c.encoder_counts_per_rev = 16u;
    c.cal_left = FIX_Q30_ONE / 2;
    c.cal_right = FIX_Q30_ONE + FIX_Q30_ONE / 2;
    c.cell_um = 20000u;
    c.clearance_um = 159999u; /* the widest corridor 20 mm cells take */
    c.start_cell_a = (uint16_t)(SLAM_GRID_A - 1u);
    c.start_cell_b = 0u;
    c.sweep_stops = 1u;
    c.sweep_first_mdeg = c.sweep_last_mdeg = 90000;
    c.post_template_k = 8u;
    c.post_threshold = (uint8_t)(GRID_EVIDENCE_MAX - 1u);
    c.om_hit = GRID_EVIDENCE_MAX;
    c.om_miss = 1u;
    c.post_insert = 1u;
    assert_int_equal(slam_config_check(&c, NULL), SLAM_OK);
    slam_config_paper(&c);
    c.post_threshold = (uint8_t)(c.om_max - 1u);
    assert_int_equal(slam_config_check(&c, NULL), SLAM_OK);
    /* The grid's size: the capacity itself, and the smallest, 3 cells, with the start in it. */
    c.grid_a = (uint16_t)SLAM_GRID_A;
    c.grid_b = 3u;
    c.start_cell_a = (uint16_t)(SLAM_GRID_A - 1u);
    c.start_cell_b = 2u;
    assert_int_equal(slam_config_check(&c, NULL), SLAM_OK);
}

/* Every row of config_fields.h, as the check must apply it. */
typedef struct {
    const char *name;
    size_t offset;
    char type; /* 'b' U8, 'h' U16, 'w' U32, 's' I32 or Q30 */
    int64_t lo, hi;
    bool rule; /* compared with other fields too */
} row_t;
#define ROW_U8 'b'
#define ROW_U16 'h'
#define ROW_U32 'w'
#define ROW_I32 's'
#define ROW_Q30 's'
static const row_t rows[] = {
#define ROW(name, type, dflt, lo, hi, rule, id, live, words)                                       \
    {#name,          offsetof(slam_config_t, name), ROW_##type, (int64_t)(lo), (int64_t)(hi),      \
     #rule[0] != 'N'},
    SLAM_CONFIG_FIELDS(ROW)
#undef ROW
};

/* Stores v into a row's field; false when the type cannot hold it. */
static bool row_store(slam_config_t *c, const row_t *r, int64_t v)
{
    uint8_t *p = (uint8_t *)c + r->offset;
    int64_t tmin = r->type == 's' ? INT32_MIN : 0;
    int64_t tmax = r->type == 'b'   ? UINT8_MAX
                   : r->type == 'h' ? UINT16_MAX
                   : r->type == 'w' ? (int64_t)UINT32_MAX
                                    : INT32_MAX;
    if (v < tmin || v > tmax) {
        return false;
    }
    uint8_t b8 = (uint8_t)v;
    uint16_t b16 = (uint16_t)v;
    uint32_t b32 = (uint32_t)v;
    int32_t s32 = (int32_t)v;
    switch (r->type) {
    case 'b':
        memcpy(p, &b8, 1);
        break;
    case 'h':
        memcpy(p, &b16, 2);
        break;
    case 'w':
        memcpy(p, &b32, 4);
        break;
    default:
        memcpy(p, &s32, 4);
        break;
    }
    return true;
}

/* The check holds each field to its row's range: just outside it is refused (naming the
 * field, or a field before it whose rule compares the two), and at either end it is
 * accepted unless a rule refuses it. */
static void test_every_row_bounds_its_field(void **state)
{
    (void)state;
    assert_int_equal(sizeof rows / sizeof rows[0], SLAM_CONFIG_ROWS);
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        const row_t *r = &rows[i];
        const int64_t probe[4] = {r->lo - 1, r->hi + 1, r->lo, r->hi};
        for (int k = 0; k < 4; k++) {
            slam_config_t c;
            slam_config_default(&c);
            if (!row_store(&c, r, probe[k])) {
                continue; /* the type itself keeps the value out */
            }
            const char *field = NULL;
            int rc = slam_config_check(&c, &field);
            size_t named = 0;
            while (field != NULL && named < SLAM_CONFIG_ROWS &&
                   strcmp(rows[named].name, field) != 0) {
                named++;
            }
            bool by_rule = field != NULL && named < SLAM_CONFIG_ROWS && rows[named].rule;
            if (k < 2 ? rc != SLAM_EINVAL || (named != i && !(by_rule && named < i))
                      : rc != SLAM_OK && !by_rule) {
                fail_msg("%s = %lld: slam_config_check() %s (%s)", r->name, (long long)probe[k],
                         rc == SLAM_OK ? "accepts it" : "refuses it", field != NULL ? field : "-");
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_the_papers),
        cmocka_unit_test(test_every_bad_field_is_named),
        cmocka_unit_test(test_edges_of_valid_ranges_pass),
        cmocka_unit_test(test_every_row_bounds_its_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
