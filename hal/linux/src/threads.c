/* SPDX-License-Identifier: MIT */
/* The Linux backend's tick, events and watchdog threads, and how they start and end. */
#define _GNU_SOURCE /* pthread_timedjoin_np */
#include <errno.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "lhal/wdog.h"
#include "lx.h"

#define LX_EDGE_HOLD_NS (2u * LX_NS_PER_MS) /* margin for the kernel's queueing of edges */
#define LX_JOIN_S 1                         /* a thread that takes longer to end is stuck */

/* Poll slots of the events thread: four encoder lines, then each sonar's echo, each bump
 * switch, the stop signal. */
enum { LX_POLL_ECHO = 4, LX_POLL_MAX = LX_POLL_ECHO + LCONF_SONARS + LCONF_BUMPS + 1 };

int lx_spawn(lx_thread_t *t, void *(*fn)(void *), unsigned prio, bool *fifo, int *prio_err)
{
    static const int sigs[] = {SIGINT,  SIGTERM, SIGHUP,  SIGQUIT,
                               SIGPIPE, SIGUSR1, SIGUSR2, SIGALRM};
    sigset_t block;
    sigset_t old;
    sigemptyset(&block);
    for (size_t i = 0u; i < sizeof sigs / sizeof sigs[0]; i++) {
        sigaddset(&block, sigs[i]);
    }
    atomic_store(&t->beat_ns, lx_now());
    atomic_store(&t->rounds, 0u);
    pthread_sigmask(SIG_BLOCK, &block, &old);
    int rc = pthread_create(&t->id, NULL, fn, NULL);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    t->running = rc == 0;
    *fifo = false;
    *prio_err = 0;
    if (rc == 0 && prio > 0u) {
        struct sched_param sp = {.sched_priority = (int)prio};
        *prio_err = pthread_setschedparam(t->id, SCHED_FIFO, &sp);
        *fifo = *prio_err == 0;
    }
    return rc;
}

bool lx_join(lx_thread_t *t, const char *name)
{
    if (!t->running) {
        return true;
    }
    t->running = false;
    struct timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    deadline.tv_sec += LX_JOIN_S;
    if (pthread_timedjoin_np(t->id, NULL, &deadline) == 0) {
        return true;
    }
    /* Stuck in a call that does not return: the motors are stopped already, and the
     * process is about to end. */
    fprintf(stderr, "sonarslam-linux: the %s thread does not stop; leaving it\n", name);
    pthread_detach(t->id);
    return false;
}

/* ---- tick ------------------------------------------------------------------------------ */

void *lx_tick_main(void *arg)
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
        atomic_store(&lx.tick.beat_ns, lx_now());
        atomic_fetch_add(&lx.tick.rounds, 1u);
    }
    return NULL;
}

/* ---- events ---------------------------------------------------------------------------- */

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

static const char *const lx_echo_key[LCONF_SONARS] = {"sonar_echo", "sonar1_echo"};

static bool lx_read_echo(unsigned sonar)
{
    edgeq_edge_t buf[16];
    int n = gpio_line_read_edges(LX_ECHO(sonar), 0u, buf, 16u);
    if (n < 0) {
        lx_fault(LHAL_FAULT_IO, "%s: reading edges failed: %s", lx_echo_key[sonar],
                 strerror(errno));
        return false;
    }
    pthread_mutex_lock(&lx_sonar_lock);
    for (int i = 0; i < n; i++) {
        echo_edge(&lx.echo[sonar], buf[i].ts_ns, buf[i].rising);
    }
    pthread_mutex_unlock(&lx_sonar_lock);
    return true;
}

/* A bump switch's edges: its level is the last one's. */
static bool lx_read_bump(unsigned bump)
{
    edgeq_edge_t buf[16];
    int n = gpio_line_read_edges(LX_BUMP(bump), 0u, buf, 16u);
    if (n < 0) {
        lx_fault(LHAL_FAULT_IO, "bump%u: reading edges failed: %s", bump, strerror(errno));
        return false;
    }
    if (n > 0 && buf[n - 1].rising) {
        atomic_fetch_or(&lx.bump_high, 1u << bump);
    } else if (n > 0) {
        atomic_fetch_and(&lx.bump_high, ~(1u << bump));
    }
    return true;
}

void *lx_events_main(void *arg)
{
    (void)arg;
    struct pollfd pfd[LX_POLL_MAX];
    for (unsigned i = 0u; i < 4u; i++) {
        pfd[i] = (struct pollfd){.fd = gpio_line_fd(LX_ENC(i / 2u, i % 2u)), .events = POLLIN};
    }
    for (unsigned i = 0u; i < lx.sonars; i++) {
        pfd[LX_POLL_ECHO + i] = (struct pollfd){.fd = gpio_line_fd(LX_ECHO(i)), .events = POLLIN};
    }
    const unsigned poll_bump = LX_POLL_ECHO + lx.sonars;
    for (unsigned i = 0u; i < lx.bumps; i++) {
        pfd[poll_bump + i] = (struct pollfd){.fd = gpio_line_fd(LX_BUMP(i)), .events = POLLIN};
    }
    const unsigned poll_stop = poll_bump + lx.bumps;
    pfd[poll_stop] = (struct pollfd){.fd = lx.stop_fd, .events = POLLIN};

    while (!atomic_load(&lx.stop)) {
        /* Every round stamps, and no wait is longer than a beat: the watchdog tells a thread
         * that died or hangs from one that has no edge to read. */
        atomic_store(&lx.events.beat_ns, lx_now());
        atomic_fetch_add(&lx.events.rounds, 1u);
        bool held = !edgeq_empty(&lx.edgeq[0]) || !edgeq_empty(&lx.edgeq[1]);
        int r = poll(pfd, poll_stop + 1u, held ? 3 : LX_BEAT_MS);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r < 0) {
            /* Without this thread the counts freeze and the speed control winds up to full
             * duty: that is a fault, never a quiet end. */
            lx_fault(LHAL_FAULT_IO, "the events thread stopped: poll: %s", strerror(errno));
            return NULL;
        }
        if (pfd[poll_stop].revents & POLLIN) {
            break;
        }
        for (unsigned i = 0u; i < poll_stop; i++) {
            if (pfd[i].revents & (POLLERR | POLLHUP | POLLNVAL)) {
                char bump[16];
                snprintf(bump, sizeof bump, "bump%u", i >= poll_bump ? i - poll_bump : 0u);
                lx_fault(LHAL_FAULT_IO, "a GPIO event descriptor failed (line of %s)",
                         i < LX_POLL_ECHO ? "an encoder"
                         : i < poll_bump  ? lx_echo_key[i - LX_POLL_ECHO]
                                          : bump);
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
        for (unsigned i = 0u; i < lx.sonars; i++) {
            if ((pfd[LX_POLL_ECHO + i].revents & POLLIN) && !lx_read_echo(i)) {
                return NULL;
            }
        }
        for (unsigned i = 0u; i < lx.bumps; i++) {
            if ((pfd[poll_bump + i].revents & POLLIN) && !lx_read_bump(i)) {
                return NULL;
            }
        }
    }
    return NULL;
}

/* ---- watchdog ---------------------------------------------------------------------------- */

static void lx_wdog_judge(const wdog_t *w)
{
    if (!atomic_load(&lx.tick_started) || atomic_load(&lx.fault) != LHAL_FAULT_NONE) {
        return;
    }
    uint64_t now = lx_now(); /* before the stamps, so a fresh stamp is never "old" */
    const wdog_stamps_t s = {
        .tick_ns = atomic_load(&lx.tick.beat_ns),
        .events_ns = atomic_load(&lx.events.beat_ns),
        .output_ns = atomic_load(&lx.output.beat_ns),
        .kick_ns = atomic_load(&lx.last_kick_ns),
    };
    uint64_t age = 0u;
    wdog_verdict_t v = wdog_check(w, now, &s, &age);
    unsigned long long ms = (unsigned long long)(age / LX_NS_PER_MS);
    const char *doing = atomic_load(&lx.doing);
    switch (v) {
    case WDOG_TICK_STALL:
        lx_fault(LHAL_FAULT_WATCHDOG, "watchdog: no control tick for %llu ms; motors stopped", ms);
        break;
    case WDOG_EVENTS_STALL:
        lx_fault(LHAL_FAULT_WATCHDOG,
                 "watchdog: the events thread (encoders, echo) stopped %llu ms ago; motors stopped",
                 ms);
        break;
    case WDOG_OUTPUT_STALL:
        lx_fault(LHAL_FAULT_WATCHDOG,
                 "watchdog: writing %s has not returned for %llu ms; motors stopped",
                 doing != NULL ? doing : "the outputs", ms);
        break;
    case WDOG_IDLE_STALL:
        lx_fault(
            LHAL_FAULT_WATCHDOG,
            "watchdog: the background loop stalled for %llu ms (watchdog_idle_ms); motors stopped",
            ms);
        break;
    default:
        break;
    }
}

void *lx_wdog_main(void *arg)
{
    (void)arg;
    const wdog_t w = {.tick_limit_ns = WDOG_TICK_LIMIT_NS,
                      .idle_limit_ns = (uint64_t)lx.cfg.watchdog_idle_ms * LX_NS_PER_MS};
    struct pollfd pfd[2] = {{.fd = atomic_load(&lx.kill_fd), .events = POLLIN},
                            {.fd = lx.stop_fd, .events = POLLIN}};
    for (;;) {
        int r = poll(pfd, 2u, LX_BEAT_MS);
        if (r < 0 && errno != EINTR) {
            /* Keep watching at the same pace without the wake-ups. */
            const struct timespec beat = {0, LX_BEAT_MS * (long)LX_NS_PER_MS};
            nanosleep(&beat, NULL);
        }
        if (r > 0 && (pfd[0].revents & POLLIN)) {
            uint64_t n;
            (void)!read(pfd[0].fd, &n, sizeof n);
        }
        /* A stop was asked for (a signal, the shutdown), or a kill's PWM writes failed (no
         * descriptor left, say): (again) now, and every beat until they work. */
        if (atomic_exchange(&lx.kill_asked, false) || atomic_load(&lx.pwm_failed)) {
            lx_kill();
        }
        if (atomic_load(&lx.stop)) {
            break;
        }
        lx_wdog_judge(&w);
    }
    return NULL;
}
