/* SPDX-License-Identifier: MIT */
/* Output files of a run: directories, PGM maps with their ROS YAML, checked writes. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hal_common/mapexport.h"
#include "host_sim.h"

char *fmt_fixed(char *out, double v, int decimals, char sep)
{
    static const double scale[11] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10};
    double s = v * scale[decimals];
    long long n = (long long)(s < 0 ? s - 0.5 : s + 0.5);
    if (n < 0) {
        *out++ = '-';
        n = -n;
    } else if (n == 0 && v < 0) {
        *out++ = '-'; /* printf keeps the sign of a negative that rounds to zero */
    }
    char digits[32];
    int k = 0;
    do {
        digits[k++] = (char)('0' + n % 10);
        n /= 10;
    } while (n > 0 || k <= decimals);
    while (k > decimals) {
        *out++ = digits[--k];
    }
    if (decimals > 0) {
        *out++ = '.';
        while (k > 0) {
            *out++ = digits[--k];
        }
    }
    if (sep != 0) {
        *out++ = sep;
    }
    return out;
}

const char *reading_status(const sonar_t *s, bool echo, uint32_t range_um)
{
    if (!echo) {
        return "timeout";
    }
    if (range_um >= s->confidence_um) {
        return "far";
    }
    return range_um < s->range_min_um ? "near" : "ok";
}

int make_dirs(const char *path)
{
    char buf[4096];
    if (strlen(path) >= sizeof buf) {
        fprintf(stderr, "host_sim: output path too long: %s\n", path);
        return -1;
    }
    strcpy(buf, path);
    for (char *p = buf + 1; ; p++) {
        if (*p == '/' || *p == '\0') {
            char c = *p;
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                fprintf(stderr, "host_sim: cannot create %s: %s\n", buf, strerror(errno));
                return -1;
            }
            *p = c;
            if (c == '\0') {
                break;
            }
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "host_sim: %s is not a directory\n", path);
        return -1;
    }
    return 0;
}

FILE *open_out(const char *dir, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "host_sim: cannot write %s: %s\n", path, strerror(errno));
    }
    return f;
}

int close_out(FILE *f, const char *dir, const char *name)
{
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        fprintf(stderr, "host_sim: writing %s/%s failed\n", dir, name);
        return -1;
    }
    return 0;
}

int write_map(const char *dir, const char *name, const map_geom_t *g, const uint8_t *img,
              bool yaml)
{
    char file[256];
    snprintf(file, sizeof file, "%s.pgm", name);
    FILE *f = open_out(dir, file);
    if (f == NULL) {
        return -1;
    }
    fprintf(f, "P5\n%lu %lu\n255\n", (unsigned long)g->a, (unsigned long)g->b);
    fwrite(img, 1, (size_t)g->a * g->b, f);
    if (close_out(f, dir, file) != 0 || !yaml) {
        return yaml ? -1 : 0;
    }
    char text[512];
    if (mapx_yaml(text, sizeof text, file, g->cell_um, g->origin_x_um, g->origin_y_um) < 0) {
        fprintf(stderr, "host_sim: %s/%s.yaml: the map's name is too long\n", dir, name);
        return -1;
    }
    snprintf(file, sizeof file, "%s.yaml", name);
    f = open_out(dir, file);
    if (f == NULL) {
        return -1;
    }
    fputs(text, f);
    return close_out(f, dir, file);
}

int write_storage(const char *dir)
{
    if (make_dirs(dir) != 0) {
        return -1;
    }
    int bad = 0;
    for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
        char name[32];
        snprintf(name, sizeof name, "slot%u.bin", (unsigned)slot);
        FILE *f = open_out(dir, name);
        if (f == NULL) {
            return -1;
        }
        fwrite(hal_host_storage_slot(slot), 1u, hal_storage_size(), f);
        bad |= close_out(f, dir, name);
    }
    return bad;
}
