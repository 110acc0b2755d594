/* SPDX-License-Identifier: MIT */
/**
 * @file
 * A scriptable HAL for unit tests: tests set what the hardware reports and read back what
 * the firmware did. Every call is counted; fake_hal_reset() clears all state and must be
 * called before each test.
 */
#ifndef SLAM_TEST_FAKE_HAL_H
#define SLAM_TEST_FAKE_HAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal/hal.h"

#define FAKE_HAL_STORAGE_SIZE 65536u
#define FAKE_HAL_UART_SIZE (1u << 20)

typedef struct {
    /* Set by the test. */
    uint16_t encoder[2];            /**< what hal_encoder_count() returns */
    hal_sonar_status_t sonar_next;  /**< what the next hal_sonar_poll() of sonar 0 returns */
    uint32_t sonar_echo_us;         /**< width returned with HAL_SONAR_ECHO */
    int trigger_result;             /**< what hal_sonar_trigger() of sonar 0 returns */
    uint8_t servos;                 /**< what hal_servo_count() returns (fake_hal_reset(): 1) */
    uint8_t sonars;                 /**< what hal_sonar_count() returns (1); sonars past 0 are
                                         idle and take every ping */
    hal_sonar_status_t sonar1_next; /**< what the next hal_sonar_poll() of sonar 1 returns
                                         (IDLE) */
    uint32_t sonar1_echo_us;        /**< width returned with it */
    uint32_t time_us;               /**< what hal_time_us() returns (0) */
    uint8_t bumps;                  /**< what hal_bump_count() returns (0: HAL_ENOSYS) */
    bool bump_pressed[8];           /**< what hal_bump_read() says of each switch */
    size_t storage_size;            /**< what hal_storage_size() returns */
    size_t uart_room;               /**< bytes hal_uart_write() takes per call (0: all) */
    bool uart_no_reader;            /**< hal_uart_has_reader() answers false */
    uint8_t rx[4096];               /**< bytes hal_uart_read() hands out, in order */
    size_t rx_len;                  /**< bytes in rx */
    size_t rx_pos;                  /**< bytes already read */

    /* Recorded from the firmware. */
    int16_t motor[2];                 /**< last duty per wheel */
    uint16_t servo_pulse_us;          /**< last command of servo 0 */
    uint16_t servo_pulse_other_us[8]; /**< last command of servo 1, 2, ... ([servo - 1]) */
    unsigned calls_encoder;
    unsigned calls_motor;
    unsigned calls_servo;          /**< hal_servo_set_pulse() of servo 0 */
    unsigned calls_trigger;        /**< hal_sonar_trigger() of sonar 0 */
    unsigned calls_poll;           /**< hal_sonar_poll() of sonar 0 */
    unsigned calls_other_instance; /**< servo and sonar calls of an instance past 0 */
    unsigned calls_trigger1;       /**< hal_sonar_trigger() of sonar 1 */
    unsigned calls_poll1;          /**< hal_sonar_poll() of sonar 1 */
    unsigned calls_bad_instance;   /**< calls refused with HAL_EINVAL (no such instance) */
    unsigned calls_bump;
    unsigned calls_watchdog;
    unsigned calls_storage_write;
    unsigned calls_storage_commit;
    unsigned calls_storage_begin;
    unsigned storage_begin_moving; /**< hal_storage_begin() calls with a motor running */
    int storage_fail_at;           /**< hal_storage_write call number that fails (0: none) */

    /* Flash and power cuts (all off after fake_hal_reset()). */
    bool storage_nor;            /**< writes only program bits (1 -> 0), as NOR flash */
    long storage_cut_after;      /**< bytes still programmed before the power fails; -1 */
    uint8_t storage_cut_bits;    /**< of the byte being programmed at the cut, the bits
                                      that did get programmed (a mask) */
    unsigned storage_erase_cut;  /**< hal_storage_begin call number whose erase the power
                                      cuts (0: none) */
    uint32_t storage_erase_done; /**< bytes from the start of the slot erased by then */
    bool storage_erase_noise;    /**< the rest of the slot half-erased: bits set at random */
    bool storage_powered_off;    /**< after a cut every storage call fails with HAL_EIO */
    uint8_t storage[HAL_STORAGE_SLOTS][FAKE_HAL_STORAGE_SIZE];
    uint8_t uart[FAKE_HAL_UART_SIZE]; /**< every byte written to the UART */
    size_t uart_len;
    bool storage_committed[HAL_STORAGE_SLOTS];
} fake_hal_t;

extern fake_hal_t fake_hal;

/** Forget everything: counters, recorded outputs and scripted inputs. */
void fake_hal_reset(void);

/** Queue bytes for hal_uart_read() (they must fit in rx). */
void fake_hal_receive(const uint8_t *data, size_t len);

/** Power the storage on again after a cut: its contents stay, the cuts are disarmed. */
void fake_hal_power_on(void);

#endif /* SLAM_TEST_FAKE_HAL_H */
