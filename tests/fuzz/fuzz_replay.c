/* SPDX-License-Identifier: MIT */
/* Fuzz target: host_sim's readings.csv reader, every row it accepts mapped into OM. */
#define _POSIX_C_SOURCE 200809L /* fmemopen */
#include <math.h>
#include <string.h>

#include "fuzz.h"
#include "host_sim.h"

static grid_t grid;
static mapper_t mapper;
static loc_t loc;

static void map_row(void *ctx, const replay_row_t *row)
{
    unsigned *rows = ctx;
    (*rows)++;
    FUZZ_CHECK(row->servo_deg >= -360.0 && row->servo_deg <= 360.0);
    FUZZ_CHECK(row->range_m >= 0.0 && row->range_m <= 1000.0 && (row->echo || row->range_m == 0.0));
    FUZZ_CHECK(fabs(row->x_m) <= 1000.0 && fabs(row->y_m) <= 1000.0 && fabs(row->th_rad) <= 1000.0);
    /* As the replay takes it: mapped and matched, or mapped alone with the correction off. */
    const readq_reading_t rd = replay_reading(row);
    if (loc.on) {
        loc_reading(&loc, &mapper, &grid, &rd);
    } else {
        readq_map(&rd, &mapper, &grid);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0u) {
        return 0; /* fmemopen needs a byte; an empty file is tested in tests/sim */
    }
    static slam_config_t cfg;
    static bool ready;
    if (!ready) {
        slam_config_default(&cfg);
        grid_init(&grid, &cfg);
        mapper_init(&mapper, &cfg);
        ready = true;
    }
    loc_init(&loc, &cfg); /* what a file leaves held back is not the next file's */
    FILE *in = fmemopen((void *)(uintptr_t)data, size, "r");
    FUZZ_CHECK(in != NULL);
    unsigned rows = 0;
    char err[512] = "";
    if (replay_read(in, "fuzz.csv", map_row, &rows, err, sizeof err) != 0) {
        FUZZ_CHECK(strncmp(err, "fuzz.csv", 8) == 0);
    }
    fclose(in);
    loc_flush(&loc, &mapper, &grid);
    return 0;
}
