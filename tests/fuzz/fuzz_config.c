/* SPDX-License-Identifier: MIT */
/*
 * Fuzz target: the configuration text (hal/common/config_text.c) with the Linux robot's
 * own keys (robot.conf). What loads must pass the core's check and read back the same
 * after writing; what does not load must change nothing.
 */
#define _POSIX_C_SOURCE 200809L /* fmemopen */
#include <string.h>

#include "fuzz.h"
#include "hal_common/config_text.h"
#include "lhal/lconf.h"
#include "slam/error.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    slam_config_t cfg;
    slam_config_default(&cfg);
    slam_config_t before = cfg;
    lconf_t lc;
    lconf_default(&lc);
    cfgtext_where_t where;
    char err[512] = "";
    if (cfgtext_parse_in("fuzz.conf", (const char *)data, size, "linux", &cfg, lconf_set, &lc,
                         &where, err, sizeof err) != 0) {
        FUZZ_CHECK(strncmp(err, "fuzz.conf", 9) == 0);
        FUZZ_CHECK(memcmp(&cfg, &before, sizeof cfg) == 0);
        return 0;
    }
    FUZZ_CHECK(slam_config_check(&cfg, NULL) == SLAM_OK);
    (void)lconf_check(&lc, err, sizeof err);
    /* Written out and read back: the same configuration. */
    char text[8192];
    FILE *f = fmemopen(text, sizeof text, "w");
    FUZZ_CHECK(f != NULL);
    cfgtext_write(f, &cfg);
    long n = ftell(f);
    fclose(f);
    FUZZ_CHECK(n > 0 && (size_t)n < sizeof text);
    slam_config_t again;
    slam_config_default(&again);
    FUZZ_CHECK(cfgtext_parse("again", text, (size_t)n, &again, NULL, NULL, NULL, err, sizeof err) ==
               0);
    FUZZ_CHECK(memcmp(&again, &cfg, sizeof cfg) == 0);
    return 0;
}
