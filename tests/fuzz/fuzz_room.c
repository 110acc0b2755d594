/* SPDX-License-Identifier: MIT */
/* Fuzz target: the .room parser, then the geometry and the simulated robot on what it took. */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "host/sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    room_t r;
    char err[512] = "";
    if (room_parse(&r, "fuzz.room", (const char *)data, size, err, sizeof err) != 0) {
        FUZZ_CHECK(strncmp(err, "fuzz.room", 9) == 0); /* every error names the file */
        return 0;
    }
    FUZZ_CHECK(r.has_start && r.nsegs + r.ncircles > 0u);
    FUZZ_CHECK(r.min_x <= r.max_x && r.min_y <= r.max_y);
    FUZZ_CHECK(room_disc_free(&r, r.start_x, r.start_y, ROOM_BODY_RADIUS_M));
    /* A large room's index answers as a look at every object does. */
    room_t every = r;
    every.index = NULL;
    for (int k = 0; k < 8; k++) {
        double dir = k * 0.785398163397448;
        double x = r.start_x + 0.3 * cos(3.0 * dir);
        double y = r.start_y + 0.3 * sin(3.0 * dir);
        double c1 = 0.0;
        double c2 = 0.0;
        double a = room_ray(&r, x, y, dir, 10.0, &c1);
        double b = room_ray(&every, x, y, dir, 10.0, &c2);
        FUZZ_CHECK(a == b && a >= 0.0);
        FUZZ_CHECK(room_clearance(&r, x, y, 0.34) == room_clearance(&every, x, y, 0.34));
    }
    (void)room_encloses(&r, r.start_x, r.start_y, NULL);
    static uint8_t truth[32 * 32];
    room_rasterize(&r, r.start_x - 0.8, r.start_y - 0.8, 0.05, 32u, 32u, truth);
    /* The robot drives and pings in it. */
    sim_params_t p;
    sim_params_default(&p);
    sim_errors_t e;
    sim_errors_default(&e);
    sim_t *s = sim_create(&r, &p, &e, size);
    FUZZ_CHECK(s != NULL);
    sim_motor_set(s, HAL_WHEEL_LEFT, 900);
    sim_motor_set(s, HAL_WHEEL_RIGHT, 700);
    for (int t = 0; t < 20; t++) {
        sim_servo_set_pulse(s, (uint16_t)(600 + 100 * t));
        (void)sim_sonar_trigger(s);
        uint32_t w;
        (void)sim_sonar_poll(s, &w);
        sim_step(s);
    }
    sim_truth_t tr = sim_truth(s);
    /* The body never overlaps an obstacle. */
    FUZZ_CHECK(isfinite(tr.x) && isfinite(tr.y) &&
               room_clearance(&r, tr.x, tr.y, p.body_radius_m) >= p.body_radius_m - 1e-9);
    sim_destroy(s);
    room_free(&r);
    return 0;
}
