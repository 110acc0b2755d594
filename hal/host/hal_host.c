/* SPDX-License-Identifier: MIT */
/* The host backend: every call of hal/hal.h against the attached simulated world. */
#include <stdbool.h>
#include <string.h>

#include "hal/hal.h"
#include "hal_common/trace.h"
#include "host/sim.h"

/* Bytes in each storage slot: OM and TM of a 160 x 160 grid with room to spare, the
 * size of an MCU's flash sector; hal_host_storage_resize() makes room for larger grids. */
#define HOST_STORAGE_SIZE (128u * 1024u)

static struct {
    sim_t *sim;
    bool lossy; /* the world may lose ticks (tick_miss) */
    hal_tick_fn fn;
    void *ctx;
    uint64_t t0_us; /* world time at hal_init() */
    FILE *uart;
    uint8_t rx[HAL_HOST_UART_RX_BYTES]; /* received, not yet read: rx_head - rx_tail bytes */
    size_t rx_head, rx_tail;
    FILE *trace;
    uint64_t trace_ticks;
    bool untraced_said; /* the firmware was told the trace misses what it used */
    bool recording;     /* a tick is under way and a trace records its HAL calls */
    trace_tick_t rec;   /* what the firmware saw in the tick under way */
    uint8_t storage[HAL_STORAGE_SLOTS][HAL_HOST_STORAGE_MAX];
    size_t storage_size; /* bytes of each slot in use; 0 until the first use */
    bool rewriting[HAL_STORAGE_SLOTS];
    bool storage_ready;
} hh;

static void storage_erase(uint8_t slot)
{
    memset(hh.storage[slot], 0xFF, HAL_HOST_STORAGE_MAX); /* as erased flash reads */
}

/* Storage starts erased, once per process: it outlives worlds and hal_init(). */
static void storage_power_on(void)
{
    if (hh.storage_size == 0u) {
        hh.storage_size = HOST_STORAGE_SIZE;
    }
    if (!hh.storage_ready) {
        for (uint8_t i = 0; i < HAL_STORAGE_SLOTS; i++) {
            storage_erase(i);
        }
        hh.storage_ready = true;
    }
}

void hal_host_attach(sim_t *s)
{
    hh.sim = s;
    hh.lossy = s != NULL && sim_ticks_lost(s);
    hh.fn = NULL;
    hh.ctx = NULL;
    hh.t0_us = s != NULL ? sim_truth(s).time_us : 0u;
    hh.recording = false;
    hh.rx_head = hh.rx_tail = 0u; /* nothing received survives a power-up */
}

void hal_host_uart_sink(FILE *f)
{
    hh.uart = f;
}

size_t hal_host_uart_receive(const uint8_t *data, size_t len)
{
    size_t room = HAL_HOST_UART_RX_BYTES - (hh.rx_head - hh.rx_tail);
    size_t n = len < room ? len : room;
    for (size_t i = 0; i < n; i++) {
        hh.rx[hh.rx_head++ % HAL_HOST_UART_RX_BYTES] = data[i];
    }
    return n;
}

void hal_host_trace(FILE *f)
{
    if (hh.trace != NULL && hh.trace != f) {
        trace_write_end(hh.trace, hh.trace_ticks);
        fflush(hh.trace);
    }
    if (hh.trace != f) {
        hh.trace_ticks = 0u;
        hh.untraced_said = false;
    }
    hh.trace = f;
}

void hal_host_step(void)
{
    if (hh.sim == NULL) {
        return;
    }
    if (hh.fn != NULL && !(hh.lossy && sim_tick_lost(hh.sim))) {
        /* Without a trace nothing of the tick is recorded (it cost 60 instructions a tick). */
        hh.recording = hh.trace != NULL;
        if (hh.recording) {
            hh.rec = (trace_tick_t){
                .enc = {sim_encoder_count(hh.sim, HAL_WHEEL_LEFT),
                        sim_encoder_count(hh.sim, HAL_WHEEL_RIGHT)},
                .poll = '-',
                .trig = '-',
            };
        }
        hh.fn(hh.ctx);
        if (hh.recording) {
            hh.recording = false;
            hh.rec.duty[0] = sim_motor_duty(hh.sim, HAL_WHEEL_LEFT);
            hh.rec.duty[1] = sim_motor_duty(hh.sim, HAL_WHEEL_RIGHT);
            hh.rec.servo_us = sim_servo_pulse_on(hh.sim, HAL_SERVO_SWEEP);
            trace_write_tick(hh.trace, &hh.rec);
            hh.trace_ticks++;
        }
    }
    sim_step(hh.sim);
}

/* ---- hal.h ----------------------------------------------------------------------------- */

int hal_init(void)
{
    if (hh.sim == NULL) {
        fprintf(stderr, "hal_host: no world attached (call hal_host_attach() first)\n");
        return HAL_EIO;
    }
    storage_power_on();
    hh.fn = NULL;
    hh.ctx = NULL;
    hh.t0_us = sim_truth(hh.sim).time_us;
    sim_motor_set(hh.sim, HAL_WHEEL_LEFT, 0);
    sim_motor_set(hh.sim, HAL_WHEEL_RIGHT, 0);
    return HAL_OK;
}

int hal_tick_start(hal_tick_fn fn, void *ctx)
{
    if (fn == NULL) {
        return HAL_EINVAL;
    }
    if (hh.fn != NULL) {
        return HAL_EBUSY;
    }
    hh.fn = fn; /* the caller drives time with hal_host_step() */
    hh.ctx = ctx;
    return HAL_OK;
}

uint32_t hal_time_us(void)
{
    return hh.sim != NULL ? (uint32_t)(sim_truth(hh.sim).time_us - hh.t0_us) : 0u;
}

uint32_t hal_tick_overruns(void)
{
    /* Virtual time: a tick never overruns, but one may be lost (the tick_miss fault). */
    return hh.sim != NULL ? (uint32_t)sim_ticks_missed(hh.sim) : 0u;
}

uint16_t hal_encoder_count(hal_wheel_t wheel)
{
    return hh.sim != NULL ? sim_encoder_count(hh.sim, wheel) : 0u;
}

void hal_motor_set(hal_wheel_t wheel, int16_t duty)
{
    if (hh.sim != NULL) {
        sim_motor_set(hh.sim, wheel, duty);
    }
}

/* A trace (version 1) records the paper's servo and sonar, instance 0, the only ones the
 * firmware uses: a tick that uses another instance or a bump switch makes a trace that
 * will not replay, and is said so once. */
static void untraced(const char *what, unsigned instance)
{
    if (hh.recording && !hh.untraced_said) {
        fprintf(stderr,
                "hal_host: warning: the HAL trace records servo and sonar 0 only; the firmware "
                "used %s %u, so the trace will not replay it\n",
                what, instance);
        hh.untraced_said = true;
    }
}

uint8_t hal_servo_count(void)
{
    return hh.sim != NULL ? sim_servo_count(hh.sim) : 1u;
}

uint8_t hal_sonar_count(void)
{
    return hh.sim != NULL ? sim_sonar_count(hh.sim) : 1u;
}

int hal_servo_set_pulse(uint8_t servo, uint16_t pulse_us)
{
    if (servo >= hal_servo_count()) {
        return HAL_EINVAL;
    }
    if (servo != HAL_SERVO_SWEEP) {
        untraced("servo", servo);
    }
    return hh.sim != NULL ? sim_servo_set_pulse_on(hh.sim, servo, pulse_us) : HAL_OK;
}

int hal_sonar_trigger(uint8_t sonar)
{
    if (sonar >= hal_sonar_count()) {
        return HAL_EINVAL;
    }
    if (hh.sim == NULL) {
        return HAL_EIO;
    }
    int rc = sim_sonar_trigger_on(hh.sim, sonar);
    if (sonar != HAL_SONAR_SWEPT) {
        untraced("sonar", sonar);
    } else if (hh.recording) {
        hh.rec.trig = rc == HAL_OK ? 'o' : 'b';
    }
    return rc;
}

int hal_sonar_poll(uint8_t sonar, uint32_t *echo_us)
{
    if (sonar >= hal_sonar_count()) {
        return HAL_EINVAL;
    }
    if (hh.sim == NULL) {
        return HAL_SONAR_IDLE;
    }
    uint32_t width = 0u;
    int st = sim_sonar_poll_on(hh.sim, sonar, &width);
    if (st == HAL_SONAR_ECHO) {
        *echo_us = width;
    }
    if (sonar != HAL_SONAR_SWEPT) {
        untraced("sonar", sonar);
    } else if (hh.recording) {
        static const char code[] = {'i', 'b', 'e', 't'};
        hh.rec.poll = code[st];
        hh.rec.echo_us = st == HAL_SONAR_ECHO ? width : 0u;
    }
    return st;
}

uint8_t hal_bump_count(void)
{
    return hh.sim != NULL ? sim_bump_count(hh.sim) : 0u;
}

int hal_bump_read(uint8_t bump, bool *pressed)
{
    if (hh.sim == NULL) {
        return HAL_ENOSYS;
    }
    int rc = sim_bump_read(hh.sim, bump, pressed);
    if (rc == HAL_OK) {
        untraced("bump switch", bump);
    }
    return rc;
}

size_t hal_uart_write(const uint8_t *data, size_t len)
{
    if (hh.uart != NULL && len > 0u) {
        return fwrite(data, 1u, len, hh.uart);
    }
    return len; /* no cable: the bytes go nowhere, as on a robot without a radio */
}

bool hal_uart_has_reader(void)
{
    return hh.uart != NULL; /* without a sink hal_uart_write() discards every byte */
}

size_t hal_uart_read(uint8_t *data, size_t len)
{
    size_t n = 0;
    while (n < len && hh.rx_tail != hh.rx_head) {
        data[n++] = hh.rx[hh.rx_tail++ % HAL_HOST_UART_RX_BYTES];
    }
    return n;
}

void hal_host_storage_resize(size_t bytes)
{
    hh.storage_size = bytes > HAL_HOST_STORAGE_MAX ? HAL_HOST_STORAGE_MAX : bytes;
    hh.storage_ready = false;
    storage_power_on();
}

const uint8_t *hal_host_storage_slot(uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS) {
        return NULL;
    }
    storage_power_on();
    return hh.storage[slot];
}

size_t hal_storage_size(void)
{
    storage_power_on();
    return hh.storage_size;
}

/* A range [offset, offset + len) inside a slot, without overflow. */
static bool storage_range_ok(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    return slot < HAL_STORAGE_SLOTS && offset <= hh.storage_size &&
           len <= hh.storage_size - offset && (data != NULL || len == 0u);
}

int hal_storage_begin(uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS) {
        return HAL_EINVAL;
    }
    storage_power_on();
    storage_erase(slot);
    hh.rewriting[slot] = true;
    return HAL_OK;
}

int hal_storage_write(uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    if (!storage_range_ok(slot, offset, data, len) || !hh.rewriting[slot]) {
        return HAL_EINVAL;
    }
    if (len > 0u) {
        memcpy(&hh.storage[slot][offset], data, len);
    }
    return HAL_OK;
}

int hal_storage_commit(uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS || !hh.rewriting[slot]) {
        return HAL_EINVAL;
    }
    hh.rewriting[slot] = false;
    return HAL_OK;
}

int hal_storage_read(uint8_t slot, uint32_t offset, void *data, size_t len)
{
    if (!storage_range_ok(slot, offset, data, len)) {
        return HAL_EINVAL;
    }
    storage_power_on();
    if (len > 0u) {
        memcpy(data, &hh.storage[slot][offset], len);
    }
    return HAL_OK;
}

hal_irq_state_t hal_critical_enter(void)
{
    return 0u; /* one thread: the tick never interrupts anything */
}

void hal_critical_exit(hal_irq_state_t state)
{
    (void)state;
}

void hal_watchdog_kick(void)
{
}
