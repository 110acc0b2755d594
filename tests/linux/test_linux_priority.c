/* SPDX-License-Identifier: MIT */
/* Priority inversion on the Linux backend's locks: a normal-priority thread that holds the
 * sonar state while a medium-priority one runs must not hold up the SCHED_FIFO tick.
 * Needs real-time scheduling: exits 77 (skipped, with the reason) where it is refused. */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "fake_gpio.h"
#include "hal/hal.h"
#include "lhal/lhal.h"
#include "tmptree.h"
#include "wait_until.h"
#include "wiring.h"

#define MS 1000000ull

static char root[TMPTREE_PATH_MAX];
static lconf_t cfg;
static pthread_t main_thread;
static atomic_bool armed;
static atomic_uint ticks;
static atomic_uint ticks_while_hog_ran;

/* Every tick reads the sonar, as robot_tick() does while a ping is out. */
static void tick_cb(void *ctx)
{
    (void)ctx;
    uint32_t w;
    (void)hal_sonar_poll(HAL_SONAR_SWEPT, &w);
    atomic_fetch_add(&ticks, 1u);
}

static pthread_t hog_thread;
static atomic_bool hog_started;

/* A medium-priority thread that computes on the only CPU until five ticks went by, or
 * 300 ms (a bound that only keeps a broken build from hanging: ticks come every 10 ms). */
static void *hog(void *arg)
{
    (void)arg;
    atomic_store(&hog_started, true);
    unsigned before = atomic_load(&ticks);
    uint64_t end = wait_real_ns() + 300u * MS;
    while (atomic_load(&ticks) < before + 5u && wait_real_ns() < end) {
    }
    atomic_store(&ticks_while_hog_ran, atomic_load(&ticks) - before);
    return NULL;
}

/* The backend's clock. Called by the main thread inside hal_sonar_trigger(HAL_SONAR_SWEPT), with
 * the sonar state locked: there, once, the medium-priority thread starts, and the main thread,
 * which has only to return and unlock, waits its turn for the CPU. */
static uint64_t clock_that_starts_the_hog(void)
{
    if (pthread_equal(pthread_self(), main_thread) && atomic_exchange(&armed, false)) {
        pthread_attr_t a;
        pthread_attr_init(&a);
        pthread_attr_setinheritsched(&a, PTHREAD_EXPLICIT_SCHED);
        pthread_attr_setschedpolicy(&a, SCHED_FIFO);
        struct sched_param sp = {.sched_priority = 10};
        pthread_attr_setschedparam(&a, &sp);
        if (pthread_create(&hog_thread, &a, hog, NULL) == 0) {
            /* Holding the lock until the hog has had the CPU: sleeping, not spinning. A tick
             * that comes first boosts this thread above the hog (priority inheritance), and
             * a spin at that priority would keep the hog from ever starting on the one CPU. */
            uint64_t end = wait_real_ns() + 1000u * MS;
            while (!atomic_load(&hog_started) && wait_real_ns() < end) {
                wait_ms(1);
            }
        }
        pthread_attr_destroy(&a);
    }
    return 1000u * MS;
}

static int setup(void **state)
{
    (void)state;
    fake_gpio_reset();
    tmptree_make(root, "prio");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    lhal_shutdown();
    tmptree_remove(root);
    return 0;
}

static void test_the_tick_runs_while_a_normal_thread_holding_the_sonar_is_preempted(void **state)
{
    (void)state;
    wiring_lconf(&cfg, "fakechip0", 1, root);
    cfg.tick_priority = 50u;
    main_thread = pthread_self();
    lhal_set_clock(clock_that_starts_the_hog);
    lhal_configure(&cfg);
    assert_int_equal(hal_init(), HAL_OK);
    assert_int_equal(hal_tick_start(tick_cb, NULL), HAL_OK);
    WAIT_UNTIL(atomic_load(&ticks) >= 3u);
    atomic_store(&armed, true);
    assert_int_equal(hal_sonar_trigger(HAL_SONAR_SWEPT), HAL_OK);
    assert_true(atomic_load(&hog_started));
    pthread_join(hog_thread, NULL);
    /* Without priority inheritance the tick waits for the lock behind the normal-priority
     * holder, which waits for the CPU behind the hog: no tick while the hog runs. */
    assert_int_equal(atomic_load(&ticks_while_hog_ran), 5u);
    assert_int_equal(lhal_fault(NULL, 0), LHAL_FAULT_NONE);
}

/* One CPU for everything, and SCHED_FIFO allowed, or the test cannot say anything. */
static int can_run(void)
{
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) {
        printf("skipped: cannot pin the test to CPU 0: %s\n", strerror(errno));
        return 0;
    }
    struct sched_param sp = {.sched_priority = 1};
    int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (rc != 0) {
        printf("skipped: SCHED_FIFO is not permitted here (%s); run as root or with "
               "CAP_SYS_NICE\n",
               strerror(rc));
        return 0;
    }
    sp.sched_priority = 0;
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp);
    return 1;
}

int main(void)
{
    if (!can_run()) {
        return 77;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(
            test_the_tick_runs_while_a_normal_thread_holding_the_sonar_is_preempted, setup,
            teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
