/* SPDX-License-Identifier: MIT */
/* Servo PWM and the HC-SR04: a one-pulse timer triggers, a PWM-input timer measures the echo. */
#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

#define SERVO_PERIOD_US 20000u /* 50 Hz */
#define SERVO_MIN_US 400u
#define SERVO_MAX_US 2600u
/* An HC-SR04 answers "nothing in range" with a long echo (about 38 ms on most modules;
 * 4 m, its range, is 23 ms): anything from 30 ms up is a timeout. */
#define SONAR_NO_ECHO_US 30000u
/* No falling edge this long after the trigger: the sensor is missing or stuck. */
#define SONAR_GIVE_UP_US 60000u

/* Posted by the capture interrupt: the width of the last echo and a count of echoes. */
static volatile uint32_t echo_width_us;
static volatile uint32_t echo_seq;

/* The tick's view of the ping under way. */
static bool ping_out;
static uint32_t ping_seq;   /* echo_seq when the ping went out */
static uint32_t ping_at_us; /* hal_time_us() when it went out */

STM32_START_UP static void timer_1mhz(stm32_tim_t *tim, uint32_t base)
{
    (void)stm32_periph_enable(base);
    tim->CR1 = 0u;
    tim->PSC = stm32_timer_clock_hz(base) / 1000000u - 1u;
}

STM32_START_UP void stm32_sonar_init(void)
{
    /* Servo: PWM mode 1 at 50 Hz, 1 µs a count; no pulse until the firmware asks. */
    stm32_tim_t *servo = STM32_TIM(BOARD_SERVO_TIM);
    timer_1mhz(servo, BOARD_SERVO_TIM);
    servo->ARR = SERVO_PERIOD_US - 1u;
    servo->CCR[BOARD_SERVO_CH - 1u] = 0u;
    (BOARD_SERVO_CH <= 2u ? &servo->CCMR1 : &servo->CCMR2)[0] |=
        STM32_TIM_CCMR_CH(BOARD_SERVO_CH, STM32_TIM_CCMR_OCM_PWM1 | STM32_TIM_CCMR_OCPE);
    servo->CCER = STM32_TIM_CCER_CCE(BOARD_SERVO_CH);
    servo->EGR = STM32_TIM_EGR_UG;
    servo->CR1 = STM32_TIM_CR1_ARPE | STM32_TIM_CR1_CEN;

    /* Trigger: one-pulse mode, PWM mode 2: low until CCR = 1, high until ARR, then the
     * counter stops by itself. Setting CEN is the whole trigger. */
    stm32_tim_t *trig = STM32_TIM(BOARD_TRIG_TIM);
    timer_1mhz(trig, BOARD_TRIG_TIM);
    trig->ARR = BOARD_TRIG_PULSE_US; /* pulse = ARR - CCR + 1 */
    trig->CCR[BOARD_TRIG_CH - 1u] = 1u;
    (BOARD_TRIG_CH <= 2u ? &trig->CCMR1 : &trig->CCMR2)[0] |=
        STM32_TIM_CCMR_CH(BOARD_TRIG_CH, STM32_TIM_CCMR_OCM_PWM2);
    trig->CCER = STM32_TIM_CCER_CCE(BOARD_TRIG_CH);
    trig->BDTR = STM32_TIM_BDTR_MOE; /* an advanced timer (TIM1, TIM8) drives no pin without it */
    trig->CR1 = STM32_TIM_CR1_URS | STM32_TIM_CR1_OPM;
    trig->EGR = STM32_TIM_EGR_UG;

    /* Echo: PWM-input mode (RM0090 §18.3.6). The rising edge resets the counter through
     * TI1FP1; the falling edge captures into CCR2, which then holds the width in µs. */
    stm32_tim_t *echo = STM32_TIM(BOARD_ECHO_TIM);
    timer_1mhz(echo, BOARD_ECHO_TIM);
    echo->ARR = 0xFFFFFFFFu;
    echo->CCMR1 = STM32_TIM_CCMR_CH(1u, STM32_TIM_CCMR_CCS_TI_SAME | STM32_TIM_CCMR_ICF(3u)) |
                  STM32_TIM_CCMR_CH(2u, STM32_TIM_CCMR_CCS_TI_OTHER | STM32_TIM_CCMR_ICF(3u));
    echo->CCER = STM32_TIM_CCER_CCE(1u) | STM32_TIM_CCER_CCE(2u) | STM32_TIM_CCER_CCP(2u);
    echo->SMCR = STM32_TIM_SMCR_TS_TI1FP1 | STM32_TIM_SMCR_SMS_RESET;
    echo->EGR = STM32_TIM_EGR_UG;
    echo->SR = 0u;
    echo->DIER = STM32_TIM_DIER_CC2IE;
    echo->CR1 = STM32_TIM_CR1_CEN;
    cm_nvic_enable(BOARD_ECHO_IRQ, BOARD_PRIO_ECHO);
}

/* The falling edge of an echo: post its width, nothing else. */
void BOARD_ECHO_IRQHandler(void)
{
    stm32_tim_t *tim = STM32_TIM(BOARD_ECHO_TIM);
    if ((tim->SR & STM32_TIM_SR_CC2IF) != 0u) {
        echo_width_us = tim->CCR[1]; /* reading CCR2 clears CC2IF */
        echo_seq = echo_seq + 1u;
    }
    /* rc_w0 flags: the zeros clear, the ones leave the other flags alone. */
    tim->SR = ~(STM32_TIM_SR_CC1IF | STM32_TIM_SR_CC1OF | STM32_TIM_SR_CC2OF);
}

void hal_servo_set_pulse(uint16_t pulse_us)
{
    uint32_t p = pulse_us < SERVO_MIN_US ? SERVO_MIN_US : pulse_us > SERVO_MAX_US ? SERVO_MAX_US : pulse_us;
    STM32_TIM(BOARD_SERVO_TIM)->CCR[BOARD_SERVO_CH - 1u] = p; /* preloaded: next period */
}

int hal_sonar_trigger(void)
{
    uint32_t now = hal_time_us();
    /* Busy while the echo of the last ping may still come; a ping whose echo came back
     * (polled or not) or that is older than the give-up time is over. */
    if (ping_out && echo_seq == ping_seq && now - ping_at_us < SONAR_GIVE_UP_US) {
        return HAL_EBUSY;
    }
    ping_seq = echo_seq;
    ping_at_us = now;
    ping_out = true;
    STM32_TIM(BOARD_TRIG_TIM)->CR1 = STM32_TIM_CR1_URS | STM32_TIM_CR1_OPM | STM32_TIM_CR1_CEN;
    return HAL_OK;
}

hal_sonar_status_t hal_sonar_poll(uint32_t *echo_us)
{
    if (!ping_out) {
        return HAL_SONAR_IDLE;
    }
    if (echo_seq != ping_seq) {
        uint32_t width = echo_width_us;
        ping_out = false;
        if (width >= SONAR_NO_ECHO_US) {
            return HAL_SONAR_TIMEOUT;
        }
        *echo_us = width;
        return HAL_SONAR_ECHO;
    }
    if (hal_time_us() - ping_at_us >= SONAR_GIVE_UP_US) {
        ping_out = false;
        return HAL_SONAR_TIMEOUT;
    }
    return HAL_SONAR_BUSY;
}
