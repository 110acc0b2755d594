/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The Linux backend's own state and the calls its files share (not an interface: the
 * program sees lhal/lhal.h and hal/hal.h).
 *
 * Threads, and who owns what:
 *   - tick: runs the hal_tick_start() callback every 10 ms holding lx_crit. It does no
 *     I/O: the outputs it sets are posted to the output thread, so no hung device can hold
 *     the tick, or the lock, or the background loop that takes it.
 *   - events: reads encoder, echo and bump switch edges; owns edgeq[] and quad[],
 *     publishes counts and the switches' levels.
 *   - output: writes what was posted (motor direction lines and duty, servos, the sonars'
 *     trigger pulses); owns motor_out[], servo state and the standby line's state.
 *   - watchdog: every LX_BEAT, or at once when woken through kill_fd: judges the stamps of
 *     the other threads, and stops the motors for a stall, a fault or a stop request.
 *   - main: hal_init(), robot_idle() inside lhal_idle_lock(), lhal_shutdown().
 * Stopping the motors (lx_kill()) takes no lock: any thread may do it while another is
 * stuck anywhere.
 */
#ifndef LHAL_LX_H
#define LHAL_LX_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "hal/hal.h"
#include "lhal/echo.h"
#include "lhal/edgeq.h"
#include "lhal/gpio_if.h"
#include "lhal/lconf.h"
#include "lhal/lhal.h"
#include "lhal/motor.h"
#include "lhal/pwm.h"
#include "lhal/quad.h"
#include "lhal/serial.h"
#include "lhal/store.h"
#include "lhal/tickstat.h"

#define LX_NS_PER_US 1000u
#define LX_NS_PER_MS 1000000u
#define LX_NS_PER_S 1000000000u
#define LX_BEAT_MS 10 /* the longest a healthy thread waits before it stamps again */
#define LX_SERVO_MIN_US 400u
#define LX_SERVO_MAX_US 2600u

/** A thread of the backend. */
typedef struct {
    pthread_t id;
    bool running;             /**< started and not joined */
    _Atomic uint64_t beat_ns; /**< lx_now() when it last went round */
    _Atomic uint32_t rounds;  /**< times it went round */
} lx_thread_t;

/** Everything the backend holds. */
typedef struct {
    lconf_t cfg;
    bool configured;
    bool up;
    char error[320];
    uint64_t (*clock)(void);
    uint64_t t0_ns;

    gpio_chip_t *chip;
    gpio_line_t *line[LCONF_LINES]; /* NULL: not wired */
    atomic_bool lines_live;         /* line[] may be used by lx_kill() */

    /* The instances wired (lhal_configure(): instance 0 of each always, no switches before). */
    unsigned servos;
    unsigned sonars;
    unsigned bumps;

    pwm_chan_t servo[LCONF_SERVOS];
    pwm_chan_t motor[2];

    /* Posted by hal_*() (the tick, or main before it starts), applied by the output thread. */
    _Atomic int32_t want_duty[2];
    _Atomic uint32_t want_servo_us[LCONF_SERVOS]; /* 0: no command yet */
    _Atomic uint32_t want_triggers[LCONF_SONARS]; /* pulses asked for */
    _Atomic uint32_t posted;                      /* postings */
    _Atomic uint32_t applied;                     /* the postings written so far */
    _Atomic(const char *) doing; /* what the output thread writes now, for messages */
    /* The output thread's own. */
    bool servo_started[LCONF_SERVOS];
    uint32_t servo_us[LCONF_SERVOS];
    uint32_t triggers[LCONF_SONARS];
    motor_out_t motor_out[2];
    bool standby_on;

    echo_t echo[LCONF_SONARS];  /* under lx_sonar_lock */
    _Atomic uint32_t bump_high; /* the events thread's: bit i set while bump i's line is high */
    edgeq_t edgeq[2];
    quad_t quad[2];
    _Atomic uint16_t enc_count[2];
    _Atomic uint32_t enc_edges[2];
    _Atomic uint32_t enc_illegal[2];
    atomic_bool ts_realtime;

    serial_t uart; /* main */
    store_t store; /* main */

    int timer_fd;
    int stop_fd;         /* readable once the threads are to end */
    int out_fd;          /* eventfd: something was posted */
    _Atomic int kill_fd; /* eventfd: the watchdog is to stop the motors now */
    lx_thread_t tick;
    lx_thread_t events;
    lx_thread_t output;
    lx_thread_t wdog;
    hal_tick_fn tick_fn;
    void *tick_ctx;
    tickstat_t tickstat; /* under lx_crit */
    bool sched_fifo;

    atomic_bool stop;
    atomic_bool killed;     /* the motors are stopped for good */
    atomic_bool kill_asked; /* the watchdog is to do the kill (a signal, the shutdown) */
    atomic_bool pwm_dead;   /* a kill turned the PWM outputs off */
    atomic_bool pwm_failed; /* a kill's PWM writes failed: the watchdog tries again */
    atomic_bool tick_started;
    _Atomic uint32_t overruns;
    _Atomic uint64_t last_kick_ns;
    atomic_int fault;
    atomic_flag fault_claimed;
    char fault_msg[256];
} lx_t;

extern lx_t lx;
extern pthread_mutex_t lx_crit;       /* the critical section: recursive, priority inheritance */
extern pthread_mutex_t lx_sonar_lock; /* echo: priority inheritance */

/* The lines by role; wheels are hal_wheel_t, encoder lines 0 = A, 1 = B. */
#define LX_ENC(w, ab) lx.line[LCONF_ENC_LEFT_A + 2u * (w) + (ab)]
#define LX_IN1(w) lx.line[LCONF_MOTOR_LEFT_IN1 + 2u * (w)]
#define LX_IN2(w) lx.line[LCONF_MOTOR_LEFT_IN2 + 2u * (w)]
#define LX_TRIGGER(s) lx.line[(s) == 0u ? LCONF_SONAR_TRIGGER : LCONF_SONAR1_TRIGGER]
#define LX_ECHO(s) lx.line[(s) == 0u ? LCONF_SONAR_ECHO : LCONF_SONAR1_ECHO]
#define LX_BUMP(b) lx.line[LCONF_BUMP0 + (b)]
#define LX_STANDBY lx.line[LCONF_MOTOR_STANDBY]
_Static_assert(LCONF_SONARS == 2u, "LX_TRIGGER and LX_ECHO know two sonars");

extern const char *const lx_wheel_name[2];

/** CLOCK_MONOTONIC in ns. */
uint64_t lx_mono_ns(void);

/** The backend's clock: lhal_set_clock()'s, or CLOCK_MONOTONIC. */
uint64_t lx_now(void);

/** Set lhal_error() and return HAL_EIO. */
__attribute__((format(printf, 1, 2))) int lx_fail(const char *fmt, ...);

/** Stop the motors for good: direction and standby lines low first, then the PWM. No lock;
 *  async-signal-safe as far as libgpiod's line writes are (an ioctl each). */
void lx_kill(void);

/** Drive the direction and standby lines low (the first half of lx_kill()). */
void lx_lines_low(void);

/** Stop the motors and keep the first fault's message; later faults only stop them again. */
__attribute__((format(printf, 2, 3))) void lx_fault(lhal_fault_t code, const char *fmt, ...);

/** Wake a thread waiting on an eventfd (async-signal-safe; a closed one, -1, is skipped). */
void lx_wake(int fd);

/** Hand the output thread what was set. */
void lx_post(void);

/**
 * Start a thread that leaves the stop signals to the main thread, at a SCHED_FIFO
 * priority when asked (prio > 0) and permitted.
 * @return 0 or an errno; *fifo and *prio_err say whether the priority was granted
 */
int lx_spawn(lx_thread_t *t, void *(*fn)(void *), unsigned prio, bool *fifo, int *prio_err);

/** Join a thread, waiting a bounded time; a stuck one is left behind. @return joined */
bool lx_join(lx_thread_t *t, const char *name);

/** The threads' bodies. */
void *lx_tick_main(void *arg);
void *lx_events_main(void *arg);
void *lx_output_main(void *arg);
void *lx_wdog_main(void *arg);

#endif /* LHAL_LX_H */
