/* SPDX-License-Identifier: MIT */
/* The Linux program's stop rule (hal/linux/README.md), each case a run of sonarslam-linux in
 * a child process on the fake GPIO chip: a servo write that never returns, an events thread
 * that dies, SIGTERM twice. */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "fake_gpio.h"
#include "lhal/app.h"
#include "lhal/lhal.h"
#include "tmptree.h"
#include "wiring.h"
#include "wait_until.h"

#define MS 1000000ull
#define STEP_NS (20u * MS)

/* The fake's line offsets, as the configuration below wires them. */
enum { L_A = 1, TRIG = 5, L_IN1 = 7, L_IN2 = 8, R_IN1 = 9, R_IN2 = 10, STBY = 11 };
static const unsigned motor_lines[] = {L_IN1, L_IN2, R_IN1, R_IN2, STBY};

static char root[TMPTREE_PATH_MAX];
static char conf[TMPTREE_PATH_MAX + 16];

/* What the test and its child share: the backend's clock, which the test moves, and what
 * the child's backend says, which a thread of the child copies here every millisecond. */
typedef struct {
    _Atomic uint64_t now_ns;
    _Atomic uint32_t ticks;
    _Atomic uint32_t events_rounds;
    _Atomic uint32_t output_rounds;
    _Atomic uint32_t posted;
    _Atomic uint32_t written;
    atomic_bool writing_servo; /* the output thread is inside a servo write */
    atomic_int fault;
    atomic_bool go;          /* the program runs: the copying may begin */
    atomic_bool kill_events; /* the test asks the child to end its events thread */
    atomic_bool quiet;       /* the test asks the copying to stop (the program is ending) */
} shared_t;

static shared_t *sh;

static uint64_t shared_clock(void)
{
    return atomic_load(&sh->now_ns);
}

static void *mirror(void *arg)
{
    (void)arg;
    while (!atomic_load(&sh->go)) {
        wait_ms(1);
    }
    while (!atomic_load(&sh->quiet)) {
        lhal_stats_t st;
        lhal_stats(&st);
        atomic_store(&sh->ticks, (uint32_t)st.tick.ticks);
        atomic_store(&sh->events_rounds, st.events_rounds);
        atomic_store(&sh->output_rounds, st.output_rounds);
        atomic_store(&sh->posted, st.outputs_posted);
        atomic_store(&sh->written, st.outputs_written);
        atomic_store(&sh->writing_servo,
                     st.output_writing != NULL && strcmp(st.output_writing, "servo_pwm") == 0);
        if (atomic_exchange(&sh->kill_events, false)) {
            fake_gpio_kill_reader(L_A);
        }
        lhal_fault_t f = lhal_fault(NULL, 0);
        atomic_store(&sh->fault, (int)f);
        if (f != LHAL_FAULT_NONE) {
            break; /* the program ends: its state is no more to be read */
        }
        wait_ms(1);
    }
    return NULL;
}

/* Runs the program in this process (a child): never returns. */
static void child(void)
{
    lhal_set_clock(shared_clock);
    char path[TMPTREE_PATH_MAX + 16];
    snprintf(path, sizeof path, "%s/out.txt", root);
    FILE *out = fopen(path, "w");
    snprintf(path, sizeof path, "%s/err.txt", root);
    FILE *err = fopen(path, "w");
    if (out == NULL || err == NULL) {
        _exit(99);
    }
    setvbuf(out, NULL, _IONBF, 0);
    setvbuf(err, NULL, _IONBF, 0);
    /* The copying thread leaves the stop signals to the program's main thread. */
    sigset_t all;
    sigset_t old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    pthread_t t;
    pthread_create(&t, NULL, mirror, NULL);
    pthread_detach(t);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    char *argv[] = {"sonarslam-linux", "--config", conf, NULL};
    int rc = app_main(3, argv, out, err);
    _exit(rc);
}

static pid_t start(void)
{
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        child();
    }
    return pid;
}

/* Starts the program in a child and waits until the motors run. */
static pid_t start_driving(void)
{
    pid_t pid = start();
    WAIT_UNTIL(fake_gpio_value(L_IN1) == 1 && fake_gpio_value(STBY) == 1);
    atomic_store(&sh->go, true);
    return pid;
}

/* The child's exit status (128 + N when signal N ended it); bounded, it never hangs. */
static int finish(pid_t pid)
{
    int status = 0;
    pid_t r = 0;
    for (int i = 0; i < 60000 && (r = waitpid(pid, &status, WNOHANG)) == 0; i++) {
        wait_ms(1);
    }
    if (r == 0) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        fail_msg("the program did not end within 60 s");
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* Moves the child's clock 20 ms at a time, each step once the tick and the threads that
 * should be alive went round twice since the last (so only a stuck one grows old), until
 * the watchdog trips. */
static void step_until_fault(bool output_alive, bool events_alive)
{
    WAIT_UNTIL(atomic_load(&sh->ticks) >= 10u);
    for (int i = 0; i < 100 && atomic_load(&sh->fault) == LHAL_FAULT_NONE; i++) {
        uint32_t ticks = atomic_load(&sh->ticks);
        uint32_t out = atomic_load(&sh->output_rounds);
        uint32_t ev = atomic_load(&sh->events_rounds);
        atomic_fetch_add(&sh->now_ns, STEP_NS);
        WAIT_UNTIL(atomic_load(&sh->fault) != LHAL_FAULT_NONE ||
                   (atomic_load(&sh->ticks) >= ticks + 2u &&
                    (!output_alive || atomic_load(&sh->output_rounds) >= out + 2u) &&
                    (!events_alive || atomic_load(&sh->events_rounds) >= ev + 2u)));
    }
    assert_int_not_equal(atomic_load(&sh->fault), LHAL_FAULT_NONE);
}

/* Replaces a file with a FIFO nobody reads, in one step: the next open for writing waits
 * for a reader for ever. */
static void make_fifo(const char *rel)
{
    char path[TMPTREE_PATH_MAX + 32];
    char tmp[TMPTREE_PATH_MAX + 40];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    snprintf(tmp, sizeof tmp, "%s.fifo", path);
    assert_int_equal(mkfifo(tmp, 0600), 0);
    assert_int_equal(rename(tmp, path), 0);
}

/* The age the watchdog gave a stall, from its message: "... for N ms" or "... N ms ago". */
static unsigned stall_ms(const char *err, const char *after)
{
    const char *at = strstr(err, after);
    unsigned ms = 0;
    if (at == NULL || sscanf(at + strlen(after), "%u", &ms) != 1) {
        fail_msg("no '%s' in: %s", after, err);
    }
    return ms;
}

/* The output thread is stuck: inside a servo write, and it stays there while the tick goes
 * round ten times (a healthy one goes round every 10 ms). */
static void wait_until_output_stuck(void)
{
    for (int tries = 0; tries < 1000; tries++) {
        WAIT_UNTIL(atomic_load(&sh->writing_servo));
        uint32_t rounds = atomic_load(&sh->output_rounds);
        uint32_t ticks = atomic_load(&sh->ticks);
        WAIT_UNTIL(atomic_load(&sh->ticks) >= ticks + 10u ||
                   atomic_load(&sh->output_rounds) != rounds);
        if (atomic_load(&sh->output_rounds) == rounds && atomic_load(&sh->writing_servo)) {
            return;
        }
    }
    fail_msg("the output thread kept writing");
}

static bool lines_low(void)
{
    for (unsigned i = 0; i < sizeof motor_lines / sizeof motor_lines[0]; i++) {
        if (fake_gpio_value(motor_lines[i]) != 0) {
            return false;
        }
    }
    return true;
}

static const char *file(const char *rel)
{
    return tmptree_read(root, rel);
}

static int setup(void **state)
{
    (void)state;
    fake_gpio_reset();
    if (sh == NULL) {
        sh = mmap(NULL, sizeof *sh, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        assert_true(sh != MAP_FAILED);
    }
    memset(sh, 0, sizeof *sh);
    atomic_store(&sh->now_ns, 1000u * MS);
    tmptree_make(root, "stop");
    tmptree_file(root, "maps/.keep", "");
    snprintf(conf, sizeof conf, "%s/robot.conf", root);
    /* With a standby line, and a square: the motors run from the first tick. */
    wiring_conf_file(root, "explore_mode = 3\n", "motor_standby = 11\n");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    tmptree_remove(root);
    return 0;
}

/* The motors ran, and are off now: duty 0 and disabled, every direction and standby line
 * low. */
static void assert_motors_ran_and_stopped(void)
{
    assert_true(fake_gpio_rises(L_IN1) >= 1u);
    assert_true(fake_gpio_rises(STBY) >= 1u);
    assert_true(lines_low());
    assert_string_equal(file("pwmchip0/pwm0/duty_cycle"), "0\n");
    assert_string_equal(file("pwmchip0/pwm0/enable"), "0\n");
    assert_string_equal(file("pwmchip0/pwm1/duty_cycle"), "0\n");
    assert_string_equal(file("pwmchip0/pwm1/enable"), "0\n");
}

/* The program found the stall the watchdog names within 50 ms past the limit (the age it
 * gives is the stamp's, on the backend's clock), stopped the motors, saved the maps and
 * exited 3. */
static void assert_stopped_for_a_stall(pid_t pid, const char *says)
{
    assert_int_equal(finish(pid), APP_EXIT_SAFETY);
    unsigned ms = stall_ms(file("err.txt"), says);
    assert_true(ms > 100u && ms <= 150u);
    assert_motors_ran_and_stopped();
    assert_true(tmptree_exists(root, "maps/om.pgm"));
    assert_true(tmptree_exists(root, "maps/om_post.pgm"));
    assert_true(tmptree_exists(root, "maps/tm.pgm"));
    assert_non_null(strstr(file("out.txt"), "maps written to"));
}

/* The servo's duty_cycle becomes a FIFO nobody reads while the robot drives: its next write
 * never returns (a PCA9685 on a hung I2C bus). The tick goes on; the watchdog finds the
 * output thread stuck within 50 ms past the 100 ms limit (on the backend's clock) and
 * drops the lines in the same pass, though that thread never comes back. The program
 * saves the maps and exits 3. */
static void test_a_servo_write_that_never_returns(void **state)
{
    (void)state;
    pid_t pid = start_driving();
    make_fifo("pwmchip1/pwm0/duty_cycle");
    step_until_fault(false, true);
    assert_stopped_for_a_stall(pid, "watchdog: writing servo_pwm has not returned for ");
}

/* The events thread ends without a word (as it did when poll() failed): the encoder counts
 * freeze while the motors run. The watchdog sees it stamp no more. */
static void test_the_events_thread_killed(void **state)
{
    (void)state;
    pid_t pid = start_driving();
    atomic_store(&sh->kill_events, true);
    WAIT_UNTIL(!atomic_load(&sh->kill_events));
    step_until_fault(true, false);
    assert_stopped_for_a_stall(pid, "watchdog: the events thread (encoders, echo) stopped ");
}

/* SIGTERM while the output thread hangs in a servo write, before the watchdog's limit (its
 * clock does not move): the motors stop, the thread is left where it hangs, the maps are
 * written as the tick left them, and the exit status is 3, a stalled thread, as
 * documented (it was 0). */
static void test_sigterm_with_the_output_stuck_exits_3(void **state)
{
    (void)state;
    pid_t pid = start_driving();
    make_fifo("pwmchip1/pwm0/duty_cycle");
    wait_until_output_stuck();
    atomic_store(&sh->quiet, true);
    assert_int_equal(kill(pid, SIGTERM), 0);
    assert_int_equal(finish(pid), APP_EXIT_SAFETY);
    assert_non_null(strstr(file("err.txt"), "a thread did not stop"));
    assert_motors_ran_and_stopped();
    assert_true(tmptree_exists(root, "maps/om.pgm"));
    assert_true(tmptree_exists(root, "maps/tm.pgm"));
}

/* SIGTERM while the output thread hangs in a servo write and the map cannot be written (its
 * file is a FIFO nobody reads): the first signal stops the motors at once, though a thread
 * is stuck and the program is not done; the second ends it at once. */
static void test_sigterm_twice(void **state)
{
    (void)state;
    make_fifo("maps/om.pgm.tmp");
    pid_t pid = start_driving();
    make_fifo("pwmchip1/pwm0/duty_cycle");
    wait_until_output_stuck();
    atomic_store(&sh->quiet, true);
    assert_int_equal(kill(pid, SIGTERM), 0);
    WAIT_UNTIL(lines_low() && strcmp(file("pwmchip0/pwm0/enable"), "0\n") == 0 &&
               strcmp(file("pwmchip0/pwm1/enable"), "0\n") == 0 &&
               strcmp(file("pwmchip0/pwm0/duty_cycle"), "0\n") == 0 &&
               strcmp(file("pwmchip0/pwm1/duty_cycle"), "0\n") == 0);
    assert_motors_ran_and_stopped();
    assert_int_equal(waitpid(pid, NULL, WNOHANG), 0); /* not done, and it cannot be */
    assert_int_equal(kill(pid, SIGTERM), 0);
    assert_int_equal(finish(pid), 128 + SIGTERM);
    assert_false(tmptree_exists(root, "maps/om.pgm"));
    assert_true(lines_low());
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_a_servo_write_that_never_returns, setup, teardown),
        cmocka_unit_test_setup_teardown(test_the_events_thread_killed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sigterm_with_the_output_stuck_exits_3, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_sigterm_twice, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
