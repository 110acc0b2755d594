/* SPDX-License-Identifier: MIT */
/* End to end on the kernel's gpio-sim: the real libgpiod glue against simulated lines. */
#define _GNU_SOURCE
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "hal/hal.h"
#include "lhal/lhal.h"
#include "tmptree.h"
#include "wait_until.h"
#include "wiring.h"

/* CTest's SKIP_RETURN_CODE for this test. */
#define SKIP_CODE 77

#define CONFIGFS "/sys/kernel/config"
#define SIM_ROOT CONFIGFS "/gpio-sim"
#define MS 1000000ull

/* Our lines on the simulated chip, in wiring.h's order. */
enum {
    L_A = 0,
    L_B = 1,
    R_A = 2,
    R_B = 3,
    TRIG = 4,
    ECHO = 5,
    L_IN1 = 6,
    L_IN2 = 7,
    R_IN1 = 8,
    R_IN2 = 9,
    STBY = 10,
    SIM_LINES = 16
};

static char sim_dir[96];    /* our device in configfs */
static char sim_lines[160]; /* /sys/devices/platform/<dev>/<chip> */
static char chip_name[32];
static char root[TMPTREE_PATH_MAX];
static lconf_t cfg;

/* Why gpio-sim cannot be used here, or NULL when it can. */
static const char *gpiosim_unavailable(void)
{
    FILE *f = fopen("/proc/filesystems", "r");
    bool configfs = false;
    char line[128];
    while (f != NULL && fgets(line, sizeof line, f) != NULL) {
        configfs = configfs || strstr(line, "configfs") != NULL;
    }
    if (f != NULL) {
        fclose(f);
    }
    if (!configfs) {
        return "the kernel has no configfs (CONFIG_CONFIGFS_FS is not set)";
    }
    struct stat st;
    if (stat(CONFIGFS, &st) != 0) {
        return "configfs is not mounted at " CONFIGFS " (mount -t configfs none " CONFIGFS ")";
    }
    if (stat(SIM_ROOT, &st) != 0) {
        return SIM_ROOT " does not exist: load the module (modprobe gpio-sim; the kernel needs "
                        "CONFIG_GPIO_SIM) or mount configfs";
    }
    if (access(SIM_ROOT, W_OK) != 0) {
        return "creating a simulated chip in " SIM_ROOT " needs root";
    }
    return NULL;
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        return -1;
    }
    int rc = fputs(text, f) < 0 ? -1 : 0;
    return fclose(f) != 0 ? -1 : rc;
}

static int read_text(const char *path, char *out, size_t n)
{
    FILE *f = fopen(path, "r");
    if (f == NULL || fgets(out, (int)n, f) == NULL) {
        if (f != NULL) {
            fclose(f);
        }
        return -1;
    }
    fclose(f);
    out[strcspn(out, "\n")] = '\0';
    return 0;
}

/* Drive a simulated input: the pull is what the outside world puts on the line. */
static void sim_pull(unsigned line, bool high)
{
    char path[224];
    snprintf(path, sizeof path, "%s/sim_gpio%u/pull", sim_lines, line);
    assert_int_equal(write_text(path, high ? "pull-up" : "pull-down"), 0);
}

/* What the backend drives on a simulated output (the pull when nobody drives it). */
static int sim_value(unsigned line)
{
    char path[224];
    char v[8];
    snprintf(path, sizeof path, "%s/sim_gpio%u/value", sim_lines, line);
    assert_int_equal(read_text(path, v, sizeof v), 0);
    return atoi(v);
}

static void sim_remove(void)
{
    char path[160];
    snprintf(path, sizeof path, "%s/live", sim_dir);
    (void)write_text(path, "0");
    snprintf(path, sizeof path, "%s/bank0", sim_dir);
    (void)rmdir(path);
    (void)rmdir(sim_dir);
}

static int sim_create(void)
{
    char path[160];
    char dev[64];
    snprintf(sim_dir, sizeof sim_dir, SIM_ROOT "/sonarslam-%ld", (long)getpid());
    snprintf(path, sizeof path, "%s/bank0", sim_dir);
    if (mkdir(sim_dir, 0755) != 0 || mkdir(path, 0755) != 0) {
        return -1;
    }
    snprintf(path, sizeof path, "%s/bank0/num_lines", sim_dir);
    char num[8];
    snprintf(num, sizeof num, "%d", SIM_LINES);
    if (write_text(path, num) != 0) {
        return -1;
    }
    snprintf(path, sizeof path, "%s/live", sim_dir);
    if (write_text(path, "1") != 0) {
        return -1;
    }
    snprintf(path, sizeof path, "%s/dev_name", sim_dir);
    if (read_text(path, dev, sizeof dev) != 0) {
        return -1;
    }
    snprintf(path, sizeof path, "%s/bank0/chip_name", sim_dir);
    if (read_text(path, chip_name, sizeof chip_name) != 0) {
        return -1;
    }
    snprintf(sim_lines, sizeof sim_lines, "/sys/devices/platform/%s/%s", dev, chip_name);
    return 0;
}

/* The backend's clock is frozen: the echo deadline never passes on a slow machine. */
static uint64_t frozen_clock(void)
{
    return 7000u * MS;
}

static int setup(void **state)
{
    (void)state;
    if (sim_create() != 0) {
        fprintf(stderr, "cannot create a gpio-sim chip: %s\n", strerror(errno));
        sim_remove();
        return -1;
    }
    for (unsigned i = 0; i < SIM_LINES; i++) {
        sim_pull(i, false);
    }
    tmptree_make(root, "gpiosim");
    wiring_lconf(&cfg, chip_name, L_A, root);
    cfg.sonar_timeout_us = 100000u;
    lhal_set_clock(frozen_clock);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    lhal_shutdown();
    tmptree_remove(root);
    sim_remove();
    return 0;
}

static void test_check_opens_every_simulated_line(void **state)
{
    (void)state;
    char out[4096];
    FILE *f = fmemopen(out, sizeof out, "w");
    assert_int_equal(lhal_check(&cfg, f), 0);
    fclose(f);
    assert_non_null(strstr(out, "check: all 17 items ok"));
}

static void test_lines_end_to_end(void **state)
{
    (void)state;
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_OK);

    /* Encoder: one forward cycle on the left wheel, an edge at a time. */
    const struct {
        unsigned line;
        bool high;
    } cycle[4] = {{L_A, true}, {L_B, true}, {L_A, false}, {L_B, false}};
    for (int i = 0; i < 4; i++) {
        sim_pull(cycle[i].line, cycle[i].high);
        WAIT_UNTIL(hal_encoder_count(HAL_WHEEL_LEFT) == (uint16_t)(i + 1));
    }
    assert_int_equal(hal_encoder_count(HAL_WHEEL_RIGHT), 0);

    /* Motor direction lines are real outputs. */
    hal_motor_set(HAL_WHEEL_LEFT, 500);
    assert_int_equal(sim_value(L_IN1), 1);
    assert_int_equal(sim_value(L_IN2), 0);
    assert_int_equal(sim_value(STBY), 1);
    hal_motor_set(HAL_WHEEL_LEFT, -500);
    assert_int_equal(sim_value(L_IN1), 0);
    assert_int_equal(sim_value(L_IN2), 1);

    /* Sonar: the echo is high for at least 2 ms between two kernel timestamps. */
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    assert_int_equal(sim_value(TRIG), 0); /* the pulse is over */
    sim_pull(ECHO, true);
    wait_ms(2);
    sim_pull(ECHO, false);
    uint32_t w = 0;
    hal_sonar_status_t st = HAL_SONAR_BUSY;
    for (int i = 0; i < 20000 && st == HAL_SONAR_BUSY; i++) {
        st = (hal_sonar_status_t)hal_sonar_poll(HAL_SONAR_SWEPT,
                                                &w); /* never an error for sonar 0 */
        wait_ms(st == HAL_SONAR_BUSY ? 1 : 0);
    }
    assert_int_equal(st, HAL_SONAR_ECHO);
    assert_true(w >= 2000u);

    /* Shutdown drives the outputs low and releases them. */
    hal_motor_set(HAL_WHEEL_LEFT, 500);
    lhal_shutdown();
    assert_int_equal(sim_value(L_IN1), 0);
    assert_int_equal(sim_value(STBY), 0);
    assert_string_equal(tmptree_read(root, "pwmchip0/pwm0/enable"), "0\n");
}

int main(void)
{
    const char *why = gpiosim_unavailable();
    if (why != NULL) {
        printf("SKIP: gpio-sim cannot be used on this machine: %s\n", why);
        return SKIP_CODE;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_check_opens_every_simulated_line, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lines_end_to_end, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
