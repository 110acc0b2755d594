/* SPDX-License-Identifier: MIT */
/* The wheels: two timers in encoder mode, and PWM plus direction pins for two motors. */
#include "board.h"
#include "cortex_m.h"
#include "hal/hal.h"
#include "stm32f4_port.h"

typedef struct {
    volatile uint32_t *ccr; /* the PWM channel's compare register */
    uint32_t forward;       /* BSRR word for forward: IN1 high, IN2 low */
    uint32_t reverse;       /* BSRR word for reverse: IN1 low, IN2 high */
    uint32_t off;           /* BSRR word for coasting: both low */
} motor_t;

#define DIR_WORDS(in1, in2, invert)                                                                \
    .forward =                                                                                     \
        (invert) ? (1u << (in2)) | (1u << ((in1) + 16u)) : (1u << (in1)) | (1u << ((in2) + 16u)),  \
    .reverse =                                                                                     \
        (invert) ? (1u << (in1)) | (1u << ((in2) + 16u)) : (1u << (in2)) | (1u << ((in1) + 16u)),  \
    .off = (1u << ((in1) + 16u)) | (1u << ((in2) + 16u))

static const motor_t motors[2] = {
    {.ccr = &STM32_TIM(BOARD_MOTOR_TIM)->CCR[BOARD_MOTOR_LEFT_CH - 1u],
     DIR_WORDS(BOARD_MOTOR_LEFT_IN1, BOARD_MOTOR_LEFT_IN2, BOARD_MOTOR_LEFT_INVERT)},
    {.ccr = &STM32_TIM(BOARD_MOTOR_TIM)->CCR[BOARD_MOTOR_RIGHT_CH - 1u],
     DIR_WORDS(BOARD_MOTOR_RIGHT_IN1, BOARD_MOTOR_RIGHT_IN2, BOARD_MOTOR_RIGHT_INVERT)},
};

static uint32_t motor_period; /* timer counts in one PWM period: full duty */
static uint32_t motor_dir[2]; /* the BSRR word the direction pins were last given */

STM32_START_UP static void encoder_setup(uint32_t base, bool invert)
{
    stm32_tim_t *tim = STM32_TIM(base);
    (void)stm32_periph_enable(base);
    tim->CR1 = 0u;
    tim->SMCR = 0u;
    uint32_t in = STM32_TIM_CCMR_CCS_TI_SAME | STM32_TIM_CCMR_ICF(BOARD_ENC_FILTER);
    tim->CCMR1 = STM32_TIM_CCMR_CH(1u, in) | STM32_TIM_CCMR_CH(2u, in);
    /* Inverting TI1 reverses the count, so forward always counts up. */
    tim->CCER = invert ? STM32_TIM_CCER_CCP(1u) : 0u;
    tim->SMCR = STM32_TIM_SMCR_SMS_ENCODER3;
    tim->PSC = 0u;
    tim->ARR = 0xFFFFu; /* the full 16 bits: the core handles the wrap */
    tim->CNT = 0u;
    tim->CR1 = STM32_TIM_CR1_CEN;
}

STM32_START_UP void stm32_wheels_init(void)
{
    encoder_setup(BOARD_ENC_LEFT_TIM, BOARD_ENC_LEFT_INVERT);
    encoder_setup(BOARD_ENC_RIGHT_TIM, BOARD_ENC_RIGHT_INVERT);

    stm32_tim_t *tim = STM32_TIM(BOARD_MOTOR_TIM);
    (void)stm32_periph_enable(BOARD_MOTOR_TIM);
    tim->CR1 = 0u;
    motor_period = stm32_timer_clock_hz(BOARD_MOTOR_TIM) / BOARD_MOTOR_PWM_HZ;
    tim->PSC = 0u;
    tim->ARR = motor_period - 1u;
    tim->CCR[BOARD_MOTOR_LEFT_CH - 1u] = 0u;
    tim->CCR[BOARD_MOTOR_RIGHT_CH - 1u] = 0u;
    uint32_t pwm = STM32_TIM_CCMR_OCM_PWM1 | STM32_TIM_CCMR_OCPE; /* new duty at the next period */
    volatile uint32_t *ccmr_l = BOARD_MOTOR_LEFT_CH <= 2u ? &tim->CCMR1 : &tim->CCMR2;
    volatile uint32_t *ccmr_r = BOARD_MOTOR_RIGHT_CH <= 2u ? &tim->CCMR1 : &tim->CCMR2;
    *ccmr_l |= STM32_TIM_CCMR_CH(BOARD_MOTOR_LEFT_CH, pwm);
    *ccmr_r |= STM32_TIM_CCMR_CH(BOARD_MOTOR_RIGHT_CH, pwm);
    tim->CCER = STM32_TIM_CCER_CCE(BOARD_MOTOR_LEFT_CH) | STM32_TIM_CCER_CCE(BOARD_MOTOR_RIGHT_CH);
    tim->BDTR = STM32_TIM_BDTR_MOE; /* needed if the board puts the motors on TIM1/TIM8 */
    tim->EGR = STM32_TIM_EGR_UG;
    tim->CR1 = STM32_TIM_CR1_ARPE | STM32_TIM_CR1_CEN;

    STM32_GPIO(BOARD_MOTOR_DIR_PORT)->BSRR = motors[0].off | motors[1].off;
    motor_dir[0] = motors[0].off;
    motor_dir[1] = motors[1].off;
    stm32_gpio_write(BOARD_MOTOR_STBY_PORT, BOARD_MOTOR_STBY_PIN, true);
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    uint32_t base = wheel == HAL_WHEEL_RIGHT ? BOARD_ENC_RIGHT_TIM : BOARD_ENC_LEFT_TIM;
    return (uint16_t)STM32_TIM(base)->CNT;
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    unsigned i = (unsigned)wheel & 1u;
    const motor_t *m = &motors[i];
    int32_t d = duty;
    uint32_t dir = m->forward;
    if (d > HAL_DUTY_MAX) {
        d = HAL_DUTY_MAX;
    } else if (d < 0) {
        d = d < -HAL_DUTY_MAX ? HAL_DUTY_MAX : -d;
        dir = m->reverse;
    } else if (d == 0) {
        dir = m->off;
    }
    volatile uint32_t *ccr = m->ccr;
    if (dir != motor_dir[i]) {
        /* The duty in force was meant for the old direction, and a CCR write only takes
         * effect at the end of the period: zero it and load it now (UG, which restarts the
         * period of both channels), then turn, in one BSRR write. */
        motor_dir[i] = dir;
        *ccr = 0u;
        STM32_TIM(BOARD_MOTOR_TIM)->EGR = STM32_TIM_EGR_UG;
        STM32_GPIO(BOARD_MOTOR_DIR_PORT)->BSRR = dir;
    }
    *ccr = (uint32_t)d * motor_period / HAL_DUTY_MAX; /* from the next period */
}

STM32_START_UP void cm_safe_outputs(void)
{
    stm32_tim_t *tim = STM32_TIM(BOARD_MOTOR_TIM);
    tim->CCR[BOARD_MOTOR_LEFT_CH - 1u] = 0u;
    tim->CCR[BOARD_MOTOR_RIGHT_CH - 1u] = 0u;
    tim->EGR = STM32_TIM_EGR_UG; /* now, not at the end of the period */
    STM32_GPIO(BOARD_MOTOR_DIR_PORT)->BSRR = motors[0].off | motors[1].off;
    motor_dir[0] = motors[0].off;
    motor_dir[1] = motors[1].off;
    stm32_gpio_write(BOARD_MOTOR_STBY_PORT, BOARD_MOTOR_STBY_PIN, false);
}
