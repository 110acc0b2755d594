/* SPDX-License-Identifier: MIT */
/* Loading ROS maps: the map_server .yaml and the 8-bit PGM it names, a crop of a building. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "hal_common/number.h"
#include "host/sim.h"
#include "room_parse.h"

typedef struct {
    uint32_t w, h;
    unsigned maxval;
    uint8_t *px; /* row 0 at the top, as in the file */
} pgm_t;

/* The next header token of a PGM: skips whitespace and '#' comments. */
static const char *pgm_token(const char *p, const char *end, unsigned long *v)
{
    for (;;) {
        while (p < end && isspace((unsigned char)*p)) {
            p++;
        }
        if (p < end && *p == '#') {
            while (p < end && *p != '\n') {
                p++;
            }
            continue;
        }
        break;
    }
    if (p >= end || !isdigit((unsigned char)*p)) {
        return NULL;
    }
    unsigned long n = 0u;
    while (p < end && isdigit((unsigned char)*p)) {
        if (n > 100000000ul) {
            return NULL;
        }
        n = n * 10u + (unsigned long)(*p - '0');
        p++;
    }
    *v = n;
    return p;
}

/* A PGM image held in memory; the pixels are allocated (img->px). */
static int parse_pgm(const char *path, const char *buf, size_t len, pgm_t *img, char *err,
                     size_t errlen)
{
    const char *end = buf + len;
    int ascii = 0;
    if (len >= 2u && buf[0] == 'P' && buf[1] == '5') {
        ascii = 0;
    } else if (len >= 2u && buf[0] == 'P' && buf[1] == '2') {
        ascii = 1;
    } else {
        room_fail(err, errlen, path, 0u, "not a PGM image (P5 or P2)");
        return -1;
    }
    unsigned long w;
    unsigned long h;
    unsigned long maxval;
    const char *p = buf + 2;
    if ((p = pgm_token(p, end, &w)) == NULL || (p = pgm_token(p, end, &h)) == NULL ||
        (p = pgm_token(p, end, &maxval)) == NULL) {
        room_fail(err, errlen, path, 0u, "bad PGM header (width height maxval)");
        return -1;
    }
    if (w == 0u || h == 0u || w > 65535u || h > 65535u || w * h > ROOM_MAX_PIXELS) {
        room_fail(err, errlen, path, 0u, "image size %lux%lu is not supported", w, h);
        return -1;
    }
    if (maxval == 0u || maxval > 255u) {
        room_fail(err, errlen, path, 0u, "only 8-bit images are supported (maxval %lu)", maxval);
        return -1;
    }
    size_t n = (size_t)w * (size_t)h;
    uint8_t *px = malloc(n);
    if (px == NULL) {
        room_fail(err, errlen, path, 0u, "out of memory");
        return -1;
    }
    if (!ascii) {
        if (p >= end || !isspace((unsigned char)*p) || (size_t)(end - p - 1) < n) {
            room_fail(err, errlen, path, 0u, "image data is truncated (expected %zu bytes)", n);
            free(px);
            return -1;
        }
        memcpy(px, p + 1, n);
    } else {
        for (size_t i = 0; i < n; i++) {
            unsigned long v;
            if ((p = pgm_token(p, end, &v)) == NULL) {
                room_fail(err, errlen, path, 0u,
                          "image data is truncated or not a number (pixel %zu)", i);
                free(px);
                return -1;
            }
            px[i] = (uint8_t)(v > 255u ? 255u : v);
            if (v > maxval) {
                room_fail(err, errlen, path, 0u, "pixel %zu is %lu, above maxval %lu", i, v,
                          maxval);
                free(px);
                return -1;
            }
        }
    }
    for (size_t i = 0; !ascii && i < n; i++) {
        if (px[i] > maxval) {
            room_fail(err, errlen, path, 0u, "pixel %zu is %u, above maxval %lu", i,
                      (unsigned)px[i], maxval);
            free(px);
            return -1;
        }
    }
    img->w = (uint32_t)w;
    img->h = (uint32_t)h;
    img->maxval = (unsigned)maxval;
    img->px = px;
    return 0;
}

typedef struct {
    char image[512];
    double resolution;
    double origin[3];
    int negate;
    double occupied_thresh;
    double free_thresh;
    unsigned line[6]; /* where each key was given; 0 = not given */
} ros_yaml_t;

enum { YK_IMAGE, YK_RESOLUTION, YK_ORIGIN, YK_NEGATE, YK_OCC, YK_FREE };

/* Strip matching quotes from a YAML scalar. */
static char *unquote(char *s)
{
    size_t n = strlen(s);
    if (n >= 2u && (s[0] == '"' || s[0] == '\'') && s[n - 1u] == s[0]) {
        s[n - 1u] = '\0';
        return s + 1;
    }
    return s;
}

static int yaml_value(ros_yaml_t *y, const char *key, char *val, const char *path, unsigned lineno,
                      char *err, size_t errlen)
{
    static const char *const keys[] = {"image",  "resolution",      "origin",
                                       "negate", "occupied_thresh", "free_thresh"};
    int k = -1;
    for (int i = 0; i < 6; i++) {
        if (strcmp(key, keys[i]) == 0) {
            k = i;
        }
    }
    if (k < 0) {
        if (strcmp(key, "mode") == 0) {
            val = unquote(val);
            if (strcmp(val, "trinary") != 0 && strcmp(val, "scale") != 0 &&
                strcmp(val, "raw") != 0) {
                room_fail(err, errlen, path, lineno, "unknown mode '%.40s'", val);
                return -1;
            }
        }
        return 0; /* other keys of map_server's format are not needed here */
    }
    if (y->line[k] != 0u) {
        room_fail(err, errlen, path, lineno, "'%s' given twice (first on line %u)", key,
                  y->line[k]);
        return -1;
    }
    y->line[k] = lineno;
    double v = 0.0;
    switch (k) {
    case YK_IMAGE:
        val = unquote(val);
        if (val[0] == '\0') {
            room_fail(err, errlen, path, lineno, "image needs a file name");
            return -1;
        }
        if (strlen(val) >= sizeof y->image) {
            room_fail(err, errlen, path, lineno,
                      "image: a file name of %zu characters, longer than the %zu taken",
                      strlen(val), sizeof y->image - 1u);
            return -1;
        }
        strcpy(y->image, val);
        return 0;
    case YK_ORIGIN: {
        size_t n = strlen(val);
        if (n < 2u || val[0] != '[' || val[n - 1u] != ']') {
            room_fail(err, errlen, path, lineno, "origin must be [x, y, yaw]");
            return -1;
        }
        val[n - 1u] = '\0';
        char *p = val + 1;
        for (int i = 0; i < 3; i++) {
            char *comma = strchr(p, ',');
            if ((comma == NULL) != (i == 2)) {
                room_fail(err, errlen, path, lineno, "origin must be [x, y, yaw]");
                return -1;
            }
            if (comma != NULL) {
                *comma = '\0';
            }
            int r = room_parse_number(cfgtext_trim(p), &y->origin[i]);
            if (r == -3) {
                room_fail(err, errlen, path, lineno, "origin lies beyond +-%g m", ROOM_MAX_COORD_M);
                return -1;
            }
            if (r != 0) {
                room_fail(err, errlen, path, lineno,
                          "origin must be [x, y, yaw] with finite numbers");
                return -1;
            }
            p = comma != NULL ? comma + 1 : p;
        }
        if (fabs(y->origin[2]) > 1e-9) {
            room_fail(err, errlen, path, lineno, "an origin yaw of %g is not supported (only 0)",
                      y->origin[2]);
            return -1;
        }
        return 0;
    }
    case YK_NEGATE:
        if (strcmp(val, "0") == 0 || strcmp(val, "false") == 0) {
            y->negate = 0;
        } else if (strcmp(val, "1") == 0 || strcmp(val, "true") == 0) {
            y->negate = 1;
        } else {
            room_fail(err, errlen, path, lineno, "negate must be 0 or 1");
            return -1;
        }
        return 0;
    default: {
        num_status_t nr = num_real(val, -HUGE_VAL, HUGE_VAL, &v);
        if (nr == NUM_RANGE) {
            v = val[0] == '-' ? -HUGE_VAL : HUGE_VAL; /* a number, far out of range */
        } else if (nr != NUM_OK) {
            room_fail(err, errlen, path, lineno, "%s needs a decimal number, not '%.40s'", key,
                      val);
            return -1;
        }
        if (k == YK_RESOLUTION) {
            if (!(v > 0.0)) {
                room_fail(err, errlen, path, lineno, "resolution must be positive");
                return -1;
            }
            if (v < ROOM_MIN_RES_M || v > ROOM_MAX_RES_M) {
                room_fail(err, errlen, path, lineno, "resolution %.40s m is out of range %g..%g m",
                          val, ROOM_MIN_RES_M, ROOM_MAX_RES_M);
                return -1;
            }
            y->resolution = v;
        } else {
            if (!(v >= 0.0 && v <= 1.0)) {
                room_fail(err, errlen, path, lineno, "%s must lie in 0..1", key);
                return -1;
            }
            *(k == YK_OCC ? &y->occupied_thresh : &y->free_thresh) = v;
        }
        return 0;
    }
    }
}

/* A ROS map's YAML held in memory. */
static int parse_ros_yaml(const char *path, const char *yaml, size_t len, ros_yaml_t *y, char *err,
                          size_t errlen)
{
    room_lines_t lines;
    if (room_lines_open(&lines, path, yaml, len, err, errlen) != 0) {
        return -1;
    }
    memset(y, 0, sizeof *y);
    int rc = 0;
    char *line;
    while (rc == 0 && (rc = room_lines_next(&lines, &line, err, errlen)) > 0) {
        unsigned lineno = lines.lineno;
        rc = 0;
        /* A '#' at the start or after a blank begins a comment (YAML). */
        for (char *c = line; *c != '\0'; c++) {
            if (*c == '#' && (c == line || isspace((unsigned char)c[-1]))) {
                *c = '\0';
                break;
            }
        }
        line = cfgtext_trim(line);
        if (*line == '\0') {
            continue;
        }
        char *colon = strchr(line, ':');
        if (colon == NULL) {
            room_fail(err, errlen, path, lineno, "expected 'key: value'");
            rc = -1;
            break;
        }
        *colon = '\0';
        char *key = cfgtext_trim(line);
        rc = yaml_value(y, key, cfgtext_trim(colon + 1), path, lineno, err, errlen);
    }
    room_lines_close(&lines);
    if (rc != 0) {
        return -1;
    }
    static const char *const need[] = {"image", "resolution",      "origin",
                                       NULL,    "occupied_thresh", "free_thresh"};
    for (int k = 0; k < 6; k++) {
        if (need[k] != NULL && y->line[k] == 0u) {
            room_fail(err, errlen, path, 0u, "no '%s' key", need[k]);
            return -1;
        }
    }
    if (y->free_thresh > y->occupied_thresh) {
        room_fail(err, errlen, path, y->line[YK_FREE], "free_thresh %g is above occupied_thresh %g",
                  y->free_thresh, y->occupied_thresh);
        return -1;
    }
    return 0;
}

/* The pixel range [lo, hi] whose centres lie in [a, a + size), clamped to [0, n). */
static int crop_range(double a, double size, double origin, double res, uint32_t n, uint32_t *lo,
                      uint32_t *hi)
{
    double first = ceil((a - origin) / res - 0.5);
    double last = ceil((a + size - origin) / res - 0.5) - 1.0;
    first = fmax(first, 0.0);
    last = fmin(last, (double)n - 1.0);
    if (first > last) {
        return -1;
    }
    *lo = (uint32_t)first;
    *hi = (uint32_t)last;
    return 0;
}

/* The room of a ROS map from its parsed YAML and its image in memory. */
static int ros_build(room_t *out, const char *path, const ros_yaml_t *yp, const char *img_path,
                     const char *pgm, size_t pgm_len, const room_crop_t *crop, char *err,
                     size_t errlen)
{
    const ros_yaml_t y = *yp;
    pgm_t img;
    if (parse_pgm(img_path, pgm, pgm_len, &img, err, errlen) != 0) {
        return -1;
    }
    double map_x1 = y.origin[0] + (double)img.w * y.resolution;
    double map_y1 = y.origin[1] + (double)img.h * y.resolution;
    if (fabs(map_x1) > ROOM_MAX_COORD_M || fabs(map_y1) > ROOM_MAX_COORD_M) {
        room_fail(err, errlen, path, y.line[YK_RESOLUTION],
                  "the map (%ux%u pixels of %g m from (%g, %g)) reaches beyond +-%g m", img.w,
                  img.h, y.resolution, y.origin[0], y.origin[1], ROOM_MAX_COORD_M);
        free(img.px);
        return -1;
    }

    uint32_t c0 = 0u;
    uint32_t c1 = img.w - 1u;
    uint32_t r0 = 0u; /* rows counted from the bottom */
    uint32_t r1 = img.h - 1u;
    if (crop != NULL) {
        if (!(isfinite(crop->x) && isfinite(crop->y) && crop->w > 0.0 && crop->h > 0.0 &&
              isfinite(crop->w) && isfinite(crop->h))) {
            room_fail(err, errlen, path, 0u,
                      "the crop needs a finite position and a positive size");
            free(img.px);
            return -1;
        }
        if (crop_range(crop->x, crop->w, y.origin[0], y.resolution, img.w, &c0, &c1) != 0 ||
            crop_range(crop->y, crop->h, y.origin[1], y.resolution, img.h, &r0, &r1) != 0) {
            bool overlaps = crop->x < map_x1 && crop->x + crop->w > y.origin[0] &&
                            crop->y < map_y1 && crop->y + crop->h > y.origin[1];
            if (overlaps) {
                room_fail(err, errlen, path, 0u,
                          "the crop (%g %g %g %g) holds no pixel centre (the pixels are %g m)",
                          crop->x, crop->y, crop->w, crop->h, y.resolution);
            } else {
                room_fail(err, errlen, path, 0u,
                          "the crop (%g %g %g %g) lies outside the map (%g %g .. %g %g)", crop->x,
                          crop->y, crop->w, crop->h, y.origin[0], y.origin[1], map_x1, map_y1);
            }
            free(img.px);
            return -1;
        }
    }
    uint32_t w = c1 - c0 + 1u;
    uint32_t h = r1 - r0 + 1u;
    uint8_t *occ = malloc((size_t)w * h);
    uint8_t *fre = malloc((size_t)w * h);
    if (occ == NULL || fre == NULL) {
        room_fail(err, errlen, path, 0u, "out of memory");
        free(occ);
        free(fre);
        free(img.px);
        return -1;
    }
    size_t occupied = 0u;
    for (uint32_t row = 0; row < h; row++) {
        uint32_t file_row = img.h - 1u - (r0 + row);
        for (uint32_t col = 0; col < w; col++) {
            double v = (double)img.px[(size_t)file_row * img.w + c0 + col];
            double pr =
                y.negate ? v / (double)img.maxval : ((double)img.maxval - v) / (double)img.maxval;
            uint8_t o = pr > y.occupied_thresh ? 1u : 0u;
            /* A crop's edges are walls: the part taken out of the building keeps the
             * robot in, whatever doors it has. */
            bool edge = crop != NULL && (row == 0u || col == 0u || row + 1u == h || col + 1u == w);
            o = edge ? 1u : o;
            occ[(size_t)row * w + col] = o;
            fre[(size_t)row * w + col] = !edge && pr < y.free_thresh ? 1u : 0u;
            occupied += o;
        }
    }
    free(img.px);
    if (occupied == 0u) {
        room_fail(err, errlen, path, 0u, "no occupied pixels%s",
                  crop != NULL ? " in the crop" : "");
        free(occ);
        free(fre);
        return -1;
    }
    room_t r = {0};
    r.occ = occ;
    r.occ_free = fre;
    r.occ_w = w;
    r.occ_h = h;
    r.occ_res = y.resolution;
    r.occ_x0 = y.origin[0] + (double)c0 * y.resolution;
    r.occ_y0 = y.origin[1] + (double)r0 * y.resolution;
    room_bounds(&r);
    *out = r;
    return 0;
}

int room_parse_ros(room_t *out, const char *yaml_name, const char *yaml, size_t yaml_len,
                   const char *pgm_name, const char *pgm, size_t pgm_len, const room_crop_t *crop,
                   char *err, size_t errlen)
{
    ros_yaml_t y;
    if (parse_ros_yaml(yaml_name, yaml, yaml_len, &y, err, errlen) != 0) {
        return -1;
    }
    return ros_build(out, yaml_name, &y, pgm_name, pgm, pgm_len, crop, err, errlen);
}

int room_load_ros(room_t *out, const char *path, const room_crop_t *crop, char *err, size_t errlen)
{
    size_t len;
    char *text = cfgtext_read_file(path, ROOM_YAML_MAX, &len, err, errlen);
    if (text == NULL) {
        return -1;
    }
    ros_yaml_t y;
    int rc = parse_ros_yaml(path, text, len, &y, err, errlen);
    free(text);
    if (rc != 0) {
        return -1;
    }
    char img_path[1024];
    const char *slash = strrchr(path, '/');
    int n;
    if (y.image[0] == '/' || slash == NULL) {
        n = snprintf(img_path, sizeof img_path, "%s", y.image);
    } else {
        n = snprintf(img_path, sizeof img_path, "%.*s/%s", (int)(slash - path), path, y.image);
    }
    if (n < 0 || (size_t)n >= sizeof img_path) {
        room_fail(err, errlen, path, y.line[YK_IMAGE], "image path is too long");
        return -1;
    }
    char *pgm = cfgtext_read_file(img_path, ROOM_PGM_MAX, &len, err, errlen);
    if (pgm == NULL) {
        return -1;
    }
    rc = ros_build(out, path, &y, img_path, pgm, len, crop, err, errlen);
    free(pgm);
    return rc;
}
