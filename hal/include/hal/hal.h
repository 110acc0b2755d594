/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The hardware abstraction layer: the only door between the mapping core and hardware.
 *
 * Exactly one backend implements it per build (hal/stm32f4, hal/linux, hal/host; a new
 * port starts from hal/template). The HAL speaks raw hardware quantities (encoder counts,
 * echo pulse width in µs, servo pulse width in µs, motor duty) and the core converts
 * them, so the simulator runs the same conversion code as the robot.
 *
 * Context: "ISR-safe" functions may be called from the 10 ms tick callback, which runs
 * in interrupt context on an MCU and in a timer thread on Linux. The others belong to
 * start-up code or to the background loop (robot_idle()).
 */
#ifndef HAL_HAL_H
#define HAL_HAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** Return codes of the HAL; every error is negative. */
typedef enum {
    HAL_OK = 0,      /**< success */
    HAL_EINVAL = -1, /**< an argument is out of range */
    HAL_EIO = -2,    /**< the hardware failed or did not answer */
    HAL_EBUSY = -3,  /**< the resource is in use (a ping is already out) */
    HAL_ENOSYS = -4, /**< not supported by this backend */
} hal_err_t;

/** The two driven wheels; the numbering is the core's (ODOM_LEFT, ODOM_RIGHT). */
typedef enum { HAL_WHEEL_LEFT = 0, HAL_WHEEL_RIGHT = 1 } hal_wheel_t;

/** Full-scale motor duty: hal_motor_set() takes -HAL_DUTY_MAX .. HAL_DUTY_MAX. */
#define HAL_DUTY_MAX 1000

/** The period of the control tick, µs. */
#define HAL_TICK_PERIOD_US 10000u

/* ---- start-up and time ------------------------------------------------------------ */

/**
 * Bring up clocks and every peripheral in a safe state (motors off).
 * @retval HAL_OK   ready
 * @retval HAL_EIO  a peripheral could not be brought up (the backend says which)
 */
int hal_init(void);

/** The tick callback: robot_tick() wrapped with its robot. */
typedef void (*hal_tick_fn)(void *ctx);

/**
 * Start calling @p fn every HAL_TICK_PERIOD_US; it must return well within the period.
 * @retval HAL_OK      started
 * @retval HAL_EINVAL  fn is NULL
 * @retval HAL_EBUSY   already started
 * @retval HAL_EIO     the timer could not be started (Linux: timerfd or the thread)
 */
int hal_tick_start(hal_tick_fn fn, void *ctx);

/** Monotonic microseconds since hal_init(); wraps after 2^32 µs. ISR-safe. */
uint32_t hal_time_us(void);

/** Ticks that started late or overran their period since hal_init(). ISR-safe. */
uint32_t hal_tick_overruns(void);

/* ---- wheels ----------------------------------------------------------------------- */

/**
 * The raw 16-bit quadrature counter of a wheel; it increases when the wheel rolls the
 * robot forward and wraps freely. ISR-safe.
 */
uint16_t hal_encoder_count(hal_wheel_t wheel);

/**
 * Drive a motor. ISR-safe.
 * @param duty  -HAL_DUTY_MAX (full reverse) .. HAL_DUTY_MAX (full forward); clamped
 */
void hal_motor_set(hal_wheel_t wheel, int16_t duty);

/* ---- servos and sonars: instances ----------------------------------------------------- */

/*
 * Servos and sonars are addressed by an instance index, as the wheels are. Instance 0 is
 * the paper's: HAL_SERVO_SWEEP turns HAL_SONAR_SWEPT through the sweep. A board may have
 * more (a fixed side-looking sonar, say), numbered from 1 in its instance table; every
 * backend has at least instance 0 of each. An index the board does not have is refused
 * with HAL_EINVAL and changes nothing, never taken for another instance.
 */

/** The servo that sweeps the paper's sonar. */
#define HAL_SERVO_SWEEP ((uint8_t)0u)

/** The paper's sonar, on the sweep servo. */
#define HAL_SONAR_SWEPT ((uint8_t)0u)

/** The optional second sonar, fixed (robot_idle() maps it when sonar1_map is 1). */
#define HAL_SONAR_FIXED ((uint8_t)1u)

/** How many servos the backend has: instances 0 .. count - 1 (at least 1). ISR-safe. */
uint8_t hal_servo_count(void);

/** How many sonars the backend has: instances 0 .. count - 1 (at least 1). ISR-safe. */
uint8_t hal_sonar_count(void);

/**
 * Command a servo: the pulse width of its 50 Hz signal, in force from its next period.
 * ISR-safe.
 * @param servo     the instance, 0 .. hal_servo_count() - 1
 * @param pulse_us  high time in µs, clamped to 400..2600
 * @retval HAL_OK      commanded
 * @retval HAL_EINVAL  no such servo (nothing changed)
 */
int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us);

/** The state of a sonar as hal_sonar_poll() reports it. */
typedef enum {
    HAL_SONAR_IDLE = 0, /**< no measurement under way */
    HAL_SONAR_BUSY,     /**< a ping is out, no echo yet */
    HAL_SONAR_ECHO,     /**< an echo came back; its pulse width is reported once */
    HAL_SONAR_TIMEOUT,  /**< no echo within the sensor's timeout (HC-SR04: 38 ms) */
} hal_sonar_status_t;

/**
 * Start one measurement of a sonar (HC-SR04: a 10 µs trigger pulse). Each instance has its
 * own ping under way; pinging two sensors that face each other at once is the caller's
 * affair. ISR-safe.
 * @param sonar  the instance, 0 .. hal_sonar_count() - 1
 * @retval HAL_OK      the ping is out
 * @retval HAL_EBUSY   a measurement of this sonar is still under way
 * @retval HAL_EIO     the trigger could not be sent (Linux: the line write failed)
 * @retval HAL_EINVAL  no such sonar (nothing sent)
 */
int hal_sonar_trigger(uint8_t sonar);

/**
 * The result of a sonar's last ping. ECHO and TIMEOUT are reported once, then IDLE.
 * ISR-safe.
 * @param sonar    the instance, 0 .. hal_sonar_count() - 1
 * @param echo_us  out: the echo pulse width in µs, set with HAL_SONAR_ECHO only
 * @return the sonar's state, a hal_sonar_status_t (never negative)
 * @retval HAL_EINVAL  no such sonar (negative, unlike every state; @p echo_us untouched)
 */
int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us);

/* ---- bump switches (optional) --------------------------------------------------------- */

/*
 * Switches that close when the body touches something, numbered in the board's order
 * (its table says where each one sits). Optional: a board without them answers count 0
 * and HAL_ENOSYS (hal/defaults does, for a backend that leaves them out).
 */

/** How many bump switches the board has: 0 .. count - 1 (0: none). ISR-safe. */
uint8_t hal_bump_count(void);

/**
 * Whether a bump switch is pressed, as its input reads now (no debouncing). ISR-safe.
 * @param bump     the switch, 0 .. hal_bump_count() - 1
 * @param pressed  out: true while the switch is closed; set with HAL_OK only
 * @retval HAL_OK      read
 * @retval HAL_EINVAL  no such switch, or @p pressed is NULL
 * @retval HAL_ENOSYS  the board has no bump switches
 * @retval HAL_EIO     the input cannot be read now (Linux: before hal_init())
 */
int hal_bump_read(uint8_t bump, bool *pressed);

/* ---- telemetry UART --------------------------------------------------------------- */

/** Queue bytes for sending without blocking; returns how many fit. ISR-safe. */
size_t hal_uart_write(const uint8_t *data, size_t len);

/** Take up to @p len received bytes without blocking; returns how many. */
size_t hal_uart_read(uint8_t *data, size_t len);

/**
 * Whether anything may read what hal_uart_write() sends. A backend answers false only when
 * it knows the bytes go nowhere (the simulator without a telemetry sink): the firmware then
 * counts its frames as written, whole, without building them. Optional: hal/defaults
 * answers true, since a UART may always have a listener. ISR-safe.
 */
bool hal_uart_has_reader(void);

/* ---- map storage ------------------------------------------------------------------ */

/** Storage slots: a map is written to one while the other keeps the last good one. */
#define HAL_STORAGE_SLOTS 2u

/** Bytes in one storage slot (0: the backend has no storage). */
size_t hal_storage_size(void);

/**
 * Begin rewriting a slot (flash: erase it). Not ISR-safe.
 * @retval HAL_OK / HAL_EINVAL (no such slot) / HAL_EIO / HAL_ENOSYS (no storage)
 */
int hal_storage_begin(uint8_t slot);

/**
 * Write bytes into a slot being rewritten. Not ISR-safe.
 * @retval HAL_OK / HAL_EINVAL (slot, or range beyond the slot) / HAL_EIO
 */
int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len);

/**
 * Make a rewritten slot durable (file: fsync and rename). Not ISR-safe.
 * @retval HAL_OK / HAL_EINVAL / HAL_EIO
 */
int hal_storage_commit(uint8_t slot);

/**
 * Read bytes from a slot; bytes never written read as 0xFF, like erased flash. Not ISR-safe.
 * @retval HAL_OK / HAL_EINVAL (slot, or range beyond the slot) / HAL_EIO / HAL_ENOSYS
 */
int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len);

/* ---- system ----------------------------------------------------------------------- */

/** Opaque saved interrupt state of a critical section. */
typedef uint32_t hal_irq_state_t;

/** Enter a critical section (the tick cannot run inside it); nests. ISR-safe. */
hal_irq_state_t hal_critical_enter(void);

/** Leave a critical section, restoring the state hal_critical_enter() returned. ISR-safe. */
void hal_critical_exit(hal_irq_state_t state);

/** Tell the watchdog the system is alive. ISR-safe. */
void hal_watchdog_kick(void);

#endif /* HAL_HAL_H */
