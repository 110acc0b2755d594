/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The Linux robot's configuration: the keys of robot.conf that are not core fields.
 *
 * robot.conf is one `key = value` file (hal_common/config_text.h reads it): the core's
 * slam_config_t fields (wheel geometry, encoder resolution, sweep timing...) first, then,
 * under a `[linux]` line, the keys below, which say where the hardware is (the simulator
 * reads the same file and skips that section). Line offsets are those of one GPIO chip; PWM
 * channels are sysfs pwmchipN/pwmM pairs. Keys marked "required" have no default: a
 * robot's wiring is never guessed. Every line may be used once and every PWM channel
 * once; optional lines and PWM channels take -1 for "not wired".
 *
 * Servos and sonars are instances as hal.h numbers them: the sonar_* and servo_* keys are
 * instance 0's (the paper's, required), the sonar1_* and servo1_* keys instance 1's,
 * optional and off unless given. Bump switches bump0, bump1, ... are optional, numbered
 * from 0 without a gap.
 */
#ifndef LHAL_LCONF_H
#define LHAL_LCONF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "slam/config.h"

/** An optional line that is not wired. */
#define LCONF_NO_LINE (-1)

/** The largest line offset and PWM chip or channel number accepted. */
#define LCONF_LINE_MAX 4095
#define LCONF_PWM_MAX 1023

/** The most backend keys there can be (lconf_t.seen has a bit for each). */
#define LCONF_KEYS_MAX 64

/** Sonars and servos a robot.conf can wire: instance 0 and instance 1. */
#define LCONF_SONARS 2u
#define LCONF_SERVOS 2u

/** Bump switches a robot.conf can wire: bump0 .. bump3. */
#define LCONF_BUMPS 4u

/** The bias of the encoder inputs. */
typedef enum {
    LCONF_BIAS_AS_IS = 0, /**< leave the pin as the firmware set it */
    LCONF_BIAS_DISABLE,   /**< no pull resistor */
    LCONF_BIAS_PULL_UP,   /**< open-collector encoders */
    LCONF_BIAS_PULL_DOWN,
} lconf_bias_t;

/** A PWM channel: ROOT/pwmchip<chip>/pwm<channel>; an optional one not wired is -1, -1. */
typedef struct {
    int32_t chip;
    int32_t channel;
} lconf_pwm_t;

/** Where everything is. Wheels are indexed by hal_wheel_t (0 left, 1 right). */
typedef struct {
    char gpio_chip[64];            /**< gpio_chip: name, path, label or number; "gpiochip0" */
    int32_t enc_a[2];              /**< encoder_left_a, encoder_right_a: required */
    int32_t enc_b[2];              /**< encoder_left_b, encoder_right_b: required */
    bool enc_invert[2];            /**< encoder_left_invert, encoder_right_invert; 0 */
    uint8_t enc_bias;              /**< encoder_bias: an lconf_bias_t; as-is */
    int32_t sonar_trigger;         /**< sonar_trigger: required */
    int32_t sonar_echo;            /**< sonar_echo: required */
    int32_t sonar1_trigger;        /**< sonar1_trigger: sonar 1's; -1 (no sonar 1) */
    int32_t sonar1_echo;           /**< sonar1_echo: sonar 1's; -1; given with sonar1_trigger */
    uint32_t sonar_timeout_us;     /**< sonar_timeout_us: 1000..100000, every sonar's; 30000
                                        (5.1 m) */
    char pwm_root[160];            /**< pwm_root: "/sys/class/pwm" */
    lconf_pwm_t servo_pwm;         /**< servo_pwm_chip, servo_pwm_channel: required */
    lconf_pwm_t servo1_pwm;        /**< servo1_pwm_chip, servo1_pwm_channel: servo 1's, both or
                                        neither; -1 (no servo 1) */
    lconf_pwm_t motor_pwm[2];      /**< motor_{left,right}_pwm_{chip,channel}: required */
    uint32_t motor_period_ns;      /**< motor_pwm_period_ns: 10000..50000000; 50000 (20 kHz) */
    int32_t motor_in1[2];          /**< motor_{left,right}_in1: required */
    int32_t motor_in2[2];          /**< motor_{left,right}_in2: required, -1 for a DIR driver */
    bool motor_invert[2];          /**< motor_{left,right}_invert; 0 */
    int32_t motor_standby;         /**< motor_standby: high while a motor runs; -1 */
    int32_t bump[LCONF_BUMPS];     /**< bump0 .. bump3: bump switch inputs; -1 (none). bumpN
                                        needs every bump before it */
    uint8_t bump_bias;             /**< bump_bias: an lconf_bias_t; pull-up */
    bool bump_active_low;          /**< bump_active_low: a pressed switch reads low (closes to
                                        ground); 1 */
    char telemetry[128];           /**< telemetry: a device path, "pty" or "none"; "none" */
    uint32_t telemetry_baud;       /**< telemetry_baud: 9600..921600; 115200 */
    char storage_dir[160];         /**< storage_dir: slots and maps; "." */
    uint32_t storage_bytes;        /**< storage_bytes: bytes per slot, 4096..16777216; 65536 */
    uint32_t tick_priority;        /**< tick_priority: SCHED_FIFO 1..98, 0 for normal; 50 */
    uint32_t watchdog_idle_ms;     /**< watchdog_idle_ms: 0 (off) or 100..60000; 2000 */
    uint64_t seen;                 /**< which keys were given (one bit per key) */
    unsigned line[LCONF_KEYS_MAX]; /**< the line of the file that set each key; 0 */
} lconf_t;

/** The defaults above; required keys are unset. */
void lconf_default(lconf_t *c);

/**
 * Set one key from its text (a cfgtext_other_fn).
 * @param ctx   the lconf_t
 * @param line  the line of the file that holds the key (0: not from a file)
 * @retval 0   set
 * @retval -1  not a key of this backend (err says so)
 * @retval -2  bad value, or a key given twice (err names the key; nothing changed)
 */
int lconf_set(void *ctx, const char *key, const char *value, unsigned line, char *err,
              size_t errlen);

/**
 * Check the whole: required keys given, every line and PWM channel used once.
 * @return 0, or -1 with err naming the key(s) and the lines of the file that set them
 */
int lconf_check(const lconf_t *c, char *err, size_t errlen);

/**
 * Read robot.conf: core keys (before the first section) on top of @p core, backend keys
 * (under `[linux]`) on top of @p lc, then check both. Nothing changes unless everything is right.
 * @param err  out: "FILE:LINE: message" or "FILE: message"
 * @return 0, or -1
 */
int lconf_load(const char *path, slam_config_t *core, lconf_t *lc, char *err, size_t errlen);

/** The configured lines, in the order lconf_lines() lists them. */
enum {
    LCONF_ENC_LEFT_A = 0,
    LCONF_ENC_LEFT_B,
    LCONF_ENC_RIGHT_A,
    LCONF_ENC_RIGHT_B,
    LCONF_SONAR_TRIGGER,
    LCONF_SONAR_ECHO,
    LCONF_MOTOR_LEFT_IN1,
    LCONF_MOTOR_LEFT_IN2,
    LCONF_MOTOR_RIGHT_IN1,
    LCONF_MOTOR_RIGHT_IN2,
    LCONF_MOTOR_STANDBY,
    LCONF_SONAR1_TRIGGER,
    LCONF_SONAR1_ECHO,
    LCONF_BUMP0,
    LCONF_BUMP_LAST = LCONF_BUMP0 + LCONF_BUMPS - 1u,
    LCONF_LINES
};

/** How many sonars, servos and bump switches a configuration wires. */
unsigned lconf_sonars(const lconf_t *c);
unsigned lconf_servos(const lconf_t *c);
unsigned lconf_bumps(const lconf_t *c);

/** How a line is used. */
#define LCONF_OUTPUT (-1) /**< bias value of an output line */

/** One configured line. */
typedef struct {
    const char *name; /**< its key ("encoder_left_a"...) */
    int32_t offset;   /**< the line offset; LCONF_NO_LINE when not wired */
    int8_t bias;      /**< an input with edge events and this lconf_bias_t, or LCONF_OUTPUT */
} lconf_line_t;

/** Every line of a configuration, wired or not, indexed by the enum above. */
void lconf_lines(const lconf_t *c, lconf_line_t out[LCONF_LINES]);

#endif /* LHAL_LCONF_H */
