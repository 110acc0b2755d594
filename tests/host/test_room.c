/* SPDX-License-Identifier: MIT */
/* Tests of room loading: every statement, every error with its file and line, ROS maps. */
#include <math.h>

#include "host_test.h"

/* ---- .room files ---------------------------------------------------------------------- */

static void test_every_shape(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "# a header comment\n"
                  "\n"
                  "wall 0 0 6 0   # the south wall\n"
                  "box 1 1 0.5 0.25\n"
                  "\tpoly 3 3 4 3 3.5 4\n"
                  "circle 5 2 0.3\n"
                  "start 2 2.5 90\n");
    assert_int_equal(r.nsegs, 1u + 4u + 3u);
    assert_int_equal(r.nboxes, 1u);
    assert_int_equal(r.ncircles, 1u + 2u); /* the circle, the lone wall's two free ends */
    assert_null(r.occ);
    /* The box's four edges, counter-clockwise from its lower-left corner. */
    assert_true(r.segs[1].x1 == 1.0 && r.segs[1].y1 == 1.0 && r.segs[1].x2 == 1.5);
    assert_true(r.segs[2].x2 == 1.5 && r.segs[2].y2 == 1.25);
    assert_true(r.boxes[0].x0 == 1.0 && r.boxes[0].y1 == 1.25);
    /* The polygon is closed: its last edge returns to the first point. */
    assert_true(r.segs[7].x1 == 3.5 && r.segs[7].y1 == 4.0 && r.segs[7].x2 == 3.0 &&
                r.segs[7].y2 == 3.0);
    assert_true(r.circles[0].cx == 5.0 && r.circles[0].r == (double)0.3);
    assert_true(r.has_start);
    assert_true(r.start_x == 2.0 && r.start_y == 2.5);
    assert_true(fabs(r.start_th - TEST_PI / 2.0) < 1e-12);
    /* The bounds take in the lone wall's round ends. */
    assert_true(r.min_x == -ROOM_WALL_END_M && r.min_y == -ROOM_WALL_END_M);
    assert_true(fabs(r.max_x - (6.0 + ROOM_WALL_END_M)) < 1e-12 && fabs(r.max_y - 4.0) < 1e-12);
    room_free(&r);
    assert_null(r.segs);
    assert_int_equal(r.nsegs, 0u);
}

/* A wall's free end is a small circle (a real screen's end has a face); ends that meet
 * another wall, a box or a polygon, at an end or along it, are not. */
static void test_free_wall_ends_are_round(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 6 0\nwall 6 0 6 4\nwall 6 4 0 4\nwall 0 4 0 0\n"
                  "wall 2 1 3 1        # a screen: two free ends\n"
                  "wall 4 0 4 1.5      # from the south wall: one free end\n"
                  "wall 0 3 2 3\nbox 2 2.5 0.5 1   # a wall that meets a box's edge\n"
                  "start 1 1 0\n");
    assert_int_equal(r.ncircles, 3u);
    const double want[3][2] = {{2.0, 1.0}, {3.0, 1.0}, {4.0, 1.5}};
    for (size_t i = 0; i < 3u; i++) {
        assert_true(r.circles[i].cx == want[i][0] && r.circles[i].cy == want[i][1]);
        assert_true(r.circles[i].r == ROOM_WALL_END_M);
    }
    room_free(&r);
}

static void test_crlf_and_angles(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 4 0\r\nwall 4 0 4 4\r\nstart 1 1 -270\r\n");
    assert_int_equal(r.nsegs, 2u);
    assert_true(fabs(r.start_th - TEST_PI / 2.0) < 1e-12); /* -270° is +90° */
    room_free(&r);
}

typedef struct {
    const char *text;
    const char *expect; /* after "PATH" */
} bad_room_t;

static const bad_room_t bad_rooms[] = {
    {"wall 0 0 4 0\nstart 1 1 0\nwal 0 0 1 1\n", ":3: unknown keyword 'wal'"},
    {"wall 0 0 4\nstart 1 1 0\n", ":1: wall needs 4 values (x1 y1 x2 y2), got 3"},
    {"wall 0 0 4 0 5\nstart 1 1 0\n", ":1: wall needs 4 values"},
    {"wall 0 0 4 0\nbox 2 2 1\nstart 1 1 0\n", ":2: box needs 4 values"},
    {"wall 0 0 4 0\ncircle 2 2\nstart 1 1 0\n", ":2: circle needs 3 values"},
    {"wall 0 0 4 0\nstart 1 1\n", ":2: start needs 3 values"},
    {"wall 0 0 4 0\npoly 0 0 1 1 2\nstart 1 1 0\n", ":2: poly needs an even number"},
    {"wall 0 0 4 0\npoly 0 0 1 1\nstart 1 1 0\n", ":2: poly needs an even number"},
    {"wall 0 0 inf 0\nstart 1 1 0\n", ":1: 'inf' is not a finite number"},
    {"wall 0 0 4 0\nstart 1 nan 0\n", ":2: 'nan' is not a finite number"},
    {"wall 0 0 1e999 0\nstart 1 1 0\n", ":1: '1e999' is not a finite number"},
    {"wall 0 0 4 0\ncircle 2 2 0.1x\nstart 1 1 0\n", ":2: '0.1x' is not a number"},
    {"wall 1 1 1 1\nstart 3 3 0\n", ":1: wall has zero length"},
    {"wall 0 0 4 0\nbox 2 2 -1 1\nstart 1 1 0\n", ":2: box width and height must be positive"},
    {"wall 0 0 4 0\ncircle 2 2 0\nstart 1 1 0\n", ":2: circle radius must be positive"},
    {"wall 0 0 4 0\npoly 2 2 3 2 3 2 2 3\nstart 1 1 0\n", ":2: poly points 2 and 3 are the same"},
    {"wall 0 0 4 0\nstart 1 1 0\n\nstart 2 2 0\n", ":4: a second start (the first is on line 2)"},
    {"wall 0 0 4 0\n", ": no start pose"},
    {"# nothing here\nstart 1 1 0\n", ": no walls or obstacles"},
    {"", ": no walls or obstacles"},
    /* Start poses: inside a box, inside a circle, touching a wall, a whisker too close. */
    {"wall 0 0 4 0\nbox 1 1 2 2\nstart 2 2 0\n", ":3: start pose (2, 2) is inside an obstacle"},
    {"wall 0 0 4 0\ncircle 2 2 0.5\n# x\nstart 2.1 2 0\n", ":4: start pose (2.1, 2) is inside"},
    {"start 1 0.05 0\nwall 0 0 4 0\n", ":1: start pose (1, 0.05) is too close to an obstacle"},
    {"wall 0 0 4 0\nstart 1 0.0899 0\n", ":2: start pose (1, 0.0899) is too close"},
    {"circle 2 2 0.5\nstart 2.589 2 0\n", ":2: start pose (2.589, 2) is too close"},
};

static void test_errors_name_file_and_line(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_rooms / sizeof bad_rooms[0]; i++) {
        const char *path = test_write("bad.room", bad_rooms[i].text);
        test_load_refused(path, NULL, bad_rooms[i].expect);
        unlink(path);
    }
}

static void test_start_just_clear_is_accepted(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 4 0\nstart 1 0.0901 0\n");
    assert_true(r.has_start);
    room_free(&r);
    /* Inside a polygon outline is where a room is: accepted. */
    test_room(&r, "poly 0 0 3 0 3 2 0 2\nstart 1.5 1 0\n");
    assert_int_equal(r.nsegs, 4u);
    room_free(&r);
}

static void test_missing_file(void **state)
{
    (void)state;
    room_t r = {0};
    char err[300] = "";
    assert_int_equal(room_load(&r, "/nonexistent/x.room", NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.room: cannot open"));
    assert_int_equal(room_load(&r, "/nonexistent/x.yaml", NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/x.yaml: cannot open"));
}

static void test_shipped_rooms_load(void **state)
{
    (void)state;
    static const char *const names[] = {"default", "obstacles", "clutter",
                                        "narrow",  "slanted",   "flat"};
    for (size_t i = 0; i < 6u; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s.room", HOST_ROOMS_DIR, names[i]);
        room_t r;
        char err[300] = "";
        if (room_load(&r, path, NULL, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        assert_true(r.has_start);
        assert_true(room_disc_free(&r, r.start_x, r.start_y, ROOM_BODY_RADIUS_M));
        /* Walled in: rays in every direction hit something within the bounding box. */
        double diag = hypot(r.max_x - r.min_x, r.max_y - r.min_y);
        for (int k = 0; k < 36; k++) {
            assert_true(room_ray(&r, r.start_x, r.start_y, k * TEST_PI / 18.0, diag, NULL) <= diag);
        }
        if (i == 0u) { /* the paper's ~20 m² */
            assert_true(fabs((r.max_x - r.min_x) * (r.max_y - r.min_y) - 20.0) < 1.0);
        }
        if (i == 3u) { /* the passage lets the body through, and no more than twice over */
            double gap = room_clearance(&r, 2.55, 1.5, 1.0);
            assert_true(gap > ROOM_BODY_RADIUS_M && gap < 2.0 * ROOM_BODY_RADIUS_M);
        }
        if (i == 5u) { /* three rooms: each door 0.8 m wide, a jamb 0.4 m from its middle */
            assert_true(fabs(room_clearance(&r, 3.05, 1.4, 1.0) - 0.4) < 1e-9);
            assert_true(fabs(room_clearance(&r, 5.4, 2.85, 1.0) - 0.4) < 1e-9);
            assert_true(room_ray(&r, 2.0, 1.4, 0.0, 10.0, NULL) > 4.0);  /* through the door */
            assert_true(room_ray(&r, 2.0, 3.0, 0.0, 10.0, NULL) < 1.01); /* not through a wall */
        }
        room_free(&r);
    }
}

/* ---- ROS maps ------------------------------------------------------------------------- */

#define MW 12u
#define MH 8u

/* A 12 x 8 image: a wall frame of 0 (occupied), inside 254 (free), with test pixels. */
static void map_pixels(uint8_t px[MH][MW])
{
    for (uint32_t y = 0; y < MH; y++) {
        for (uint32_t x = 0; x < MW; x++) {
            px[y][x] = (x == 0u || y == 0u || x == MW - 1u || y == MH - 1u) ? 0u : 254u;
        }
    }
    px[2][3] = 89u;  /* p = 0.651 > 0.65: occupied */
    px[2][4] = 90u;  /* p = 0.647: not occupied, not free */
    px[2][5] = 206u; /* p = 0.192 < 0.196: free */
    px[2][6] = 205u; /* p = 0.196: unknown (map_server's grey) */
}

static const char *write_pgm(const char *tag, int ascii, const uint8_t px[MH][MW])
{
    const char *path = test_path(tag);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f, "%s\n# a comment\n%u %u\n255\n", ascii ? "P2" : "P5", MW, MH);
    for (uint32_t y = 0; y < MH; y++) {
        for (uint32_t x = 0; x < MW; x++) {
            if (ascii) {
                fprintf(f, "%u%c", (unsigned)px[y][x], x + 1u == MW ? '\n' : ' ');
            } else {
                fputc(px[y][x], f);
            }
        }
    }
    fclose(f);
    return path;
}

static const char *write_yaml(const char *tag, const char *image, const char *extra)
{
    char text[1024];
    const char *slash = strrchr(image, '/');
    snprintf(text, sizeof text,
             "image: %s\nresolution: 0.1\norigin: [-1.0, -0.5, 0.0]  # metres\n"
             "occupied_thresh: 0.65\nfree_thresh: 0.196\n%s",
             slash != NULL ? slash + 1 : image, extra);
    return test_write(tag, text);
}

/* Pixel (x, y) of the file (row 0 at the top) in the room's raster (row 0 at the bottom). */
static uint8_t occ_at(const room_t *r, uint32_t x, uint32_t file_y)
{
    return r->occ[(size_t)(r->occ_h - 1u - file_y) * r->occ_w + x];
}

static uint8_t free_at(const room_t *r, uint32_t x, uint32_t file_y)
{
    return r->occ_free[(size_t)(r->occ_h - 1u - file_y) * r->occ_w + x];
}

static void check_map(const room_t *r)
{
    assert_false(r->has_start);
    assert_int_equal(r->occ_w, MW);
    assert_int_equal(r->occ_h, MH);
    assert_true(fabs(r->occ_res - 0.1) < 1e-12);
    assert_true(fabs(r->occ_x0 + 1.0) < 1e-12 && fabs(r->occ_y0 + 0.5) < 1e-12);
    assert_int_equal(occ_at(r, 0, 0), 1);
    assert_int_equal(occ_at(r, 1, 1), 0);
    assert_int_equal(free_at(r, 1, 1), 1);
    assert_int_equal(occ_at(r, 3, 2), 1);
    assert_int_equal(occ_at(r, 4, 2), 0);
    assert_int_equal(free_at(r, 4, 2), 0);
    assert_int_equal(free_at(r, 5, 2), 1);
    assert_int_equal(free_at(r, 6, 2), 0);
    assert_int_equal(occ_at(r, 6, 2), 0);
    /* The bounding box is the occupied frame: the whole image here. */
    assert_true(fabs(r->min_x + 1.0) < 1e-12 && fabs(r->max_x - 0.2) < 1e-12);
    assert_true(fabs(r->min_y + 0.5) < 1e-12 && fabs(r->max_y - 0.3) < 1e-12);
}

static void test_ros_map_p5_and_p2(void **state)
{
    (void)state;
    uint8_t px[MH][MW];
    map_pixels(px);
    for (int ascii = 0; ascii < 2; ascii++) {
        const char *img = write_pgm(ascii ? "m2.pgm" : "m5.pgm", ascii, px);
        const char *yaml = write_yaml("m.yaml", img, "negate: 0\nmode: trinary\n");
        room_t r;
        char err[300] = "";
        if (room_load(&r, yaml, NULL, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        check_map(&r);
        /* The pixel at file row 2, column 3 spans x -0.7..-0.6, y 0..0.1 (row 5 from the
           bottom); a ray along +x from x = -0.85 meets its face head-on. */
        double c = 0.0;
        double d = room_ray(&r, -0.85, -0.5 + 5.5 * 0.1, 0.0, 5.0, &c);
        assert_true(fabs(d - 0.15) < 1e-9);
        assert_true(c > 0.99);
        room_free(&r);
        unlink(img);
        unlink(yaml);
    }
}

static void test_ros_map_negate(void **state)
{
    (void)state;
    uint8_t px[MH][MW];
    for (uint32_t y = 0; y < MH; y++) {
        for (uint32_t x = 0; x < MW; x++) {
            px[y][x] = (x == 0u || y == 0u || x == MW - 1u || y == MH - 1u) ? 255u : 0u;
        }
    }
    const char *img = write_pgm("neg.pgm", 0, px);
    const char *yaml = write_yaml("neg.yaml", img, "negate: 1\n");
    room_t r;
    char err[300] = "";
    if (room_load(&r, yaml, NULL, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(occ_at(&r, 0, 0), 1);
    assert_int_equal(occ_at(&r, 5, 5), 0);
    assert_int_equal(free_at(&r, 5, 5), 1);
    room_free(&r);
    unlink(img);
    unlink(yaml);
}

static void test_ros_map_crop(void **state)
{
    (void)state;
    uint8_t px[MH][MW];
    map_pixels(px);
    const char *img = write_pgm("crop.pgm", 0, px);
    const char *yaml = write_yaml("crop.yaml", img, "");
    room_t r;
    char err[300] = "";
    /* Pixel centres x = -0.95 + 0.1 i; keep i = 2..5 (x in [-0.8, -0.4)), and the bottom
       three rows (centres y = -0.45, -0.35, -0.25 in [-0.5, -0.2)). */
    room_crop_t crop = {-0.8, -0.5, 0.4, 0.3};
    if (room_load(&r, yaml, &crop, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(r.occ_w, 4u);
    assert_int_equal(r.occ_h, 3u);
    assert_true(fabs(r.occ_x0 + 0.8) < 1e-9 && fabs(r.occ_y0 + 0.5) < 1e-9);
    assert_int_equal(r.occ[0], 1u); /* the bottom wall */
    assert_int_equal(r.occ[(size_t)1u * 4u + 1u], 0u);
    /* (3, 2) of the file is row 5 from the bottom: outside this crop. */
    room_free(&r);

    /* A crop of free pixels only is closed by its edges: a box of that size. */
    room_crop_t free_only = {-0.6, -0.2, 0.3, 0.3};
    if (room_load(&r, yaml, &free_only, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(r.occ_w, 3u);
    assert_int_equal(r.occ_h, 3u);
    for (uint32_t k = 0; k < 9u; k++) {
        assert_int_equal(r.occ[k], k == 4u ? 0u : 1u); /* all but the middle */
    }
    room_free(&r);

    /* The crop with that pixel only. */
    room_crop_t one = {-0.7, -0.5 + 0.5, 0.1, 0.1};
    if (room_load(&r, yaml, &one, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_int_equal(r.occ_w, 1u);
    assert_int_equal(r.occ_h, 1u);
    assert_int_equal(r.occ[0], 1u);
    room_free(&r);

    room_t untouched;
    memset(&r, 0x5A, sizeof r);
    memcpy(&untouched, &r, sizeof r);
    room_crop_t outside = {10.0, 10.0, 1.0, 1.0};
    assert_int_equal(room_load(&r, yaml, &outside, err, sizeof err), -1);
    assert_non_null(strstr(err, "lies outside the map"));
    room_crop_t bad = {0.0, 0.0, -1.0, 1.0};
    assert_int_equal(room_load(&r, yaml, &bad, err, sizeof err), -1);
    assert_non_null(strstr(err, "positive size"));
    assert_memory_equal(&r, &untouched, sizeof r);
    unlink(img);
    unlink(yaml);
}

static void test_ros_map_errors(void **state)
{
    (void)state;
    uint8_t px[MH][MW];
    map_pixels(px);
    const char *img = write_pgm("e.pgm", 0, px);
    const char *name = strrchr(img, '/') + 1;
    char text[1024];
    struct {
        const char *yaml;
        const char *expect;
    } cases[] = {
        {"resolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n",
         ": no 'image' key"},
        {"@origin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", ": no 'resolution' key"},
        {"@resolution: 0.1\norigin: [0, 0, 0.5]\noccupied_thresh: 0.65\n"
         "free_thresh: 0.2\n",
         ":3: an origin yaw of 0.5 is not supported"},
        {"@resolution: 0.1\norigin: [0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n",
         ":3: origin must be [x, y, yaw]"},
        {"@resolution: -1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
         "free_thresh: 0.2\n",
         ":2: resolution must be positive"},
        {"@resolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 1.5\n"
         "free_thresh: 0.2\n",
         ":4: occupied_thresh must lie in 0..1"},
        {"@resolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.1\n"
         "free_thresh: 0.2\n",
         ":5: free_thresh 0.2 is above occupied_thresh 0.1"},
        {"@resolution: 0.1\nresolution: 0.2\n", ":3: 'resolution' given twice"},
        {"@resolution: 0.1\nnegate: maybe\n", ":3: negate must be 0 or 1"},
        {"@this line has no colon\n", ":2: expected 'key: value'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        /* '@' at the start stands for the image line. */
        if (cases[i].yaml[0] == '@') {
            snprintf(text, sizeof text, "image: %s\n%s", name, cases[i].yaml + 1);
        } else {
            snprintf(text, sizeof text, "%s", cases[i].yaml);
        }
        const char *yaml = test_write("e.yaml", text);
        room_t r;
        char err[300] = "";
        assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), -1);
        char want[600];
        snprintf(want, sizeof want, "%s%s", yaml, cases[i].expect);
        if (strncmp(err, want, strlen(want)) != 0) {
            fail_msg("case %zu: got \"%s\", want \"%s...\"", i, err, want);
        }
        unlink(yaml);
    }
    unlink(img);

    /* Image problems name the image. */
    struct {
        const char *bytes;
        size_t len;
        const char *expect;
    } images[] = {
        {"P6\n2 2\n255\n", 11u, ": not a PGM image"},
        {"P5\n2 2\n65535\n", 13u, ": only 8-bit images are supported"},
        {"P5\n2 2\n255\n\x01\x02", 13u, ": image data is truncated"},
        {"P2\n2 2\n9\n1 2 3 10\n", 18u, ": pixel 3 is 10, above maxval 9"},
        {"P5\n0 2\n255\n", 11u, ": image size 0x2"},
    };
    for (size_t i = 0; i < sizeof images / sizeof images[0]; i++) {
        const char *bad = test_path("bad.pgm");
        FILE *f = fopen(bad, "wb");
        assert_non_null(f);
        fwrite(images[i].bytes, 1u, images[i].len, f);
        fclose(f);
        const char *yaml = write_yaml("bad.yaml", bad, "");
        room_t r;
        char err[300] = "";
        assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), -1);
        char want[600];
        snprintf(want, sizeof want, "%s%s", bad, images[i].expect);
        if (strncmp(err, want, strlen(want)) != 0) {
            fail_msg("image %zu: got \"%s\", want \"%s...\"", i, err, want);
        }
        unlink(yaml);
        unlink(bad);
    }
}

static void test_find_start(void **state)
{
    (void)state;
    /* A 4 m x 3 m room with a pillar in the middle: the start is beside the pillar. */
    room_t r;
    test_room(&r, "wall 0 0 4 0\nwall 4 0 4 3\nwall 4 3 0 3\nwall 0 3 0 0\n"
                  "circle 2 1.5 0.3\nstart 0.5 0.5 0\n");
    double x = -1.0;
    double y = -1.0;
    double th = -1.0;
    assert_int_equal(room_find_start(&r, 0.2, &x, &y, &th), 0);
    double d = hypot(x - 2.0, y - 1.5);
    assert_true(d >= 0.5 - 1e-9 && d < 0.5 + 0.03); /* just clear of the pillar */
    assert_true(room_disc_free(&r, x, y, 0.2));
    assert_true(th == 0.0);
    /* No room for a 2 m disc. */
    double x2 = 7.0;
    assert_int_equal(room_find_start(&r, 2.0, &x2, &y, &th), -1);
    assert_true(x2 == 7.0);
    room_free(&r);

    /* A raster: the frame of the test map. */
    uint8_t px[MH][MW];
    map_pixels(px);
    const char *img = write_pgm("fs.pgm", 0, px);
    const char *yaml = write_yaml("fs.yaml", img, "");
    char err[300];
    assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), 0);
    assert_int_equal(room_find_start(&r, 0.15, &x, &y, &th), 0);
    assert_true(room_disc_free(&r, x, y, 0.15));
    /* A pixel centre, on known free ground. */
    double fx = (x - r.occ_x0) / r.occ_res - 0.5;
    assert_true(fabs(fx - round(fx)) < 1e-9);
    room_free(&r);
    unlink(img);
    unlink(yaml);
}

/* The real building maps of host_sim/maps (each with its licence): each loads, crops, finds
 * a start and takes a robot. Skipped where they are not there. */
static void test_building_maps(void **state)
{
    (void)state;
    static const struct {
        const char *yaml;
        room_crop_t crop;
        bool cropped;
    } maps[] = {
        {"edu_room/edu_room_cropped.yaml", {0, 0, 0, 0}, false},
        {"intel_lab/intel.yaml", {5.0, 5.0, 12.0, 10.0}, true},
        {"willow_garage/willow-2010-02-18-0.10.yaml", {20.0, 20.0, 12.0, 12.0}, true},
        {"utexas_gdc_3ne/3ne.yaml", {-20.0, -10.0, 12.0, 10.0}, true},
    };
    char probe[512];
    snprintf(probe, sizeof probe, "%s/%s", HOST_SHARED_MAPS_DIR, maps[0].yaml);
    if (access(probe, R_OK) != 0) {
        print_message("no building maps at %s: skipped\n", HOST_SHARED_MAPS_DIR);
        skip();
    }
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", HOST_SHARED_MAPS_DIR, maps[i].yaml);
        room_t r;
        char err[300] = "";
        if (room_load(&r, path, maps[i].cropped ? &maps[i].crop : NULL, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
        assert_true(r.occ_w > 50u && r.occ_h > 50u);
        if (maps[i].cropped) {
            assert_true(r.max_x - r.min_x <= maps[i].crop.w + 0.2);
            assert_true(r.max_y - r.min_y <= maps[i].crop.h + 0.2);
        }
        double x;
        double y;
        double th;
        assert_int_equal(room_find_start(&r, 0.3, &x, &y, &th), 0);
        assert_true(room_disc_free(&r, x, y, 0.3));
        r.start_x = x;
        r.start_y = y;
        sim_t *s = test_ideal_world(&r);
        assert_non_null(s);
        sim_destroy(s);
        room_free(&r);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_shape),
        cmocka_unit_test(test_free_wall_ends_are_round),
        cmocka_unit_test(test_crlf_and_angles),
        cmocka_unit_test(test_errors_name_file_and_line),
        cmocka_unit_test(test_start_just_clear_is_accepted),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_shipped_rooms_load),
        cmocka_unit_test(test_ros_map_p5_and_p2),
        cmocka_unit_test(test_ros_map_negate),
        cmocka_unit_test(test_ros_map_crop),
        cmocka_unit_test(test_ros_map_errors),
        cmocka_unit_test(test_find_start),
        cmocka_unit_test(test_building_maps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
