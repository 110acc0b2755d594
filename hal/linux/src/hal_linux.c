/* SPDX-License-Identifier: MIT */
/* hal.h on a Linux single-board computer: start-up, shutdown, the critical section, inputs,
 * storage. */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "lx.h"

#define LX_TICK_NS ((uint64_t)HAL_TICK_PERIOD_US * LX_NS_PER_US)
#define LX_LATE_NS (2u * LX_NS_PER_MS)
#define LX_IDLE_WAIT_NS (20u * LX_NS_PER_MS) /* lhal_idle_lock()'s longest wait */

lx_t lx = {.timer_fd = -1,
           .stop_fd = -1,
           .out_fd = -1,
           .kill_fd = -1,
           .uart = {.fd = -1, .peer_fd = -1},
           .store = {.tmp_fd = {-1, -1}},
           .servos = 1u,
           .sonars = 1u};
pthread_mutex_t lx_crit;
pthread_mutex_t lx_sonar_lock;
const char *const lx_wheel_name[2] = {"left", "right"};

static pthread_once_t lx_locks_once = PTHREAD_ONCE_INIT;
/* This thread's holds of lx_crit, and whether lhal_idle_lock() is one of them. */
static _Thread_local unsigned lx_crit_depth;
static _Thread_local bool lx_idle_holds;

/* ---- time, errors, locks --------------------------------------------------------------- */

uint64_t lx_mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * LX_NS_PER_S + (uint64_t)ts.tv_nsec;
}

uint64_t lx_now(void)
{
    return lx.clock != NULL ? lx.clock() : lx_mono_ns();
}

static void lx_locks_init(void)
{
    /* Priority inheritance on both: the SCHED_FIFO tick never waits behind a normal-priority
     * thread that a third one preempted. lx_crit is recursive: the tick holds it while
     * robot_tick() may enter again. */
    pthread_mutexattr_t a;
    pthread_mutexattr_init(&a);
    pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
    pthread_mutex_init(&lx_sonar_lock, &a);
    pthread_mutexattr_settype(&a, PTHREAD_MUTEX_RECURSIVE);
    pthread_mutex_init(&lx_crit, &a);
    pthread_mutexattr_destroy(&a);
}

int lx_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(lx.error, sizeof lx.error, fmt, ap);
    va_end(ap);
    return HAL_EIO;
}

hal_irq_state_t hal_critical_enter(void)
{
    pthread_once(&lx_locks_once, lx_locks_init);
    pthread_mutex_lock(&lx_crit);
    lx_crit_depth++;
    return 0u;
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
    lx_crit_depth--;
    pthread_mutex_unlock(&lx_crit);
}

int lhal_idle_lock(void)
{
    pthread_once(&lx_locks_once, lx_locks_init);
    struct timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    uint64_t ns = (uint64_t)deadline.tv_nsec + LX_IDLE_WAIT_NS;
    deadline.tv_sec += (time_t)(ns / LX_NS_PER_S);
    deadline.tv_nsec = (long)(ns % LX_NS_PER_S);
    if (pthread_mutex_timedlock(&lx_crit, &deadline) != 0) {
        return HAL_EBUSY;
    }
    lx_crit_depth++;
    lx_idle_holds = lx_crit_depth == 1u;
    return HAL_OK;
}

void lhal_idle_unlock(void)
{
    lx_idle_holds = false;
    hal_critical_exit(0u);
}

/* Blocking file I/O that robot_idle() calls inside lhal_idle_lock() lets the tick in
 * meanwhile, as an MCU's tick interrupts its background loop. Not when robot_idle() holds
 * a critical section of its own: it keeps the tick out as it asked. The calls touch only
 * their arguments (mapstore hands them copies) and the store, never what the tick writes. */
static bool lx_io_begin(void)
{
    if (!lx_idle_holds || lx_crit_depth != 1u) {
        return false;
    }
    lx_crit_depth = 0u;
    pthread_mutex_unlock(&lx_crit);
    return true;
}

static void lx_io_end(bool released)
{
    if (released) {
        pthread_mutex_lock(&lx_crit);
        lx_crit_depth = 1u;
    }
}

/* ---- the backend's own interface ----------------------------------------------------- */

void lhal_configure(const lconf_t *cfg)
{
    lx.cfg = *cfg;
    lx.servos = lconf_servos(cfg);
    lx.sonars = lconf_sonars(cfg);
    lx.bumps = lconf_bumps(cfg);
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
    lx_kill();
}

void lhal_signal_stop(void)
{
    atomic_store(&lx.killed, true);
    atomic_store(&lx.kill_asked, true);
    lx_wake(atomic_load(&lx.kill_fd));
}

static void lx_close(int *fd)
{
    if (*fd >= 0) {
        close(*fd);
        *fd = -1;
    }
}

bool lhal_shutdown(void)
{
    /* The motors first, and without a lock: the lines here and now, the PWM by the
     * watchdog thread (a PWM chip that hangs then holds that thread, not this one). */
    atomic_store(&lx.killed, true);
    lx_lines_low();
    atomic_store(&lx.kill_asked, true);
    lx_wake(atomic_load(&lx.kill_fd));
    atomic_store(&lx.stop, true);
    lx_wake(lx.stop_fd);
    bool joined = lx_join(&lx.tick, "tick");
    joined = lx_join(&lx.events, "events") && joined;
    joined = lx_join(&lx.output, "output") && joined;
    joined = lx_join(&lx.wdog, "watchdog") && joined;
    atomic_store(&lx.tick_started, false);
    if (!joined) {
        /* A stuck thread may still use the lines: the process ends and the kernel frees them. */
        lx.up = false;
        return false;
    }
    if (!atomic_load(&lx.pwm_dead)) {
        lx_kill(); /* no watchdog did it (hal_init() failed before starting one) */
    }
    lx_lines_low();
    for (unsigned i = 0u; i < LCONF_SERVOS; i++) {
        if (lx.servo_started[i]) {
            (void)pwm_stop(&lx.servo[i]);
            lx.servo_started[i] = false;
        }
    }
    lx_close(&lx.timer_fd);
    lx_close(&lx.stop_fd);
    lx_close(&lx.out_fd);
    int kfd = atomic_exchange(&lx.kill_fd, -1);
    lx_close(&kfd);
    serial_close(&lx.uart);
    store_close(&lx.store);
    atomic_store(&lx.lines_live, false);
    gpio_chip_close(lx.chip);
    lx.chip = NULL;
    memset(lx.line, 0, sizeof lx.line);
    lx.up = false;
    return true;
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
    out->sonars = lx.sonars;
    pthread_mutex_lock(&lx_sonar_lock);
    memcpy(out->sonar, lx.echo, sizeof out->sonar);
    pthread_mutex_unlock(&lx_sonar_lock);
    out->bumps = lx.bumps;
    out->bump_high = atomic_load(&lx.bump_high);
    out->kernel_ts_realtime = atomic_load(&lx.ts_realtime);
    out->events_rounds = atomic_load(&lx.events.rounds);
    out->output_rounds = atomic_load(&lx.output.rounds);
    out->outputs_posted = atomic_load(&lx.posted);
    out->outputs_written = atomic_load(&lx.applied);
    out->output_writing = atomic_load(&lx.doing);
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
    for (unsigned i = 0u; i < s.sonars; i++) {
        const echo_t *e = &s.sonar[i];
        fprintf(f,
                "sonar%s: %u pings, %u echoes, %u out of range, %u unanswered, %u too long, "
                "%u with the echo stuck high, %u stray edges\n",
                i == 0u ? "" : " 1", (unsigned)e->pings, (unsigned)e->echoes,
                (unsigned)e->out_of_range, (unsigned)e->no_response, (unsigned)e->long_echo,
                (unsigned)e->stuck_high, (unsigned)e->stray);
    }
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
    atomic_store(&lx.lines_live, true);
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
            return lx_fail("encoder_%s: cannot read the lines: %s", lx_wheel_name[w],
                           strerror(errno));
        }
        quad_init(&lx.quad[w], a == 1, b == 1, c->enc_invert[w]);
        edgeq_init(&lx.edgeq[w]);
        atomic_store(&lx.enc_count[w], (uint16_t)0u);
        atomic_store(&lx.enc_edges[w], 0u);
        atomic_store(&lx.enc_illegal[w], 0u);
    }
    for (unsigned i = 0u; i < lx.sonars; i++) {
        int e = gpio_line_get(LX_ECHO(i));
        if (e < 0) {
            return lx_fail("%s: cannot read the line: %s", i == 0u ? "sonar_echo" : "sonar1_echo",
                           strerror(errno));
        }
        pthread_mutex_lock(&lx_sonar_lock);
        echo_init(&lx.echo[i], c->sonar_timeout_us, e == 1);
        pthread_mutex_unlock(&lx_sonar_lock);
    }
    uint32_t high = 0u;
    for (unsigned i = 0u; i < lx.bumps; i++) {
        int level = gpio_line_get(LX_BUMP(i));
        if (level < 0) {
            return lx_fail("bump%u: cannot read the line: %s", i, strerror(errno));
        }
        high |= level == 1 ? 1u << i : 0u;
    }
    atomic_store(&lx.bump_high, high);
    return HAL_OK;
}

static int lx_open_pwm(void)
{
    const lconf_t *c = &lx.cfg;
    char msg[240];
    static const char *const motor_keys[2] = {"motor_left", "motor_right"};
    for (unsigned w = 0u; w < 2u; w++) {
        if (pwm_open(&lx.motor[w], c->pwm_root, (unsigned)c->motor_pwm[w].chip,
                     (unsigned)c->motor_pwm[w].channel, PWM_EXPORT_WAIT_MS, msg, sizeof msg) != 0) {
            return lx_fail("%s_pwm: %s", motor_keys[w], msg);
        }
        int rc = pwm_start(&lx.motor[w], c->motor_period_ns, 0u);
        if (rc != 0) {
            return lx_fail("%s_pwm: cannot start %s at period %u ns: %s", motor_keys[w],
                           lx.motor[w].dir, (unsigned)c->motor_period_ns, strerror(-rc));
        }
        lx.motor_out[w] = (motor_out_t){0};
    }
    /* A servo's PWM starts with its first command, so it does not jump at start-up. */
    const lconf_pwm_t servo_pwm[LCONF_SERVOS] = {c->servo_pwm, c->servo1_pwm};
    for (unsigned i = 0u; i < lx.servos; i++) {
        if (pwm_open(&lx.servo[i], c->pwm_root, (unsigned)servo_pwm[i].chip,
                     (unsigned)servo_pwm[i].channel, PWM_EXPORT_WAIT_MS, msg, sizeof msg) != 0) {
            return lx_fail("%s: %s", i == 0u ? "servo_pwm" : "servo1_pwm", msg);
        }
    }
    return HAL_OK;
}

static int lx_eventfd(int *fd)
{
    *fd = eventfd(0u, EFD_CLOEXEC);
    return *fd >= 0 ? HAL_OK : lx_fail("eventfd: %s", strerror(errno));
}

static int lx_init(void)
{
    char msg[240];
    int kfd = -1;
    int rc = lx_eventfd(&lx.stop_fd);
    rc = rc == HAL_OK ? lx_eventfd(&lx.out_fd) : rc;
    rc = rc == HAL_OK ? lx_eventfd(&kfd) : rc;
    atomic_store(&lx.kill_fd, kfd);
    rc = rc == HAL_OK ? lx_open_lines() : rc;
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
    bool fifo;
    int prio_err;
    unsigned prio = lx.cfg.tick_priority;
    if (lx_spawn(&lx.events, lx_events_main, prio, &fifo, &prio_err) != 0 ||
        lx_spawn(&lx.output, lx_output_main, prio, &fifo, &prio_err) != 0) {
        return lx_fail("cannot start the events and output threads");
    }
    /* Above the tick, so a runaway tick cannot starve the thread that stops the motors. */
    if (lx_spawn(&lx.wdog, lx_wdog_main, prio > 0u ? prio + 1u : 0u, &fifo, &prio_err) != 0) {
        return lx_fail("cannot start the watchdog thread");
    }
    return HAL_OK;
}

int hal_init(void)
{
    pthread_once(&lx_locks_once, lx_locks_init);
    if (lx.up) {
        return HAL_OK;
    }
    if (!lx.configured) {
        return lx_fail("no configuration (lhal_configure() was not called)");
    }
    lx.error[0] = '\0';
    atomic_store(&lx.stop, false);
    atomic_store(&lx.killed, false);
    atomic_store(&lx.kill_asked, false);
    atomic_store(&lx.pwm_dead, false);
    atomic_store(&lx.pwm_failed, false);
    atomic_store(&lx.tick_started, false);
    atomic_store(&lx.ts_realtime, false);
    atomic_store(&lx.overruns, 0u);
    atomic_store(&lx.fault, LHAL_FAULT_NONE);
    atomic_flag_clear(&lx.fault_claimed);
    atomic_store(&lx.want_duty[0], 0);
    atomic_store(&lx.want_duty[1], 0);
    for (unsigned i = 0u; i < LCONF_SERVOS; i++) {
        atomic_store(&lx.want_servo_us[i], 0u);
        lx.servo_started[i] = false;
        lx.servo_us[i] = 0u;
    }
    for (unsigned i = 0u; i < LCONF_SONARS; i++) {
        atomic_store(&lx.want_triggers[i], 0u);
        lx.triggers[i] = 0u;
    }
    atomic_store(&lx.bump_high, 0u);
    atomic_store(&lx.posted, 0u);
    atomic_store(&lx.applied, 0u);
    atomic_store(&lx.doing, NULL);
    lx.standby_on = false;
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
    if (lx.tick.running) {
        return HAL_EBUSY;
    }
    lx.timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
    if (lx.timer_fd < 0) {
        return lx_fail("timerfd_create: %s", strerror(errno));
    }
    uint64_t first = lx_mono_ns() + LX_TICK_NS;
    struct itimerspec its = {
        .it_interval = {.tv_sec = 0, .tv_nsec = (long)LX_TICK_NS},
        .it_value = {.tv_sec = (time_t)(first / LX_NS_PER_S),
                     .tv_nsec = (long)(first % LX_NS_PER_S)},
    };
    if (timerfd_settime(lx.timer_fd, TFD_TIMER_ABSTIME, &its, NULL) != 0) {
        return lx_fail("timerfd_settime: %s", strerror(errno));
    }
    tickstat_init(&lx.tickstat, LX_TICK_NS, LX_LATE_NS, first);
    lx.tick_fn = fn;
    lx.tick_ctx = ctx;
    atomic_store(&lx.last_kick_ns, lx_now());
    int prio_err;
    if (lx_spawn(&lx.tick, lx_tick_main, lx.cfg.tick_priority, &lx.sched_fifo, &prio_err) != 0) {
        return lx_fail("cannot start the tick thread");
    }
    atomic_store(&lx.tick_started, true);
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
    return wheel <= HAL_WHEEL_RIGHT
               ? atomic_load_explicit(&lx.enc_count[wheel], memory_order_relaxed)
               : 0u;
}

uint8_t hal_servo_count(void)
{
    return (uint8_t)lx.servos;
}

uint8_t hal_sonar_count(void)
{
    return (uint8_t)lx.sonars;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar >= lx.sonars) {
        return HAL_EINVAL;
    }
    if (!lx.up) {
        return HAL_SONAR_IDLE;
    }
    pthread_mutex_lock(&lx_sonar_lock);
    hal_sonar_status_t st = echo_poll(&lx.echo[sonar], lx_now(), echo_us);
    pthread_mutex_unlock(&lx_sonar_lock);
    return (int)st;
}

uint8_t hal_bump_count(void)
{
    return (uint8_t)lx.bumps;
}

int hal_bump_read(uint8_t bump, bool *pressed)
{
    if (lx.bumps == 0u) {
        return HAL_ENOSYS;
    }
    if (bump >= lx.bumps || pressed == NULL) {
        return HAL_EINVAL;
    }
    if (!lx.up) {
        return HAL_EIO;
    }
    /* The events thread keeps the levels from the lines' edges: the tick reads no line. */
    bool high = (atomic_load_explicit(&lx.bump_high, memory_order_relaxed) >> bump & 1u) != 0u;
    *pressed = high != lx.cfg.bump_active_low;
    return HAL_OK;
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
    if (!lx.up) {
        return HAL_ENOSYS;
    }
    bool released = lx_io_begin();
    int rc = store_begin(&lx.store, slot);
    lx_io_end(released);
    return rc;
}

int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    if (!lx.up) {
        return HAL_ENOSYS;
    }
    bool released = lx_io_begin();
    int rc = store_write(&lx.store, slot, offset, data, len);
    lx_io_end(released);
    return rc;
}

int hal_storage_commit(uint8_t slot)
{
    if (!lx.up) {
        return HAL_ENOSYS;
    }
    bool released = lx_io_begin();
    int rc = store_commit(&lx.store, slot);
    lx_io_end(released);
    return rc;
}

int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    return lx.up ? store_read(&lx.store, slot, offset, data, len) : HAL_ENOSYS;
}

void hal_watchdog_kick(void)
{
    atomic_store(&lx.last_kick_ns, lx_now());
}
