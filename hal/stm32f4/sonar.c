/* SPDX-License-Identifier: MIT */
/* Servo PWM and the HC-SR04s, one row of the board's tables each: a one-pulse timer triggers, a
 * PWM-input timer measures the echo. */
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

/* ---- the board's rows (BOARD_SERVOS, BOARD_SONARS) ------------------------------------------ */

typedef struct {
    volatile uint32_t *ccr; /* the PWM channel's compare register */
    uint32_t tim;           /* its timer */
    uint8_t ch;             /* its channel, 1..4 */
    stm32_pin_t pin;
} servo_row_t;

typedef struct {
    uint32_t trig_tim; /* one-pulse: setting CEN is the whole trigger */
    uint32_t echo_tim; /* PWM input */
    uint8_t trig_ch;   /* 1..4 */
    uint8_t echo_ch;   /* the echo pin's channel, 1 or 2; the other captures the width */
    uint8_t irq;       /* the echo timer's interrupt */
    bool echo_wide;    /* a 32-bit echo timer; a 16-bit one wraps after 65.5 ms */
    stm32_pin_t trig_pin;
    stm32_pin_t echo_pin;
} sonar_row_t;

#define COUNT_ROW(...) +1
enum { SERVOS = 0 BOARD_SERVOS(COUNT_ROW), SONARS = 0 BOARD_SONARS(COUNT_ROW) };
_Static_assert(SERVOS >= 1 && SONARS >= 1, "every board has instance 0 of each: the paper's");
_Static_assert(SERVOS <= 255 && SONARS <= 255, "instances are numbered by a uint8_t");

#define SERVO_CHECK(i, port, pin, af, tim, ch)                                                     \
    _Static_assert((ch) >= 1 && (ch) <= 4, "servo " #i ": a timer channel is 1..4");
#define SONAR_CHECK(i, tport, tpin, taf, ttim, tch, eport, epin, eaf, etim, ech, irq)              \
    _Static_assert((tch) >= 1 && (tch) <= 4, "sonar " #i ": a timer channel is 1..4");             \
    _Static_assert((ech) == 1 || (ech) == 2, "sonar " #i ": PWM input takes CH1 or CH2");
BOARD_SERVOS(SERVO_CHECK)
BOARD_SONARS(SONAR_CHECK)

/* Designated by index, so a row numbered twice or past the count fails the build. */
#define SERVO_ROW(i, port, pin, af, tim, ch)                                                       \
    [i] = {&STM32_TIM(STM32_##tim##_BASE)->CCR[(ch)-1u],                                           \
           STM32_##tim##_BASE,                                                                     \
           ch,                                                                                     \
           {port, pin, STM32_PIN_AF, af, STM32_PIN_NOPULL, STM32_PIN_PUSHPULL, 0}},
#define SONAR_ROW(i, tport, tpin, taf, ttim, tch, eport, epin, eaf, etim, ech, irq)                \
    [i] = {STM32_##ttim##_BASE,                                                                    \
           STM32_##etim##_BASE,                                                                    \
           tch,                                                                                    \
           ech,                                                                                    \
           STM32_IRQ_##irq,                                                                        \
           STM32_##etim##_BASE == STM32_TIM2_BASE || STM32_##etim##_BASE == STM32_TIM5_BASE,       \
           {tport, tpin, STM32_PIN_AF, taf, STM32_PIN_NOPULL, STM32_PIN_PUSHPULL, 0},              \
           {eport, epin, STM32_PIN_AF, eaf, STM32_PIN_PULLDOWN, STM32_PIN_PUSHPULL, 0}},

static const servo_row_t servos[SERVOS] = {BOARD_SERVOS(SERVO_ROW)};
static const sonar_row_t sonars[SONARS] = {BOARD_SONARS(SONAR_ROW)};

/* Posted by each sonar's capture interrupt: the width of its last echo and a count of echoes. */
static volatile struct {
    uint32_t width_us;
    uint32_t seq;
} echoes[SONARS];

/* The tick's view of each sonar's ping under way. */
static struct {
    bool out;
    uint32_t seq;   /* echoes[].seq when the ping went out */
    uint32_t at_us; /* hal_time_us() when it went out */
} pings[SONARS];

/* ---- start-up -------------------------------------------------------------------------------- */

STM32_START_UP static void timer_1mhz(stm32_tim_t *tim, uint32_t base)
{
    (void)stm32_periph_enable(base);
    tim->CR1 = 0u;
    tim->PSC = stm32_timer_clock_hz(base) / 1000000u - 1u;
}

/* PWM mode 1 at 50 Hz, 1 µs a count; no pulse until the firmware asks. */
STM32_START_UP static void servo_setup(const servo_row_t *r)
{
    stm32_tim_t *servo = STM32_TIM(r->tim);
    timer_1mhz(servo, r->tim);
    servo->ARR = SERVO_PERIOD_US - 1u;
    *r->ccr = 0u;
    (r->ch <= 2u ? &servo->CCMR1 : &servo->CCMR2)[0] |=
        STM32_TIM_CCMR_CH(r->ch, STM32_TIM_CCMR_OCM_PWM1 | STM32_TIM_CCMR_OCPE);
    servo->CCER = STM32_TIM_CCER_CCE(r->ch);
    servo->EGR = STM32_TIM_EGR_UG;
    servo->CR1 = STM32_TIM_CR1_ARPE | STM32_TIM_CR1_CEN;
    stm32_gpio_setup(&r->pin, 1u); /* now that the channel drives it low */
}

STM32_START_UP static void sonar_setup(const sonar_row_t *r)
{
    /* Trigger: one-pulse mode, PWM mode 2: low until CCR = 1, high until ARR, then the
     * counter stops by itself. Setting CEN is the whole trigger. */
    stm32_tim_t *trig = STM32_TIM(r->trig_tim);
    timer_1mhz(trig, r->trig_tim);
    trig->ARR = BOARD_TRIG_PULSE_US; /* pulse = ARR - CCR + 1 */
    trig->CCR[r->trig_ch - 1u] = 1u;
    (r->trig_ch <= 2u ? &trig->CCMR1 : &trig->CCMR2)[0] |=
        STM32_TIM_CCMR_CH(r->trig_ch, STM32_TIM_CCMR_OCM_PWM2);
    trig->CCER = STM32_TIM_CCER_CCE(r->trig_ch);
    trig->BDTR = STM32_TIM_BDTR_MOE; /* an advanced timer (TIM1, TIM8) drives no pin without it */
    trig->CR1 = STM32_TIM_CR1_URS | STM32_TIM_CR1_OPM;
    trig->EGR = STM32_TIM_EGR_UG;

    /* Echo: PWM-input mode (RM0090 §18.3.6). The rising edge on the pin's channel resets the
     * counter (through its TIxFPx); the falling edge captures into the other channel's CCR,
     * which then holds the width in µs. A 16-bit timer counts only overflows as updates
     * (URS), so its interrupt can tell a width that wrapped. */
    unsigned pin = r->echo_ch;
    unsigned width = 3u - pin;
    stm32_tim_t *echo = STM32_TIM(r->echo_tim);
    timer_1mhz(echo, r->echo_tim);
    echo->ARR = r->echo_wide ? 0xFFFFFFFFu : 0xFFFFu;
    echo->CCMR1 = STM32_TIM_CCMR_CH(pin, STM32_TIM_CCMR_CCS_TI_SAME | STM32_TIM_CCMR_ICF(3u)) |
                  STM32_TIM_CCMR_CH(width, STM32_TIM_CCMR_CCS_TI_OTHER | STM32_TIM_CCMR_ICF(3u));
    echo->CCER = STM32_TIM_CCER_CCE(1u) | STM32_TIM_CCER_CCE(2u) | STM32_TIM_CCER_CCP(width);
    echo->SMCR = (pin == 1u ? STM32_TIM_SMCR_TS_TI1FP1 : STM32_TIM_SMCR_TS_TI2FP2) |
                 STM32_TIM_SMCR_SMS_RESET;
    echo->EGR = STM32_TIM_EGR_UG;
    echo->SR = 0u;
    echo->DIER = STM32_TIM_DIER_CCIE(width);
    echo->CR1 = r->echo_wide ? STM32_TIM_CR1_CEN : STM32_TIM_CR1_URS | STM32_TIM_CR1_CEN;
    stm32_gpio_setup(&r->trig_pin, 1u);
    stm32_gpio_setup(&r->echo_pin, 1u);
    cm_nvic_enable(r->irq, BOARD_PRIO_ECHO);
}

STM32_START_UP void stm32_sonar_init(void)
{
    for (unsigned i = 0; i < SERVOS; i++) {
        servo_setup(&servos[i]);
    }
    for (unsigned i = 0; i < SONARS; i++) {
        sonar_setup(&sonars[i]);
    }
}

/* ---- the echoes' interrupts --------------------------------------------------------------------
 */

/* The falling edge of sonar i's echo: post its width, nothing else. */
static inline __attribute__((always_inline)) void echo_capture(unsigned i)
{
    const sonar_row_t *r = &sonars[i];
    stm32_tim_t *tim = STM32_TIM(r->echo_tim);
    unsigned pin = r->echo_ch;
    unsigned width = 3u - pin;
    uint32_t sr = tim->SR;
    if ((sr & STM32_TIM_SR_CCIF(width)) != 0u) {
        uint32_t w = tim->CCR[width - 1u]; /* reading the CCR clears its flag */
        /* An overflow since the trigger (which cleared UIF): longer than 16 bits can say. */
        echoes[i].width_us = r->echo_wide || (sr & STM32_TIM_SR_UIF) == 0u ? w : UINT32_MAX;
        echoes[i].seq = echoes[i].seq + 1u;
    }
    /* rc_w0 flags: the zeros clear, the ones leave the other flags alone. */
    tim->SR = ~(STM32_TIM_SR_CCIF(pin) | STM32_TIM_SR_CCOF(pin) | STM32_TIM_SR_CCOF(width));
}

#define ECHO_HANDLER(i, tport, tpin, taf, ttim, tch, eport, epin, eaf, etim, ech, irq)             \
    void irq##_IRQHandler(void)                                                                    \
    {                                                                                              \
        echo_capture(i);                                                                           \
    }
BOARD_SONARS(ECHO_HANDLER)

/* ---- hal.h -------------------------------------------------------------------------------------
 */

uint8_t hal_servo_count(void)
{
    return SERVOS;
}

uint8_t hal_sonar_count(void)
{
    return SONARS;
}

/* With one instance of a kind (every shipped board), the index check leaves the index known
 * to be 0, and the rows fold into constants: the tick pays for the check alone. */

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo >= SERVOS) {
        return HAL_EINVAL;
    }
    uint32_t p = pulse_us < SERVO_MIN_US   ? SERVO_MIN_US
                 : pulse_us > SERVO_MAX_US ? SERVO_MAX_US
                                           : pulse_us;
    *servos[servo].ccr = p; /* preloaded: next period */
    return HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar >= SONARS) {
        return HAL_EINVAL;
    }
    const sonar_row_t *r = &sonars[sonar];
    uint32_t now = hal_time_us();
    /* Busy while the echo of the last ping may still come; a ping whose echo came back
     * (polled or not) or that is older than the give-up time is over. */
    if (pings[sonar].out && echoes[sonar].seq == pings[sonar].seq &&
        now - pings[sonar].at_us < SONAR_GIVE_UP_US) {
        return HAL_EBUSY;
    }
    pings[sonar].seq = echoes[sonar].seq;
    pings[sonar].at_us = now;
    pings[sonar].out = true;
    if (!r->echo_wide) {
        /* A 16-bit echo timer starts from 0 with no overflow seen: it cannot wrap before
         * the echo rises (the sensor answers within a few ms). */
        stm32_tim_t *echo = STM32_TIM(r->echo_tim);
        echo->EGR = STM32_TIM_EGR_UG;
        echo->SR = ~STM32_TIM_SR_UIF;
    }
    STM32_TIM(r->trig_tim)->CR1 = STM32_TIM_CR1_URS | STM32_TIM_CR1_OPM | STM32_TIM_CR1_CEN;
    return HAL_OK;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar >= SONARS) {
        return HAL_EINVAL;
    }
    if (!pings[sonar].out) {
        return HAL_SONAR_IDLE;
    }
    if (echoes[sonar].seq != pings[sonar].seq) {
        uint32_t width = echoes[sonar].width_us;
        pings[sonar].out = false;
        if (width >= SONAR_NO_ECHO_US) {
            return HAL_SONAR_TIMEOUT;
        }
        *echo_us = width;
        return HAL_SONAR_ECHO;
    }
    if (hal_time_us() - pings[sonar].at_us >= SONAR_GIVE_UP_US) {
        pings[sonar].out = false;
        return HAL_SONAR_TIMEOUT;
    }
    return HAL_SONAR_BUSY;
}
