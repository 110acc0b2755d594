/* SPDX-License-Identifier: MIT */
/* Loading rooms: the .room text format and ROS maps (a .yaml and the PGM it names). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "host/sim.h"
#include "hal_common/config_text.h"
#include "room_internal.h"

/* Images larger than this many pixels are refused (a 16k x 16k building). */
#define ROOM_MAX_PIXELS (1u << 28)

__attribute__((format(printf, 5, 6))) static void fail(char *err, size_t errlen,
                                                       const char *path, unsigned line,
                                                       const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (err == NULL || errlen == 0u) {
        return;
    }
    if (line > 0u) {
        snprintf(err, errlen, "%s:%u: %s", path, line, msg);
    } else {
        snprintf(err, errlen, "%s: %s", path, msg);
    }
}

/* The whole file, NUL-terminated (a NUL inside makes the text end there). */
static char *read_file(const char *path, size_t *len, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fail(err, errlen, path, 0u, "cannot open: %s", strerror(errno));
        return NULL;
    }
    size_t cap = 4096u;
    size_t n = 0u;
    char *buf = malloc(cap);
    while (buf != NULL) {
        n += fread(buf + n, 1u, cap - 1u - n, f);
        if (n < cap - 1u) {
            break;
        }
        char *grown = realloc(buf, 2u * cap);
        if (grown == NULL) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap *= 2u;
    }
    int bad = ferror(f);
    fclose(f);
    if (buf == NULL) {
        fail(err, errlen, path, 0u, "out of memory");
        return NULL;
    }
    if (bad) {
        free(buf);
        fail(err, errlen, path, 0u, "read error");
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}

/* The line at *p, cut at its newline; *p moves to the next one. */
static char *cut_line(char **p)
{
    char *line = *p;
    char *eol = strchr(line, '\n');
    if (eol != NULL) {
        *eol = '\0';
        *p = eol + 1;
    } else {
        *p = line + strlen(line);
    }
    return line;
}

/* A growable array. */
typedef struct {
    void *v;
    size_t n;
    size_t cap;
} vec_t;

static int vec_push(vec_t *a, const void *item, size_t size)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2u * a->cap : 16u;
        void *grown = realloc(a->v, cap * size);
        if (grown == NULL) {
            return -1;
        }
        a->v = grown;
        a->cap = cap;
    }
    memcpy((char *)a->v + a->n * size, item, size);
    a->n++;
    return 0;
}

/* Parse a whole token as a finite number: 0, -1 not a number, -2 not finite. */
static int parse_number(const char *tok, double *v)
{
    char *end;
    errno = 0;
    double d = strtod(tok, &end);
    if (end == tok || *end != '\0') {
        return -1;
    }
    if (!isfinite(d) || (errno == ERANGE && fabs(d) > 1.0)) {
        return -2;
    }
    *v = d;
    return 0;
}

/* Set the bounding box of a room from its geometry. */
static void room_bounds(room_t *r)
{
    double x0 = HOST_INF;
    double y0 = HOST_INF;
    double x1 = -HOST_INF;
    double y1 = -HOST_INF;
    for (size_t i = 0; i < r->nsegs; i++) {
        const room_segment_t *s = &r->segs[i];
        x0 = fmin(x0, fmin(s->x1, s->x2));
        x1 = fmax(x1, fmax(s->x1, s->x2));
        y0 = fmin(y0, fmin(s->y1, s->y2));
        y1 = fmax(y1, fmax(s->y1, s->y2));
    }
    for (size_t i = 0; i < r->ncircles; i++) {
        const room_circle_t *c = &r->circles[i];
        x0 = fmin(x0, c->cx - c->r);
        x1 = fmax(x1, c->cx + c->r);
        y0 = fmin(y0, c->cy - c->r);
        y1 = fmax(y1, c->cy + c->r);
    }
    if (r->occ != NULL) {
        for (uint32_t iy = 0; iy < r->occ_h; iy++) {
            for (uint32_t ix = 0; ix < r->occ_w; ix++) {
                if (r->occ[(size_t)iy * r->occ_w + ix]) {
                    double px = r->occ_x0 + (double)ix * r->occ_res;
                    double py = r->occ_y0 + (double)iy * r->occ_res;
                    x0 = fmin(x0, px);
                    x1 = fmax(x1, px + r->occ_res);
                    y0 = fmin(y0, py);
                    y1 = fmax(y1, py + r->occ_res);
                }
            }
        }
    }
    r->min_x = x0;
    r->min_y = y0;
    r->max_x = x1;
    r->max_y = y1;
}

/* ---- .room files --------------------------------------------------------------------- */

typedef struct {
    vec_t segs;
    vec_t circles;
    vec_t boxes;
    vec_t vals;
} room_build_t;

static void build_free(room_build_t *b)
{
    free(b->segs.v);
    free(b->circles.v);
    free(b->boxes.v);
    free(b->vals.v);
}

static int push_seg(room_build_t *b, double x1, double y1, double x2, double y2)
{
    room_segment_t s = {x1, y1, x2, y2};
    return vec_push(&b->segs, &s, sizeof s);
}

/* One statement; returns 0, or -1 with err set. */
static int room_statement(room_build_t *b, room_t *r, unsigned *start_line, char *line,
                          const char *path, unsigned lineno, char *err, size_t errlen)
{
    char *hash = strchr(line, '#');
    if (hash != NULL) {
        *hash = '\0';
    }
    char *p = line;
    const char *kw = NULL;
    b->vals.n = 0u;
    for (;;) {
        while (*p != '\0' && isspace((unsigned char)*p)) {
            p++;
        }
        if (*p == '\0') {
            break;
        }
        char *tok = p;
        while (*p != '\0' && !isspace((unsigned char)*p)) {
            p++;
        }
        if (*p != '\0') {
            *p++ = '\0';
        }
        if (kw == NULL) {
            kw = tok;
            continue;
        }
        double v;
        int rc = parse_number(tok, &v);
        if (rc == -1) {
            fail(err, errlen, path, lineno, "'%.40s' is not a number", tok);
            return -1;
        }
        if (rc == -2) {
            fail(err, errlen, path, lineno, "'%.40s' is not a finite number", tok);
            return -1;
        }
        if (vec_push(&b->vals, &v, sizeof v) != 0) {
            fail(err, errlen, path, lineno, "out of memory");
            return -1;
        }
    }
    if (kw == NULL) {
        return 0; /* blank or comment */
    }
    const double *v = b->vals.v;
    size_t n = b->vals.n;
    int oom = 0;
    if (strcmp(kw, "wall") == 0) {
        if (n != 4u) {
            fail(err, errlen, path, lineno, "wall needs 4 values (x1 y1 x2 y2), got %zu", n);
            return -1;
        }
        if (v[0] == v[2] && v[1] == v[3]) {
            fail(err, errlen, path, lineno, "wall has zero length");
            return -1;
        }
        oom = push_seg(b, v[0], v[1], v[2], v[3]);
    } else if (strcmp(kw, "box") == 0) {
        if (n != 4u) {
            fail(err, errlen, path, lineno, "box needs 4 values (x y w h), got %zu", n);
            return -1;
        }
        if (!(v[2] > 0.0 && v[3] > 0.0)) {
            fail(err, errlen, path, lineno, "box width and height must be positive");
            return -1;
        }
        double x1 = v[0] + v[2];
        double y1 = v[1] + v[3];
        room_box_t bx = {v[0], v[1], x1, y1};
        oom = push_seg(b, v[0], v[1], x1, v[1]) || push_seg(b, x1, v[1], x1, y1) ||
              push_seg(b, x1, y1, v[0], y1) || push_seg(b, v[0], y1, v[0], v[1]) ||
              vec_push(&b->boxes, &bx, sizeof bx);
    } else if (strcmp(kw, "poly") == 0) {
        if (n < 6u || n % 2u != 0u) {
            fail(err, errlen, path, lineno,
                 "poly needs an even number of values, at least 6 (x1 y1 x2 y2 x3 y3 ...), "
                 "got %zu", n);
            return -1;
        }
        size_t pts = n / 2u;
        for (size_t i = 0; i < pts; i++) {
            size_t j = (i + 1u) % pts;
            if (v[2u * i] == v[2u * j] && v[2u * i + 1u] == v[2u * j + 1u]) {
                fail(err, errlen, path, lineno, "poly points %zu and %zu are the same", i + 1u,
                     j + 1u);
                return -1;
            }
        }
        for (size_t i = 0; i < pts && !oom; i++) {
            size_t j = (i + 1u) % pts;
            oom = push_seg(b, v[2u * i], v[2u * i + 1u], v[2u * j], v[2u * j + 1u]);
        }
    } else if (strcmp(kw, "circle") == 0) {
        if (n != 3u) {
            fail(err, errlen, path, lineno, "circle needs 3 values (cx cy r), got %zu", n);
            return -1;
        }
        if (!(v[2] > 0.0)) {
            fail(err, errlen, path, lineno, "circle radius must be positive");
            return -1;
        }
        room_circle_t c = {v[0], v[1], v[2]};
        oom = vec_push(&b->circles, &c, sizeof c);
    } else if (strcmp(kw, "start") == 0) {
        if (n != 3u) {
            fail(err, errlen, path, lineno, "start needs 3 values (x y theta_deg), got %zu", n);
            return -1;
        }
        if (r->has_start) {
            fail(err, errlen, path, lineno, "a second start (the first is on line %u)",
                 *start_line);
            return -1;
        }
        r->has_start = true;
        r->start_x = v[0];
        r->start_y = v[1];
        r->start_th = remainder(v[2], 360.0) * (HOST_PI / 180.0);
        *start_line = lineno;
    } else {
        fail(err, errlen, path, lineno,
             "unknown keyword '%.40s' (expected wall, box, poly, circle or start)", kw);
        return -1;
    }
    if (oom) {
        fail(err, errlen, path, lineno, "out of memory");
        return -1;
    }
    return 0;
}

static int load_room_text(room_t *out, const char *path, char *err, size_t errlen)
{
    size_t len;
    char *text = read_file(path, &len, err, errlen);
    if (text == NULL) {
        return -1;
    }
    room_build_t b = {0};
    room_t r = {0};
    unsigned start_line = 0u;
    unsigned lineno = 0u;
    int rc = 0;
    char *p = text;
    while (rc == 0 && *p != '\0') {
        lineno++;
        rc = room_statement(&b, &r, &start_line, cut_line(&p), path, lineno, err, errlen);
    }
    free(text);
    if (rc == 0 && b.segs.n == 0u && b.circles.n == 0u) {
        fail(err, errlen, path, 0u, "no walls or obstacles");
        rc = -1;
    }
    if (rc == 0 && !r.has_start) {
        fail(err, errlen, path, 0u, "no start pose (add a line 'start x y theta_deg')");
        rc = -1;
    }
    if (rc == 0) {
        r.segs = b.segs.v;
        r.nsegs = b.segs.n;
        r.circles = b.circles.v;
        r.ncircles = b.circles.n;
        r.boxes = b.boxes.v;
        r.nboxes = b.boxes.n;
        room_bounds(&r);
        double c = room_clearance(&r, r.start_x, r.start_y, ROOM_BODY_RADIUS_M);
        if (c < ROOM_BODY_RADIUS_M) {
            fail(err, errlen, path, start_line,
                 "start pose (%g, %g) is %s an obstacle: the robot's body (radius %g m) "
                 "must touch nothing",
                 r.start_x, r.start_y, c <= 0.0 ? "inside" : "too close to",
                 ROOM_BODY_RADIUS_M);
            rc = -1;
        }
    }
    if (rc != 0) {
        build_free(&b);
        return -1;
    }
    free(b.vals.v);
    *out = r;
    return 0;
}

/* ---- ROS maps ------------------------------------------------------------------------ */

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

static int read_pgm(const char *path, pgm_t *img, char *err, size_t errlen)
{
    size_t len;
    char *buf = read_file(path, &len, err, errlen);
    if (buf == NULL) {
        return -1;
    }
    const char *end = buf + len;
    int ascii = 0;
    if (len >= 2u && buf[0] == 'P' && buf[1] == '5') {
        ascii = 0;
    } else if (len >= 2u && buf[0] == 'P' && buf[1] == '2') {
        ascii = 1;
    } else {
        fail(err, errlen, path, 0u, "not a PGM image (P5 or P2)");
        free(buf);
        return -1;
    }
    unsigned long w;
    unsigned long h;
    unsigned long maxval;
    const char *p = buf + 2;
    if ((p = pgm_token(p, end, &w)) == NULL || (p = pgm_token(p, end, &h)) == NULL ||
        (p = pgm_token(p, end, &maxval)) == NULL) {
        fail(err, errlen, path, 0u, "bad PGM header (width height maxval)");
        free(buf);
        return -1;
    }
    if (w == 0u || h == 0u || w > 65535u || h > 65535u || w * h > ROOM_MAX_PIXELS) {
        fail(err, errlen, path, 0u, "image size %lux%lu is not supported", w, h);
        free(buf);
        return -1;
    }
    if (maxval == 0u || maxval > 255u) {
        fail(err, errlen, path, 0u, "only 8-bit images are supported (maxval %lu)", maxval);
        free(buf);
        return -1;
    }
    size_t n = (size_t)w * (size_t)h;
    uint8_t *px = malloc(n);
    if (px == NULL) {
        fail(err, errlen, path, 0u, "out of memory");
        free(buf);
        return -1;
    }
    if (!ascii) {
        if (p >= end || !isspace((unsigned char)*p) || (size_t)(end - p - 1) < n) {
            fail(err, errlen, path, 0u, "image data is truncated (expected %zu bytes)", n);
            free(px);
            free(buf);
            return -1;
        }
        memcpy(px, p + 1, n);
    } else {
        for (size_t i = 0; i < n; i++) {
            unsigned long v;
            if ((p = pgm_token(p, end, &v)) == NULL) {
                fail(err, errlen, path, 0u, "image data is truncated or not a number (pixel %zu)",
                     i);
                free(px);
                free(buf);
                return -1;
            }
            px[i] = (uint8_t)(v > 255u ? 255u : v);
            if (v > maxval) {
                fail(err, errlen, path, 0u, "pixel %zu is %lu, above maxval %lu", i, v, maxval);
                free(px);
                free(buf);
                return -1;
            }
        }
    }
    for (size_t i = 0; !ascii && i < n; i++) {
        if (px[i] > maxval) {
            fail(err, errlen, path, 0u, "pixel %zu is %u, above maxval %lu", i, (unsigned)px[i],
                 maxval);
            free(px);
            free(buf);
            return -1;
        }
    }
    free(buf);
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

static int yaml_value(ros_yaml_t *y, const char *key, char *val, const char *path,
                      unsigned lineno, char *err, size_t errlen)
{
    static const char *const keys[] = {"image",    "resolution",      "origin",
                                       "negate",   "occupied_thresh", "free_thresh"};
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
                fail(err, errlen, path, lineno, "unknown mode '%.40s'", val);
                return -1;
            }
        }
        return 0; /* other keys of map_server's format are not needed here */
    }
    if (y->line[k] != 0u) {
        fail(err, errlen, path, lineno, "'%s' given twice (first on line %u)", key, y->line[k]);
        return -1;
    }
    y->line[k] = lineno;
    double v = 0.0;
    switch (k) {
    case YK_IMAGE:
        val = unquote(val);
        if (val[0] == '\0' || strlen(val) >= sizeof y->image) {
            fail(err, errlen, path, lineno, "image needs a file name");
            return -1;
        }
        strcpy(y->image, val);
        return 0;
    case YK_ORIGIN: {
        size_t n = strlen(val);
        if (n < 2u || val[0] != '[' || val[n - 1u] != ']') {
            fail(err, errlen, path, lineno, "origin must be [x, y, yaw]");
            return -1;
        }
        val[n - 1u] = '\0';
        char *p = val + 1;
        for (int i = 0; i < 3; i++) {
            char *comma = strchr(p, ',');
            if ((comma == NULL) != (i == 2)) {
                fail(err, errlen, path, lineno, "origin must be [x, y, yaw]");
                return -1;
            }
            if (comma != NULL) {
                *comma = '\0';
            }
            if (parse_number(cfgtext_trim(p), &y->origin[i]) != 0) {
                fail(err, errlen, path, lineno, "origin must be [x, y, yaw] with finite numbers");
                return -1;
            }
            p = comma != NULL ? comma + 1 : p;
        }
        if (fabs(y->origin[2]) > 1e-9) {
            fail(err, errlen, path, lineno, "an origin yaw of %g is not supported (only 0)",
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
            fail(err, errlen, path, lineno, "negate must be 0 or 1");
            return -1;
        }
        return 0;
    default:
        if (parse_number(val, &v) != 0) {
            fail(err, errlen, path, lineno, "%s needs a finite number, not '%.40s'", key, val);
            return -1;
        }
        if (k == YK_RESOLUTION) {
            if (!(v > 0.0)) {
                fail(err, errlen, path, lineno, "resolution must be positive");
                return -1;
            }
            y->resolution = v;
        } else {
            if (!(v >= 0.0 && v <= 1.0)) {
                fail(err, errlen, path, lineno, "%s must lie in 0..1", key);
                return -1;
            }
            *(k == YK_OCC ? &y->occupied_thresh : &y->free_thresh) = v;
        }
        return 0;
    }
}

static int read_ros_yaml(const char *path, ros_yaml_t *y, char *err, size_t errlen)
{
    size_t len;
    char *text = read_file(path, &len, err, errlen);
    if (text == NULL) {
        return -1;
    }
    memset(y, 0, sizeof *y);
    unsigned lineno = 0u;
    int rc = 0;
    char *p = text;
    while (rc == 0 && *p != '\0') {
        lineno++;
        char *line = cut_line(&p);
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
            fail(err, errlen, path, lineno, "expected 'key: value'");
            rc = -1;
            break;
        }
        *colon = '\0';
        char *key = cfgtext_trim(line);
        rc = yaml_value(y, key, cfgtext_trim(colon + 1), path, lineno, err, errlen);
    }
    free(text);
    if (rc != 0) {
        return -1;
    }
    static const char *const need[] = {"image", "resolution", "origin", NULL,
                                       "occupied_thresh", "free_thresh"};
    for (int k = 0; k < 6; k++) {
        if (need[k] != NULL && y->line[k] == 0u) {
            fail(err, errlen, path, 0u, "no '%s' key", need[k]);
            return -1;
        }
    }
    if (y->free_thresh > y->occupied_thresh) {
        fail(err, errlen, path, y->line[YK_FREE], "free_thresh %g is above occupied_thresh %g",
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

static int load_ros_map(room_t *out, const char *path, const room_crop_t *crop, char *err,
                        size_t errlen)
{
    ros_yaml_t y;
    if (read_ros_yaml(path, &y, err, errlen) != 0) {
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
        fail(err, errlen, path, y.line[YK_IMAGE], "image path is too long");
        return -1;
    }
    pgm_t img;
    if (read_pgm(img_path, &img, err, errlen) != 0) {
        return -1;
    }

    uint32_t c0 = 0u;
    uint32_t c1 = img.w - 1u;
    uint32_t r0 = 0u; /* rows counted from the bottom */
    uint32_t r1 = img.h - 1u;
    if (crop != NULL) {
        if (!(isfinite(crop->x) && isfinite(crop->y) && crop->w > 0.0 && crop->h > 0.0 &&
              isfinite(crop->w) && isfinite(crop->h))) {
            fail(err, errlen, path, 0u, "the crop needs a finite position and a positive size");
            free(img.px);
            return -1;
        }
        if (crop_range(crop->x, crop->w, y.origin[0], y.resolution, img.w, &c0, &c1) != 0 ||
            crop_range(crop->y, crop->h, y.origin[1], y.resolution, img.h, &r0, &r1) != 0) {
            fail(err, errlen, path, 0u, "the crop (%g %g %g %g) lies outside the map", crop->x,
                 crop->y, crop->w, crop->h);
            free(img.px);
            return -1;
        }
    }
    uint32_t w = c1 - c0 + 1u;
    uint32_t h = r1 - r0 + 1u;
    uint8_t *occ = malloc((size_t)w * h);
    uint8_t *fre = malloc((size_t)w * h);
    if (occ == NULL || fre == NULL) {
        fail(err, errlen, path, 0u, "out of memory");
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
            double pr = y.negate ? v / (double)img.maxval
                                 : ((double)img.maxval - v) / (double)img.maxval;
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
        fail(err, errlen, path, 0u, "no occupied pixels%s", crop != NULL ? " in the crop" : "");
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

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s);
    size_t m = strlen(suffix);
    if (n < m) {
        return false;
    }
    for (size_t i = 0; i < m; i++) {
        if (tolower((unsigned char)s[n - m + i]) != suffix[i]) {
            return false;
        }
    }
    return true;
}

int room_load(room_t *r, const char *path, const room_crop_t *crop, char *err, size_t errlen)
{
    if (ends_with(path, ".yaml") || ends_with(path, ".yml")) {
        return load_ros_map(r, path, crop, err, errlen);
    }
    return load_room_text(r, path, err, errlen);
}

void room_free(room_t *r)
{
    free(r->segs);
    free(r->circles);
    free(r->boxes);
    free(r->occ);
    free(r->occ_free);
    memset(r, 0, sizeof *r);
}
