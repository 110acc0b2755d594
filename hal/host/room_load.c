/* SPDX-License-Identifier: MIT */
/* Loading rooms: the .room text format, what both formats share, and the choice between them. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "host/sim.h"
#include "hal_common/config_text.h"
#include "hal_common/number.h"
#include "room_internal.h"
#include "room_parse.h"

void room_fail(char *err, size_t errlen, const char *path, unsigned line, const char *fmt, ...)
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
    cfgtext_escape(err, errlen); /* messages quote the file's words */
}

int room_lines_open(room_lines_t *l, const char *path, const char *text, size_t len, char *err,
                    size_t errlen)
{
    l->buf = malloc(len + 1u);
    if (l->buf == NULL) {
        room_fail(err, errlen, path, 0u, "out of memory");
        return -1;
    }
    memcpy(l->buf, text, len);
    l->buf[len] = '\0';
    l->len = len;
    l->pos = 0u;
    l->lineno = 0u;
    l->path = path;
    return 0;
}

int room_lines_next(room_lines_t *l, char **line, char *err, size_t errlen)
{
    if (l->pos >= l->len) {
        return 0;
    }
    l->lineno++;
    char *p = l->buf + l->pos;
    char *eol = memchr(p, '\n', l->len - l->pos);
    size_t n = eol != NULL ? (size_t)(eol - p) : l->len - l->pos;
    l->pos += n + (eol != NULL ? 1u : 0u);
    if (memchr(p, '\0', n) != NULL) {
        room_fail(err, errlen, l->path, l->lineno, "a NUL byte: not a text file");
        return -1;
    }
    p[n] = '\0';
    *line = p;
    return 1;
}

void room_lines_close(room_lines_t *l)
{
    free(l->buf);
    l->buf = NULL;
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

/* "inf", "-Infinity", "nan"...: not numbers by the rule, but a message says what they are. */
static bool spells_non_finite(const char *tok)
{
    static const char *const words[] = {"inf", "infinity", "nan"};
    const char *p = tok + (*tok == '+' || *tok == '-');
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++) {
        size_t k = 0;
        while (words[i][k] != '\0' && tolower((unsigned char)p[k]) == words[i][k]) {
            k++;
        }
        if (words[i][k] == '\0' && p[k] == '\0') {
            return true;
        }
    }
    return false;
}

int room_parse_number(const char *tok, double *v)
{
    double d;
    num_status_t r = num_real(tok, -ROOM_MAX_COORD_M, ROOM_MAX_COORD_M, &d);
    if (r == NUM_BAD) {
        return spells_non_finite(tok) ? -2 : -1;
    }
    if (r == NUM_RANGE) {
        return num_real(tok, -HUGE_VAL, HUGE_VAL, &d) == NUM_OK ? -3 : -2;
    }
    *v = d;
    return 0;
}

void room_bounds(room_t *r)
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
        int rc = room_parse_number(tok, &v);
        if (rc == -1) {
            room_fail(err, errlen, path, lineno, "'%.40s' is not a number", tok);
            return -1;
        }
        if (rc == -2) {
            room_fail(err, errlen, path, lineno, "'%.40s' is not a finite number", tok);
            return -1;
        }
        if (rc == -3) {
            room_fail(err, errlen, path, lineno, "'%.40s' is out of range: values lie within +-%g",
                      tok, ROOM_MAX_COORD_M);
            return -1;
        }
        if (vec_push(&b->vals, &v, sizeof v) != 0) {
            room_fail(err, errlen, path, lineno, "out of memory");
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
            room_fail(err, errlen, path, lineno, "wall needs 4 values (x1 y1 x2 y2), got %zu", n);
            return -1;
        }
        if (v[0] == v[2] && v[1] == v[3]) {
            room_fail(err, errlen, path, lineno, "wall has zero length");
            return -1;
        }
        oom = push_seg(b, v[0], v[1], v[2], v[3]);
    } else if (strcmp(kw, "box") == 0) {
        if (n != 4u) {
            room_fail(err, errlen, path, lineno, "box needs 4 values (x y w h), got %zu", n);
            return -1;
        }
        if (!(v[2] > 0.0 && v[3] > 0.0)) {
            room_fail(err, errlen, path, lineno, "box width and height must be positive");
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
            room_fail(err, errlen, path, lineno,
                      "poly needs an even number of values, at least 6 (x1 y1 x2 y2 x3 y3 ...), "
                      "got %zu",
                      n);
            return -1;
        }
        size_t pts = n / 2u;
        for (size_t i = 0; i < pts; i++) {
            size_t j = (i + 1u) % pts;
            if (v[2u * i] == v[2u * j] && v[2u * i + 1u] == v[2u * j + 1u]) {
                room_fail(err, errlen, path, lineno, "poly points %zu and %zu are the same", i + 1u,
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
            room_fail(err, errlen, path, lineno, "circle needs 3 values (cx cy r), got %zu", n);
            return -1;
        }
        if (!(v[2] > 0.0)) {
            room_fail(err, errlen, path, lineno, "circle radius must be positive");
            return -1;
        }
        room_circle_t c = {v[0], v[1], v[2]};
        oom = vec_push(&b->circles, &c, sizeof c);
    } else if (strcmp(kw, "start") == 0) {
        if (n != 3u) {
            room_fail(err, errlen, path, lineno, "start needs 3 values (x y theta_deg), got %zu",
                      n);
            return -1;
        }
        if (r->has_start) {
            room_fail(err, errlen, path, lineno, "a second start (the first is on line %u)",
                      *start_line);
            return -1;
        }
        r->has_start = true;
        r->start_x = v[0];
        r->start_y = v[1];
        r->start_th = remainder(v[2], 360.0) * (HOST_PI / 180.0);
        *start_line = lineno;
    } else {
        room_fail(err, errlen, path, lineno,
                  "unknown keyword '%.40s' (expected wall, box, poly, circle or start)", kw);
        return -1;
    }
    if (oom) {
        room_fail(err, errlen, path, lineno, "out of memory");
        return -1;
    }
    return 0;
}

/* A segment's free end (one that no other segment meets within 1 mm) stands for the end of
 * a real screen or partition, which has a thickness: it becomes a circle of
 * ROOM_WALL_END_M, which the sonar answers from and the body meets. Joined ends (a room's
 * corners, a box's or polygon's) get none. */
#define WALL_JOIN2_M2 1e-6 /* (1 mm)² */

/* Whether a segment other than segment i passes within 1 mm of (x, y): through the index
 * of the segments where there are enough for one (room_index_seg_near() answers the same),
 * else by looking at every one. */
static bool end_joined(const room_t *segs_only, size_t i, double x, double y)
{
    if (segs_only->index != NULL) {
        return room_index_seg_near(segs_only, x, y, WALL_JOIN2_M2, (uint32_t)i);
    }
    for (size_t j = 0; j < segs_only->nsegs; j++) {
        if (j != i && room_seg_dist2(&segs_only->segs[j], x, y) < WALL_JOIN2_M2) {
            return true;
        }
    }
    return false;
}

static int add_wall_ends(room_build_t *b)
{
    /* The segments alone, indexed: a file of 10^5 walls took half a minute looking at
     * every one for each end. */
    room_t alone = {0};
    alone.segs = b->segs.v;
    alone.nsegs = b->segs.n;
    room_bounds(&alone);
    if (room_index_build(&alone) != 0) {
        return -1;
    }
    int rc = 0;
    for (size_t i = 0; i < alone.nsegs && rc == 0; i++) {
        for (int e = 0; e < 2 && rc == 0; e++) {
            double x = e == 0 ? alone.segs[i].x1 : alone.segs[i].x2;
            double y = e == 0 ? alone.segs[i].y1 : alone.segs[i].y2;
            if (!end_joined(&alone, i, x, y)) {
                room_circle_t c = {x, y, ROOM_WALL_END_M};
                rc = vec_push(&b->circles, &c, sizeof c);
            }
        }
    }
    room_index_free(&alone);
    return rc;
}

int room_parse(room_t *out, const char *path, const char *text, size_t len, char *err,
               size_t errlen)
{
    room_lines_t lines;
    if (room_lines_open(&lines, path, text, len, err, errlen) != 0) {
        return -1;
    }
    room_build_t b = {0};
    room_t r = {0};
    unsigned start_line = 0u;
    int rc = 0;
    char *line;
    while (rc == 0 && (rc = room_lines_next(&lines, &line, err, errlen)) > 0) {
        rc = room_statement(&b, &r, &start_line, line, path, lines.lineno, err, errlen);
    }
    room_lines_close(&lines);
    if (rc == 0 && b.segs.n == 0u && b.circles.n == 0u) {
        room_fail(err, errlen, path, 0u, "no walls or obstacles");
        rc = -1;
    }
    if (rc == 0 && !r.has_start) {
        room_fail(err, errlen, path, 0u, "no start pose (add a line 'start x y theta_deg')");
        rc = -1;
    }
    if (rc == 0 && add_wall_ends(&b) != 0) {
        room_fail(err, errlen, path, 0u, "out of memory");
        rc = -1;
    }
    if (rc == 0) {
        r.segs = b.segs.v;
        r.nsegs = b.segs.n;
        r.circles = b.circles.v;
        r.ncircles = b.circles.n;
        r.boxes = b.boxes.v;
        r.nboxes = b.boxes.n;
        r.start_line = start_line;
        room_bounds(&r);
        if (room_index_build(&r) != 0) {
            room_fail(err, errlen, path, 0u, "out of memory");
            rc = -1;
        }
    }
    if (rc == 0) {
        double c = room_clearance(&r, r.start_x, r.start_y, ROOM_BODY_RADIUS_M);
        if (c < ROOM_BODY_RADIUS_M) {
            room_fail(err, errlen, path, start_line,
                      "start pose (%g, %g) is %s an obstacle: the robot's body (radius %g m) "
                      "must touch nothing",
                      r.start_x, r.start_y, c <= 0.0 ? "inside" : "too close to",
                      ROOM_BODY_RADIUS_M);
            room_index_free(&r);
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

static int load_room_text(room_t *out, const char *path, char *err, size_t errlen)
{
    size_t len;
    char *text = cfgtext_read_file(path, ROOM_TEXT_MAX, &len, err, errlen);
    if (text == NULL) {
        return -1;
    }
    int rc = room_parse(out, path, text, len, err, errlen);
    free(text);
    return rc;
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
        return room_load_ros(r, path, crop, err, errlen);
    }
    if (crop != NULL) {
        room_fail(err, errlen, path, 0u,
                  "a crop takes part of a ROS map (.yaml); a .room file "
                  "is taken whole");
        return -1;
    }
    return load_room_text(r, path, err, errlen);
}

void room_free(room_t *r)
{
    room_index_free(r);
    free(r->segs);
    free(r->circles);
    free(r->boxes);
    free(r->occ);
    free(r->occ_free);
    memset(r, 0, sizeof *r);
}
