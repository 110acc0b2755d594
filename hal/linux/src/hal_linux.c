/* SPDX-License-Identifier: MIT */
/* hal.h on a Linux single-board computer: GPIO edges, sysfs PWM, a timerfd tick, a watchdog. */
#define _GNU_SOURCE /* pthread_timedjoin_np */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "hal/hal.h"
#include "lhal/echo.h"
#include "lhal/edgeq.h"
#include "lhal/gpio_if.h"
#include "lhal/lhal.h"
#include "lhal/motor.h"
#include "lhal/pwm.h"
#include "lhal/quad.h"
#include "lhal/serial.h"
#include "lhal/store.h"
#include "lhal/tickstat.h"
#include "lhal/wdog.h"

#define LX_NS_PER_US 1000u
#define LX_NS_PER_MS 1000000u
#define LX_NS_PER_S 1000000000u
#define LX_TICK_NS ((uint64_t)HAL_TICK_PERIOD_US * LX_NS_PER_US)
#define LX_SERVO_PERIOD_NS 20000000u /* 50 Hz */
#define LX_SERVO_MIN_US 400u
#define LX_SERVO_MAX_US 2600u
#define LX_TRIGGER_NS 12000u         /* the HC-SR04 wants >= 10 µs */
#define LX_LATE_NS (2u * LX_NS_PER_MS)
#define LX_EDGE_HOLD_NS (2u * LX_NS_PER_MS) /* margin for the kernel's queueing of edges */
#define LX_WDOG_PERIOD_NS (10u * LX_NS_PER_MS)
#define LX_PWM_EXPORT_WAIT_MS 1000u

/* Poll slots of the events thread: four encoder lines, the echo, the stop signal. */
enum { LX_POLL_ECHO = 4, LX_POLL_STOP = 5, LX_POLL_N = 6 };

static const char *const lx_wheel_name[2] = {"left", "right"};

static struct {
    lconf_t cfg;
    bool configured;
    bool up;
    char error[320];
    uint64_t (*clock)(void);
    uint64_t t0_ns;

    gpio_chip_t *chip;
    gpio_line_t *line[LCONF_LINES]; /* NULL: not wired */

    pwm_chan_t servo;
    pwm_chan_t motor[2];
    bool servo_started;     /* under the critical section */
    motor_out_t motor_out[2]; /* under the critical section */
    bool standby_on;        /* under the critical section */

    echo_t echo;            /* under lx_sonar_lock */
    edgeq_t edgeq[2];       /* events thread */
    quad_t quad[2];         /* events thread */
    _Atomic uint16_t enc_count[2];
    _Atomic uint32_t enc_edges[2];
    _Atomic uint32_t enc_illegal[2];
    atomic_bool ts_realtime;

    serial_t uart;
    store_t store;

    int timer_fd;
    int stop_fd;
    pthread_t tick_thread;
    pthread_t events_thread;
    pthread_t wdog_thread;
    bool tick_running;
    bool events_running;
    bool wdog_running;
    hal_tick_fn tick_fn;
    void *tick_ctx;
    tickstat_t tickstat;    /* under the critical section */
    bool sched_fifo;

    atomic_bool stop;
    atomic_bool killed;
    atomic_bool tick_started;
    _Atomic uint32_t overruns;
    _Atomic uint64_t last_tick_ns;
    _Atomic uint64_t last_kick_ns;
    atomic_int fault;
    atomic_flag fault_claimed;
    char fault_msg[256];
} lx = {.timer_fd = -1, .stop_fd = -1, .uart = {.fd = -1, .peer_fd = -1}, .store = {.tmp_fd = {-1, -1}}};

/* The lines by role; wheels are hal_wheel_t, encoder lines 0 = A, 1 = B. */
#define LX_ENC(w, ab) lx.line[LCONF_ENC_LEFT_A + 2u * (w) + (ab)]
#define LX_IN1(w) lx.line[LCONF_MOTOR_LEFT_IN1 + 2u * (w)]
#define LX_IN2(w) lx.line[LCONF_MOTOR_LEFT_IN2 + 2u * (w)]
#define LX_TRIGGER lx.line[LCONF_SONAR_TRIGGER]
#define LX_ECHO lx.line[LCONF_SONAR_ECHO]
#define LX_STANDBY lx.line[LCONF_MOTOR_STANDBY]

static pthread_mutex_t lx_crit;
static pthread_once_t lx_crit_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t lx_sonar_lock = PTHREAD_MUTEX_INITIALIZER;

/* ---- time, errors, faults ------------------------------------------------------------ */

static uint64_t lx_mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * LX_NS_PER_S + (uint64_t)ts.tv_nsec;
}

static uint64_t lx_now(void)
{
    return lx.clock != NULL ? lx.clock() : lx_mono_ns();
}

static void lx_crit_init(void)
{
    /* Recursive: the tick holds it while robot_tick() may enter again. Priority
     * inheritance: the SCHED_FIFO tick never waits behind a preempted main thread. */
    pthread_mutexattr_t a;
    pthread_mutexattr_init(&a);
    pthread_mutexattr_settype(&a, PTHREAD_MUTEX_RECURSIVE);
    pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
    pthread_mutex_init(&lx_crit, &a);
    pthread_mutexattr_destroy(&a);
}

__attribute__((format(printf, 1, 2))) static int lx_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(lx.error, sizeof lx.error, fmt, ap);
    va_end(ap);
    return HAL_EIO;
}

/* Stops the motors without a lock, so any thread may call it while another writes. */
static void lx_motors_kill(void)
{
    atomic_store(&lx.killed, true);
    pwm_kill(&lx.motor[HAL_WHEEL_LEFT]);
    pwm_kill(&lx.motor[HAL_WHEEL_RIGHT]);
}

/* The first fault stops the motors and is kept; later ones only stop them again. */
__attribute__((format(printf, 2, 3))) static void lx_fault(lhal_fault_t code, const char *fmt, ...)
{
    lx_motors_kill();
    if (atomic_flag_test_and_set(&lx.fault_claimed)) {
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(lx.fault_msg, sizeof lx.fault_msg, fmt, ap);
    va_end(ap);
    atomic_store(&lx.fault, (int)code);
}

/* ---- threads ------------------------------------------------------------------------- */

/* Starts a thread that leaves the process's stop signals to the main thread, and gives it
 * a real-time priority when asked and permitted. Returns 0 or an errno; *fifo says
 * whether the priority was granted (its errno in *prio_err when not). */
static int lx_spawn(pthread_t *t, void *(*fn)(void *), unsigned prio, bool *fifo, int *prio_err)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGUSR1, SIGUSR2, SIGALRM};
    sigset_t block;
    sigset_t old;
    sigemptyset(&block);
    for (size_t i = 0u; i < sizeof sigs / sizeof sigs[0]; i++) {
        sigaddset(&block, sigs[i]);
    }
    pthread_sigmask(SIG_BLOCK, &block, &old);
    int rc = pthread_create(t, NULL, fn, NULL);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    *fifo = false;
    *prio_err = 0;
    if (rc == 0 && prio > 0u) {
        struct sched_param sp = {.sched_priority = (int)prio};
        *prio_err = pthread_setschedparam(*t, SCHED_FIFO, &sp);
        *fifo = *prio_err == 0;
    }
    return rc;
}

/* Waits a bounded time for a thread; one that is stuck is left behind (the process is
 * about to end) and reported. The motors are already stopped by then. */
static bool lx_join(pthread_t t, const char *name)
{
    struct timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    deadline.tv_sec += 5;
    if (pthread_timedjoin_np(t, NULL, &deadline) == 0) {
        return true;
    }
    fprintf(stderr, "sonarslam-linux: the %s thread does not stop; leaving it\n", name);
    pthread_detach(t);
    return false;
}

/* Hands the held-back edges of a wheel up to a cutoff to its decoder; publishes the count. */
static void lx_decode(unsigned w, uint64_t cutoff_ns)
{
    edgeq_edge_t out[64];
    size_t n;
    while ((n = edgeq_pop_until(&lx.edgeq[w], cutoff_ns, out, 64u)) > 0u) {
        for (size_t i = 0u; i < n; i++) {
            quad_edge(&lx.quad[w], (quad_line_t)out[i].src, out[i].rising);
        }
    }
    atomic_store_explicit(&lx.enc_count[w], lx.quad[w].count, memory_order_relaxed);
    atomic_store_explicit(&lx.enc_edges[w], lx.quad[w].edges, memory_order_relaxed);
    atomic_store_explicit(&lx.enc_illegal[w], lx.quad[w].illegal, memory_order_relaxed);
}

/* Reads one encoder line's queued edges into its wheel's queue. */
static bool lx_read_encoder(unsigned w, unsigned ab, uint64_t now_ns)
{
    edgeq_edge_t buf[16];
    int n = gpio_line_read_edges(LX_ENC(w, ab), (uint8_t)ab, buf, 16u);
    if (n < 0) {
        lx_fault(LHAL_FAULT_IO, "encoder_%s_%c: reading edges failed: %s", lx_wheel_name[w],
                 ab == 0u ? 'a' : 'b', strerror(errno));
        return false;
    }
    for (int i = 0; i < n; i++) {
        /* Kernels before 5.7 stamp edges with CLOCK_REALTIME: no holding back then. */
        if (buf[i].ts_ns > now_ns + LX_NS_PER_S) {
            atomic_store(&lx.ts_realtime, true);
        }
        if (!edgeq_push(&lx.edgeq[w], buf[i])) {
            lx_decode(w, UINT64_MAX);
            (void)edgeq_push(&lx.edgeq[w], buf[i]);
        }
    }
    return true;
}

static bool lx_read_echo(void)
{
    edgeq_edge_t buf[16];
    int n = gpio_line_read_edges(LX_ECHO, 0u, buf, 16u);
    if (n < 0) {
        lx_fault(LHAL_FAULT_IO, "sonar_echo: reading edges failed: %s", strerror(errno));
        return false;
    }
    pthread_mutex_lock(&lx_sonar_lock);
    for (int i = 0; i < n; i++) {
        echo_edge(&lx.echo, buf[i].ts_ns, buf[i].rising);
    }
    pthread_mutex_unlock(&lx_sonar_lock);
    return true;
}

static void *lx_events_main(void *arg)
{
    (void)arg;
    struct pollfd pfd[LX_POLL_N];
    for (unsigned i = 0u; i < 4u; i++) {
        pfd[i] = (struct pollfd){.fd = gpio_line_fd(LX_ENC(i / 2u, i % 2u)), .events = POLLIN};
    }
    pfd[LX_POLL_ECHO] = (struct pollfd){.fd = gpio_line_fd(LX_ECHO), .events = POLLIN};
    pfd[LX_POLL_STOP] = (struct pollfd){.fd = lx.stop_fd, .events = POLLIN};

    while (!atomic_load(&lx.stop)) {
        bool held = !edgeq_empty(&lx.edgeq[0]) || !edgeq_empty(&lx.edgeq[1]);
        int r = poll(pfd, LX_POLL_N, held ? 3 : -1);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r < 0 || (pfd[LX_POLL_STOP].revents & POLLIN)) {
            break;
        }
        for (unsigned i = 0u; i <= LX_POLL_ECHO; i++) {
            if (pfd[i].revents & (POLLERR | POLLHUP | POLLNVAL)) {
                lx_fault(LHAL_FAULT_IO, "a GPIO event descriptor failed (line of %s)",
                         i == LX_POLL_ECHO ? "sonar_echo" : "an encoder");
                return NULL;
            }
        }
        /* Taken before reading, and every encoder line is read, not only those that woke
         * us: an edge stamped before this (less the kernel's queueing margin) is then in
         * the wheel's queue, so releasing up to the cutoff never overtakes an edge of the
         * other line. */
        uint64_t now = lx_mono_ns();
        for (unsigned w = 0u; w < 2u; w++) {
            for (unsigned ab = 0u; ab < 2u; ab++) {
                if (!lx_read_encoder(w, ab, now)) {
                    return NULL;
                }
            }
            bool hold = !atomic_load(&lx.ts_realtime) && now > LX_EDGE_HOLD_NS;
            lx_decode(w, hold ? now - LX_EDGE_HOLD_NS : UINT64_MAX);
        }
        if ((pfd[LX_POLL_ECHO].revents & POLLIN) && !lx_read_echo()) {
            return NULL;
        }
    }
    return NULL;
}

static void *lx_tick_main(void *arg)
{
    (void)arg;
    for (;;) {
        uint64_t expirations = 0u;
        ssize_t r = read(lx.timer_fd, &expirations, sizeof expirations);
        if (atomic_load(&lx.stop)) {
            break;
        }
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r != (ssize_t)sizeof expirations) {
            lx_fault(LHAL_FAULT_IO, "the tick timer failed: %s", strerror(errno));
            break;
        }
        hal_irq_state_t s = hal_critical_enter();
        uint64_t start = lx_mono_ns();
        tickstat_wake(&lx.tickstat, expirations, start);
        lx.tick_fn(lx.tick_ctx);
        tickstat_done(&lx.tickstat, start, lx_mono_ns());
        atomic_store(&lx.overruns, tickstat_faults(&lx.tickstat));
        hal_critical_exit(s);
        atomic_store(&lx.last_tick_ns, lx_now());
    }
    return NULL;
}

static void *lx_wdog_main(void *arg)
{
    (void)arg;
    const wdog_t w = {.tick_limit_ns = WDOG_TICK_LIMIT_NS,
                      .idle_limit_ns = (uint64_t)lx.cfg.watchdog_idle_ms * LX_NS_PER_MS};
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (!atomic_load(&lx.stop)) {
        next.tv_nsec += (long)LX_WDOG_PERIOD_NS;
        if (next.tv_nsec >= (long)LX_NS_PER_S) {
            next.tv_nsec -= (long)LX_NS_PER_S;
            next.tv_sec++;
        }
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
        if (!atomic_load(&lx.tick_started)) {
            continue;
        }
        uint64_t now = lx_now(); /* before the stamps, so a fresh stamp is never "old" */
        uint64_t age = 0u;
        switch (wdog_check(&w, now, atomic_load(&lx.last_tick_ns), atomic_load(&lx.last_kick_ns), &age)) {
        case WDOG_TICK_STALL:
            lx_fault(LHAL_FAULT_WATCHDOG, "watchdog: no control tick for %llu ms; motors stopped",
                     (unsigned long long)(age / LX_NS_PER_MS));
            return NULL;
        case WDOG_IDLE_STALL:
            lx_fault(LHAL_FAULT_WATCHDOG,
                     "watchdog: the background loop stalled for %llu ms (watchdog_idle_ms); motors stopped",
                     (unsigned long long)(age / LX_NS_PER_MS));
            return NULL;
        default:
            break;
        }
    }
    return NULL;
}

/* ---- the backend's own interface ----------------------------------------------------- */

void lhal_configure(const lconf_t *cfg)
{
    lx.cfg = *cfg;
    lx.configured = true;
}

void lhal_set_clock(uint64_t (*now_ns)(void))
{
    lx.clock = now_ns;
}

const char *lhal_error(void)
{
    return lx.error;
}

const char *lhal_telemetry_name(void)
{
    return lx.uart.name;
}

lhal_fault_t lhal_fault(char *msg, size_t msglen)
{
    lhal_fault_t f = (lhal_fault_t)atomic_load(&lx.fault);
    if (f != LHAL_FAULT_NONE && msg != NULL) {
        snprintf(msg, msglen, "%s", lx.fault_msg);
    }
    return f;
}

void lhal_emergency_stop(void)
{
    lx_motors_kill();
}

static void lx_line_set(gpio_line_t *line, int value)
{
    if (line != NULL) {
        (void)gpio_line_set(line, value);
    }
}

void lhal_shutdown(void)
{
    lx_motors_kill(); /* first, and without a lock: a stuck thread must not delay it */
    atomic_store(&lx.stop, true);
    if (lx.stop_fd >= 0) {
        uint64_t one = 1u;
        (void)!write(lx.stop_fd, &one, sizeof one);
    }
    bool joined = true;
    if (lx.tick_running) {
        joined = lx_join(lx.tick_thread, "tick") && joined;
    }
    if (lx.events_running) {
        joined = lx_join(lx.events_thread, "events") && joined;
    }
    if (lx.wdog_running) {
        joined = lx_join(lx.wdog_thread, "watchdog") && joined;
    }
    lx.tick_running = lx.events_running = lx.wdog_running = false;
    atomic_store(&lx.tick_started, false);
    if (!joined) {
        /* A stuck thread may still use the lines: the process ends and the kernel frees them. */
        lx.up = false;
        return;
    }
    for (unsigned w = 0u; w < 2u; w++) {
        lx_line_set(LX_IN1(w), 0);
        lx_line_set(LX_IN2(w), 0);
    }
    lx_line_set(LX_STANDBY, 0);
    if (lx.servo_started) {
        (void)pwm_stop(&lx.servo);
        lx.servo_started = false;
    }
    if (lx.timer_fd >= 0) {
        close(lx.timer_fd);
        lx.timer_fd = -1;
    }
    if (lx.stop_fd >= 0) {
        close(lx.stop_fd);
        lx.stop_fd = -1;
    }
    serial_close(&lx.uart);
    store_close(&lx.store);
    gpio_chip_close(lx.chip);
    lx.chip = NULL;
    memset(lx.line, 0, sizeof lx.line);
    lx.up = false;
}

void lhal_stats(lhal_stats_t *out)
{
    *out = (lhal_stats_t){0};
    hal_irq_state_t s = hal_critical_enter();
    out->tick = lx.tickstat;
    out->uart_sent = lx.uart.sent;
    out->uart_dropped = lx.uart.dropped;
    hal_critical_exit(s);
    out->sched_fifo = lx.sched_fifo;
    for (unsigned w = 0u; w < 2u; w++) {
        out->enc_count[w] = atomic_load(&lx.enc_count[w]);
        out->enc_edges[w] = atomic_load(&lx.enc_edges[w]);
        out->enc_illegal[w] = atomic_load(&lx.enc_illegal[w]);
    }
    pthread_mutex_lock(&lx_sonar_lock);
    out->sonar = lx.echo;
    pthread_mutex_unlock(&lx_sonar_lock);
    out->kernel_ts_realtime = atomic_load(&lx.ts_realtime);
}

void lhal_report(FILE *f)
{
    lhal_stats_t s;
    lhal_stats(&s);
    fprintf(f,
            "ticks: %llu run (%s), %u late (> 2 ms), %u overran, %u missed; worst latency %llu us, "
            "longest tick %llu us\n",
            (unsigned long long)s.tick.ticks, s.sched_fifo ? "SCHED_FIFO" : "normal scheduling",
            (unsigned)s.tick.late, (unsigned)s.tick.overruns, (unsigned)s.tick.missed,
            (unsigned long long)(s.tick.max_latency_ns / LX_NS_PER_US),
            (unsigned long long)(s.tick.max_run_ns / LX_NS_PER_US));
    for (unsigned w = 0u; w < 2u; w++) {
        fprintf(f, "encoder %s: count %u, %u edges, %u illegal or lost\n", lx_wheel_name[w],
                (unsigned)s.enc_count[w], (unsigned)s.enc_edges[w], (unsigned)s.enc_illegal[w]);
    }
    fprintf(f,
            "sonar: %u pings, %u echoes, %u out of range, %u unanswered, %u too long, "
            "%u with the echo stuck high, %u stray edges\n",
            (unsigned)s.sonar.pings, (unsigned)s.sonar.echoes, (unsigned)s.sonar.out_of_range,
            (unsigned)s.sonar.no_response, (unsigned)s.sonar.long_echo,
            (unsigned)s.sonar.stuck_high, (unsigned)s.sonar.stray);
    fprintf(f, "telemetry: %llu bytes sent, %llu dropped\n", (unsigned long long)s.uart_sent,
            (unsigned long long)s.uart_dropped);
    if (s.kernel_ts_realtime) {
        fprintf(f, "note: the kernel stamps GPIO edges with CLOCK_REALTIME (Linux < 5.7)\n");
    }
}

/* ---- hal.h ---------------------------------------------------------------------------- */

static int lx_open_lines(void)
{
    const lconf_t *c = &lx.cfg;
    char msg[200];
    if (gpio_chip_open(c->gpio_chip, &lx.chip, msg, sizeof msg) != 0) {
        return lx_fail("gpio_chip: %s", msg);
    }
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(c, lines);
    for (unsigned i = 0u; i < LCONF_LINES; i++) {
        if (lines[i].offset == LCONF_NO_LINE) {
            continue; /* an optional line that is not wired */
        }
        unsigned off = (unsigned)lines[i].offset;
        int rc = lines[i].bias == LCONF_OUTPUT
                     ? gpio_line_output(lx.chip, off, 0, &lx.line[i], msg, sizeof msg)
                     : gpio_line_edges(lx.chip, off, (lconf_bias_t)lines[i].bias, &lx.line[i], msg,
                                       sizeof msg);
        if (rc != 0) {
            return lx_fail("%s: %s", lines[i].name, msg);
        }
    }
    for (unsigned w = 0u; w < 2u; w++) {
        int a = gpio_line_get(LX_ENC(w, 0u));
        int b = gpio_line_get(LX_ENC(w, 1u));
        if (a < 0 || b < 0) {
            return lx_fail("encoder_%s: cannot read the lines: %s", lx_wheel_name[w], strerror(errno));
        }
        quad_init(&lx.quad[w], a == 1, b == 1, c->enc_invert[w]);
        edgeq_init(&lx.edgeq[w]);
        atomic_store(&lx.enc_count[w], (uint16_t)0u);
        atomic_store(&lx.enc_edges[w], 0u);
        atomic_store(&lx.enc_illegal[w], 0u);
    }
    int e = gpio_line_get(LX_ECHO);
    if (e < 0) {
        return lx_fail("sonar_echo: cannot read the line: %s", strerror(errno));
    }
    pthread_mutex_lock(&lx_sonar_lock);
    echo_init(&lx.echo, c->sonar_timeout_us, e == 1);
    pthread_mutex_unlock(&lx_sonar_lock);
    return HAL_OK;
}

static int lx_open_pwm(void)
{
    const lconf_t *c = &lx.cfg;
    char msg[240];
    static const char *const motor_keys[2] = {"motor_left", "motor_right"};
    for (unsigned w = 0u; w < 2u; w++) {
        if (pwm_open(&lx.motor[w], c->pwm_root, (unsigned)c->motor_pwm[w].chip,
                     (unsigned)c->motor_pwm[w].channel, LX_PWM_EXPORT_WAIT_MS, msg, sizeof msg) != 0) {
            return lx_fail("%s_pwm: %s", motor_keys[w], msg);
        }
        int rc = pwm_start(&lx.motor[w], c->motor_period_ns, 0u);
        if (rc != 0) {
            return lx_fail("%s_pwm: cannot start %s at period %u ns: %s", motor_keys[w],
                           lx.motor[w].dir, (unsigned)c->motor_period_ns, strerror(-rc));
        }
        lx.motor_out[w] = (motor_out_t){0};
    }
    /* The servo's PWM starts with its first command, so it does not jump at start-up. */
    if (pwm_open(&lx.servo, c->pwm_root, (unsigned)c->servo_pwm.chip,
                 (unsigned)c->servo_pwm.channel, LX_PWM_EXPORT_WAIT_MS, msg, sizeof msg) != 0) {
        return lx_fail("servo_pwm: %s", msg);
    }
    lx.servo_started = false;
    lx.standby_on = false;
    return HAL_OK;
}

static int lx_init(void)
{
    char msg[240];
    int rc = lx_open_lines();
    rc = rc == HAL_OK ? lx_open_pwm() : rc;
    if (rc != HAL_OK) {
        return rc;
    }
    if (store_open(&lx.store, lx.cfg.storage_dir, lx.cfg.storage_bytes, msg, sizeof msg) != 0) {
        return lx_fail("%s", msg);
    }
    if (serial_open(&lx.uart, lx.cfg.telemetry, lx.cfg.telemetry_baud, msg, sizeof msg) != 0) {
        return lx_fail("%s", msg);
    }
    lx.stop_fd = eventfd(0u, EFD_CLOEXEC);
    if (lx.stop_fd < 0) {
        return lx_fail("eventfd: %s", strerror(errno));
    }
    bool fifo;
    int prio_err;
    unsigned prio = lx.cfg.tick_priority;
    if (lx_spawn(&lx.events_thread, lx_events_main, prio, &fifo, &prio_err) != 0) {
        return lx_fail("cannot start the events thread");
    }
    lx.events_running = true;
    /* Above the tick, so a runaway tick cannot starve the thread that stops the motors. */
    if (lx_spawn(&lx.wdog_thread, lx_wdog_main, prio > 0u ? prio + 1u : 0u, &fifo, &prio_err) != 0) {
        return lx_fail("cannot start the watchdog thread");
    }
    lx.wdog_running = true;
    return HAL_OK;
}

int hal_init(void)
{
    pthread_once(&lx_crit_once, lx_crit_init);
    if (lx.up) {
        return HAL_OK;
    }
    if (!lx.configured) {
        return lx_fail("no configuration (lhal_configure() was not called)");
    }
    lx.error[0] = '\0';
    atomic_store(&lx.stop, false);
    atomic_store(&lx.killed, false);
    atomic_store(&lx.tick_started, false);
    atomic_store(&lx.ts_realtime, false);
    atomic_store(&lx.overruns, 0u);
    atomic_store(&lx.fault, LHAL_FAULT_NONE);
    atomic_flag_clear(&lx.fault_claimed);
    memset(&lx.tickstat, 0, sizeof lx.tickstat);
    lx.sched_fifo = false;
    lx.t0_ns = lx_now();
    int rc = lx_init();
    if (rc != HAL_OK) {
        char why[sizeof lx.error];
        memcpy(why, lx.error, sizeof why);
        lhal_shutdown();
        memcpy(lx.error, why, sizeof why);
        return rc;
    }
    lx.up = true;
    return HAL_OK;
}

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    if (fn == NULL) {
        return HAL_EINVAL;
    }
    if (!lx.up) {
        return lx_fail("hal_tick_start() before hal_init()");
    }
    if (lx.tick_running) {
        return HAL_EBUSY;
    }
    lx.timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
    if (lx.timer_fd < 0) {
        return lx_fail("timerfd_create: %s", strerror(errno));
    }
    uint64_t first = lx_mono_ns() + LX_TICK_NS;
    struct itimerspec its = {
        .it_interval = {.tv_sec = 0, .tv_nsec = (long)LX_TICK_NS},
        .it_value = {.tv_sec = (time_t)(first / LX_NS_PER_S), .tv_nsec = (long)(first % LX_NS_PER_S)},
    };
    if (timerfd_settime(lx.timer_fd, TFD_TIMER_ABSTIME, &its, NULL) != 0) {
        return lx_fail("timerfd_settime: %s", strerror(errno));
    }
    tickstat_init(&lx.tickstat, LX_TICK_NS, LX_LATE_NS, first);
    lx.tick_fn = fn;
    lx.tick_ctx = ctx;
    atomic_store(&lx.last_tick_ns, lx_now());
    atomic_store(&lx.last_kick_ns, lx_now());
    atomic_store(&lx.tick_started, true);
    int prio_err;
    if (lx_spawn(&lx.tick_thread, lx_tick_main, lx.cfg.tick_priority, &lx.sched_fifo, &prio_err) != 0) {
        atomic_store(&lx.tick_started, false);
        return lx_fail("cannot start the tick thread");
    }
    lx.tick_running = true;
    if (lx.cfg.tick_priority > 0u && !lx.sched_fifo) {
        fprintf(stderr,
                "sonarslam-linux: warning: SCHED_FIFO priority %u refused (%s); the tick runs with "
                "normal scheduling and may be late under load. Run as root, or allow real-time "
                "priorities (CAP_SYS_NICE, or 'ulimit -r %u'), or set tick_priority = 0.\n",
                (unsigned)lx.cfg.tick_priority, strerror(prio_err), (unsigned)lx.cfg.tick_priority);
    }
    return HAL_OK;
}

uint32_t hal_time_us(void)
{
    return (uint32_t)((lx_now() - lx.t0_ns) / LX_NS_PER_US);
}

uint32_t hal_tick_overruns(void)
{
    return atomic_load(&lx.overruns);
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    return wheel <= HAL_WHEEL_RIGHT ? atomic_load_explicit(&lx.enc_count[wheel], memory_order_relaxed)
                                    : 0u;
}

/* STBY of a TB6612-style driver: high while a motor runs, low otherwise. */
static int lx_standby_update(void)
{
    bool on = !atomic_load(&lx.killed) &&
              (lx.motor_out[0].duty_ns != 0u || lx.motor_out[1].duty_ns != 0u);
    if (LX_STANDBY == NULL || on == lx.standby_on) {
        return 0;
    }
    lx.standby_on = on;
    return gpio_line_set(LX_STANDBY, on);
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    if (!lx.up || wheel > HAL_WHEEL_RIGHT) {
        return;
    }
    hal_irq_state_t s = hal_critical_enter();
    if (atomic_load(&lx.killed)) {
        duty = 0;
    }
    motor_out_t want = motor_plan(duty, lx.cfg.motor_invert[wheel], lx.cfg.motor_period_ns);
    motor_out_t *have = &lx.motor_out[wheel];
    int rc = 0;
    if (!motor_same_direction(*have, want)) {
        /* Never drive the new direction at the old duty: stop, turn, then go. */
        rc = pwm_set_duty(&lx.motor[wheel], 0u);
        if (rc == 0 && gpio_line_set(LX_IN1(wheel), want.in1) != 0) {
            rc = -errno;
        }
        if (rc == 0 && LX_IN2(wheel) != NULL && gpio_line_set(LX_IN2(wheel), want.in2) != 0) {
            rc = -errno;
        }
    }
    rc = rc == 0 ? pwm_set_duty(&lx.motor[wheel], want.duty_ns) : rc;
    if (rc == 0) {
        *have = want;
        rc = lx_standby_update() == 0 ? 0 : -errno;
    }
    hal_critical_exit(s);
    if (rc != 0) {
        lx_fault(LHAL_FAULT_IO, "motor_%s: %s", lx_wheel_name[wheel], strerror(-rc));
    }
    if (atomic_load(&lx.killed)) {
        /* The watchdog may have stopped the motors while this write was under way. */
        pwm_kill(&lx.motor[wheel]);
    }
}

void hal_servo_set_pulse(uint16_t pulse_us)
{
    if (!lx.up) {
        return;
    }
    uint32_t us = pulse_us < LX_SERVO_MIN_US ? LX_SERVO_MIN_US
                                             : (pulse_us > LX_SERVO_MAX_US ? LX_SERVO_MAX_US : pulse_us);
    hal_irq_state_t s = hal_critical_enter();
    int rc;
    if (lx.servo_started) {
        rc = pwm_set_duty(&lx.servo, us * LX_NS_PER_US);
    } else {
        rc = pwm_start(&lx.servo, LX_SERVO_PERIOD_NS, us * LX_NS_PER_US);
        lx.servo_started = rc == 0;
    }
    hal_critical_exit(s);
    if (rc != 0) {
        lx_fault(LHAL_FAULT_IO, "servo_pwm: writing %s failed: %s", lx.servo.dir, strerror(-rc));
    }
}

int hal_sonar_trigger(void)
{
    if (!lx.up) {
        return HAL_EIO;
    }
    pthread_mutex_lock(&lx_sonar_lock);
    int rc = echo_trigger(&lx.echo, lx_now());
    pthread_mutex_unlock(&lx_sonar_lock);
    if (rc != HAL_OK) {
        return rc;
    }
    /* Armed before the pulse, so the rising edge that follows it is taken as the echo. */
    if (gpio_line_set(LX_TRIGGER, 1) != 0) {
        lx_fault(LHAL_FAULT_IO, "sonar_trigger: %s", strerror(errno));
        return HAL_EIO;
    }
    uint64_t t = lx_mono_ns();
    while (lx_mono_ns() - t < LX_TRIGGER_NS) {
        /* 12 µs: shorter than any sleep's wake-up latency, so spin. */
    }
    if (gpio_line_set(LX_TRIGGER, 0) != 0) {
        lx_fault(LHAL_FAULT_IO, "sonar_trigger: %s", strerror(errno));
        return HAL_EIO;
    }
    return HAL_OK;
}

hal_sonar_status_t hal_sonar_poll(uint32_t *echo_us)
{
    if (!lx.up) {
        return HAL_SONAR_IDLE;
    }
    pthread_mutex_lock(&lx_sonar_lock);
    hal_sonar_status_t st = echo_poll(&lx.echo, lx_now(), echo_us);
    pthread_mutex_unlock(&lx_sonar_lock);
    return st;
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    if (!lx.up) {
        return 0u;
    }
    hal_irq_state_t s = hal_critical_enter();
    size_t n = serial_write(&lx.uart, data, len);
    hal_critical_exit(s);
    return n;
}

size_t hal_uart_read(uint8_t *data, size_t len)
{
    return lx.up ? serial_read(&lx.uart, data, len) : 0u;
}

size_t hal_storage_size(void)
{
    return lx.up ? lx.store.size : 0u;
}

int hal_storage_begin(uint8_t slot)
{
    return lx.up ? store_begin(&lx.store, slot) : HAL_ENOSYS;
}

int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    return lx.up ? store_write(&lx.store, slot, offset, data, len) : HAL_ENOSYS;
}

int hal_storage_commit(uint8_t slot)
{
    return lx.up ? store_commit(&lx.store, slot) : HAL_ENOSYS;
}

int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    return lx.up ? store_read(&lx.store, slot, offset, data, len) : HAL_ENOSYS;
}

hal_irq_state_t hal_critical_enter(void)
{
    pthread_once(&lx_crit_once, lx_crit_init);
    pthread_mutex_lock(&lx_crit);
    return 0u;
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
    pthread_mutex_unlock(&lx_crit);
}

void hal_watchdog_kick(void)
{
    atomic_store(&lx.last_kick_ns, lx_now());
}

/* ---- --check --------------------------------------------------------------------------- */

static unsigned lx_check_item(FILE *out, const char *what, int ok, const char *detail)
{
    fprintf(out, "  %-24s %s%s\n", what, ok ? "ok" : "FAIL: ", ok ? (detail[0] ? detail : "") : detail);
    return ok ? 0u : 1u;
}

unsigned lhal_check(const lconf_t *cfg, FILE *out)
{
    unsigned bad = 0u;
    unsigned items = 0u;
    char msg[256];
    char detail[600];

    gpio_chip_t *chip = NULL;
    int ok = gpio_chip_open(cfg->gpio_chip, &chip, msg, sizeof msg) == 0;
    if (ok) {
        snprintf(detail, sizeof detail, " (%s, %u lines)", gpio_chip_describe(chip), gpio_chip_lines(chip));
    }
    bad += lx_check_item(out, "gpio_chip", ok, ok ? detail : msg);
    items++;
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(cfg, lines);
    for (unsigned i = 0u; i < LCONF_LINES; i++) {
        if (lines[i].offset == LCONF_NO_LINE) {
            continue;
        }
        items++;
        if (chip == NULL) {
            bad += lx_check_item(out, lines[i].name, 0, "not checked: no GPIO chip");
            continue;
        }
        gpio_line_t *line = NULL;
        unsigned off = (unsigned)lines[i].offset;
        bool input = lines[i].bias != LCONF_OUTPUT;
        ok = (input ? gpio_line_edges(chip, off, (lconf_bias_t)lines[i].bias, &line, msg, sizeof msg)
                    : gpio_line_output(chip, off, 0, &line, msg, sizeof msg)) == 0;
        if (ok && input) {
            snprintf(detail, sizeof detail, " (line %u, input, now %s)", off,
                     gpio_line_get(line) == 1 ? "high" : "low");
        } else if (ok) {
            snprintf(detail, sizeof detail, " (line %u, output, held low)", off);
        }
        bad += lx_check_item(out, lines[i].name, ok, ok ? detail : msg);
    }
    gpio_chip_close(chip);

    const struct {
        const char *name;
        lconf_pwm_t pwm;
    } pwms[] = {{"servo_pwm", cfg->servo_pwm}, {"motor_left_pwm", cfg->motor_pwm[0]},
                {"motor_right_pwm", cfg->motor_pwm[1]}};
    for (unsigned i = 0u; i < 3u; i++) {
        pwm_chan_t p;
        items++;
        ok = pwm_open(&p, cfg->pwm_root, (unsigned)pwms[i].pwm.chip, (unsigned)pwms[i].pwm.channel,
                      LX_PWM_EXPORT_WAIT_MS, msg, sizeof msg) == 0 &&
             pwm_writable(&p, msg, sizeof msg) == 0;
        snprintf(detail, sizeof detail, " (%s)", p.dir);
        bad += lx_check_item(out, pwms[i].name, ok, ok ? detail : msg);
    }

    serial_t uart;
    items++;
    ok = serial_open(&uart, cfg->telemetry, cfg->telemetry_baud, msg, sizeof msg) == 0;
    snprintf(detail, sizeof detail, " (%s)", uart.name);
    bad += lx_check_item(out, "telemetry", ok, ok ? detail : msg);
    serial_close(&uart);

    items++;
    ok = store_probe(cfg->storage_dir, msg, sizeof msg) == 0;
    snprintf(detail, sizeof detail, " (%s: %s)", cfg->storage_dir, msg);
    bad += lx_check_item(out, "storage_dir", ok, ok ? detail : msg);

    if (bad == 0u) {
        fprintf(out, "check: all %u items ok\n", items);
    } else {
        fprintf(out, "check: %u of %u items failed\n", bad, items);
    }
    return bad;
}
