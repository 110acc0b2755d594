/* SPDX-License-Identifier: MIT */
/* --check: open every line, PWM channel, the telemetry stream and the storage directory, move
 * nothing. */
#define _GNU_SOURCE
#include <stdbool.h>
#include <stdio.h>

#include "lhal/gpio_if.h"
#include "lhal/lhal.h"
#include "lhal/pwm.h"
#include "lhal/serial.h"
#include "lhal/store.h"

static unsigned lx_check_item(FILE *out, const char *what, int ok, const char *detail)
{
    fprintf(out, "  %-24s %s%s\n", what,
            ok ? "ok" : "FAIL: ", ok ? (detail[0] ? detail : "") : detail);
    return ok ? 0u : 1u;
}

unsigned lhal_check(const lconf_t *cfg, FILE *out)
{
    unsigned bad = 0u;
    unsigned items = 0u;
    char msg[256];
    char detail[600];

    gpio_chip_t *chip = NULL;
    int ok = gpio_chip_open(cfg->gpio_chip, &chip, msg, sizeof msg) == 0;
    if (ok) {
        snprintf(detail, sizeof detail, " (%s, %u lines)", gpio_chip_describe(chip),
                 gpio_chip_lines(chip));
    }
    bad += lx_check_item(out, "gpio_chip", ok, ok ? detail : msg);
    items++;
    lconf_line_t lines[LCONF_LINES];
    lconf_lines(cfg, lines);
    for (unsigned i = 0u; i < LCONF_LINES; i++) {
        if (lines[i].offset == LCONF_NO_LINE) {
            continue;
        }
        items++;
        if (chip == NULL) {
            bad += lx_check_item(out, lines[i].name, 0, "not checked: no GPIO chip");
            continue;
        }
        gpio_line_t *line = NULL;
        unsigned off = (unsigned)lines[i].offset;
        bool input = lines[i].bias != LCONF_OUTPUT;
        ok =
            (input ? gpio_line_edges(chip, off, (lconf_bias_t)lines[i].bias, &line, msg, sizeof msg)
                   : gpio_line_output(chip, off, 0, &line, msg, sizeof msg)) == 0;
        if (ok && input) {
            snprintf(detail, sizeof detail, " (line %u, input, now %s)", off,
                     gpio_line_get(line) == 1 ? "high" : "low");
        } else if (ok) {
            snprintf(detail, sizeof detail, " (line %u, output, held low)", off);
        }
        bad += lx_check_item(out, lines[i].name, ok, ok ? detail : msg);
    }
    gpio_chip_close(chip);

    const struct {
        const char *name;
        lconf_pwm_t pwm;
    } pwms[] = {{"servo_pwm", cfg->servo_pwm},
                {"motor_left_pwm", cfg->motor_pwm[0]},
                {"motor_right_pwm", cfg->motor_pwm[1]},
                {"servo1_pwm", cfg->servo1_pwm}};
    for (unsigned i = 0u; i < sizeof pwms / sizeof pwms[0]; i++) {
        if (pwms[i].pwm.chip < 0 || pwms[i].pwm.channel < 0) {
            continue; /* an optional channel that is not wired */
        }
        pwm_chan_t p;
        items++;
        ok = pwm_open(&p, cfg->pwm_root, (unsigned)pwms[i].pwm.chip, (unsigned)pwms[i].pwm.channel,
                      PWM_EXPORT_WAIT_MS, msg, sizeof msg) == 0 &&
             pwm_writable(&p, msg, sizeof msg) == 0;
        snprintf(detail, sizeof detail, " (%s)", p.dir);
        bad += lx_check_item(out, pwms[i].name, ok, ok ? detail : msg);
    }

    serial_t uart;
    items++;
    ok = serial_open(&uart, cfg->telemetry, cfg->telemetry_baud, msg, sizeof msg) == 0;
    snprintf(detail, sizeof detail, " (%s)", uart.name);
    bad += lx_check_item(out, "telemetry", ok, ok ? detail : msg);
    serial_close(&uart);

    items++;
    ok = store_probe(cfg->storage_dir, msg, sizeof msg) == 0;
    snprintf(detail, sizeof detail, " (%s: %s)", cfg->storage_dir, msg);
    bad += lx_check_item(out, "storage_dir", ok, ok ? detail : msg);

    if (bad == 0u) {
        fprintf(out, "check: all %u items ok\n", items);
    } else {
        fprintf(out, "check: %u of %u items failed\n", bad, items);
    }
    return bad;
}
