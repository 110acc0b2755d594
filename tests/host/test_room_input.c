/* SPDX-License-Identifier: MIT */
/* Tests of room loading against hostile input: endless files, NUL bytes, huge numbers,
 * crops that cannot be, start poses outside the room; and rooms parsed from memory. */
#define _POSIX_C_SOURCE 200809L /* mkfifo, truncate */
#include <math.h>
#include <sys/stat.h>

#include "host_test.h"

static const char *yaml_for(const char *tag, const char *image, const char *extra)
{
    char text[1024];
    snprintf(text, sizeof text,
             "image: %s\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
             "free_thresh: 0.2\n%s",
             image, extra);
    return test_write(tag, text);
}

/* B7: files without end, or too large, are refused at a stated size. */
static void test_size_limits(void **state)
{
    (void)state;
    /* Inputs are regular files: one that never ends, or a FIFO that no one writes (which
     * would block for ever), is refused at once. */
    test_load_refused("/dev/zero", NULL, ": is not a regular file");
    test_load_refused(HOST_TEST_DIR, NULL, ": is a directory");
    const char *fifo = test_write("fifo.room", "");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    test_load_refused(fifo, NULL, ": is not a regular file (a FIFO");
    unlink(fifo);
    const char *yaml = yaml_for("zero.yaml", "/dev/zero", "");
    room_t r;
    char err[400] = "";
    assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "/dev/zero: is not a regular file"));
    unlink(yaml);
    /* Files larger than a kind's limit: a room, an image (sparse files, no disk used). */
    const char *big = test_write("big.room", "");
    assert_int_equal(truncate(big, (off_t)(64 << 20) + 1), 0);
    test_load_refused(big, NULL, ": larger than 67108864 bytes");
    const char *bigpgm = test_write("big.pgm", "");
    assert_int_equal(truncate(bigpgm, (off_t)(128 << 20) + 1), 0);
    yaml = yaml_for("bigpgm.yaml", bigpgm, "");
    assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "big.pgm: larger than 134217728 bytes"));
    unlink(yaml);
    unlink(big);
    unlink(bigpgm);
    /* An image whose header promises more pixels than the limit. */
    const char *pgm = test_write("huge.pgm", "P5\n9000 9000\n255\n");
    yaml = yaml_for("huge.yaml", pgm, "");
    assert_int_equal(room_load(&r, yaml, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "image size 9000x9000 is not supported"));
    unlink(yaml);
    unlink(pgm);
}

/* B13: a NUL byte is an error naming its line, in a room file and in a map's YAML. */
static void test_nul_bytes(void **state)
{
    (void)state;
    static const char room[] = "wall 0 0 4 0\nwall 4 0 4 4\n\0wall 4 4 0 4\nstart 1 1 0\n";
    char err[300] = "";
    room_t r;
    assert_int_equal(room_parse(&r, "nul.room", room, sizeof room - 1u, err, sizeof err), -1);
    assert_string_equal(err, "nul.room:3: a NUL byte: not a text file");
    static const char first[] = "\0wall 0 0 4 0\nstart 1 1 0\n";
    assert_int_equal(room_parse(&r, "nul.room", first, sizeof first - 1u, err, sizeof err), -1);
    assert_string_equal(err, "nul.room:1: a NUL byte: not a text file");
    static const char yaml[] = "image: x.pgm\nresolution: 0.05\x00\n";
    assert_int_equal(room_parse_ros(&r, "m.yaml", yaml, sizeof yaml - 1u, "x.pgm", "", 0u, NULL,
                                    err, sizeof err),
                     -1);
    assert_string_equal(err, "m.yaml:2: a NUL byte: not a text file");
}

/* N5: a message quotes the file's words with control bytes escaped, never raw (an xterm
 * takes ESC ] 0 ; ... BEL as its new title); printable UTF-8 is shown as it is. */
static void test_messages_escape_control_bytes(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *says;
    } cases[] = {
        {"wall \033]0;PWNED\007 0 5 0\nstart 1 1 0\n", "esc.room:1: '\\x1b]0;PWNED\\x07' is not"},
        {"\033[2Jwall 0 0 5 0\nstart 1 1 0\n", "esc.room:1: unknown keyword '\\x1b[2Jwall'"},
        {"m\xc3\xbcr 0 0 5 0\nstart 1 1 0\n", "unknown keyword 'm\xc3\xbcr'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        room_t r;
        char err[300] = "";
        assert_int_equal(
            room_parse(&r, "esc.room", cases[i].text, strlen(cases[i].text), err, sizeof err), -1);
        if (strstr(err, cases[i].says) == NULL) {
            fail_msg("case %zu: '%s' does not say '%s'", i, err, cases[i].says);
        }
    }
    static const char yaml[] = "image: \033]0;x\007\nresolution: 0.05\nmode: \033[1m\n";
    char err[300] = "";
    room_t r;
    assert_int_equal(room_parse_ros(&r, "m.yaml", yaml, sizeof yaml - 1u, "x.pgm", "", 0u, NULL,
                                    err, sizeof err),
                     -1);
    assert_string_equal(err, "m.yaml:3: unknown mode '\\x1b[1m'");
}

/* Numbers a room cannot hold are refused without printing them in full. */
static void test_huge_numbers(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *says;
    } cases[] = {
        {"wall 0 0 1e300 0\nstart 1 1 0\n",
         "big.room:1: '1e300' is out of range: values lie within +-10000"},
        {"wall 0 0 4 0\nstart 10000.5 1 0\n", "big.room:2: '10000.5' is out of range"},
        {"circle 0 0 20001\nstart 1 1 0\n", "big.room:1: '20001' is out of range"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        room_t r;
        char err[300] = "";
        assert_int_equal(
            room_parse(&r, "big.room", cases[i].text, strlen(cases[i].text), err, sizeof err), -1);
        if (strstr(err, cases[i].says) == NULL) {
            fail_msg("case %zu: got \"%s\", want \"%s\"", i, err, cases[i].says);
        }
    }
    static const char pgm[] = "P5\n2 2\n255\n\x00\x00\x00\x00";
    static const struct {
        const char *yaml;
        const char *says;
    } maps[] = {
        {"image: m.pgm\nresolution: 0.05\norigin: [-2e4, 0, 0]\noccupied_thresh: "
         "0.65\nfree_thresh: 0.2\n",
         "m.yaml:3: origin lies beyond +-10000 m"},
        {"image: m.pgm\nresolution: 1e-9\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: "
         "0.2\n",
         "m.yaml:2: resolution 1e-9 m is out of range 0.001..10 m"},
        /* Numbers past a double, or far out of range, are out of range, not "not finite". */
        {"image: m.pgm\nresolution: 1e300\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: "
         "0.2\n",
         "m.yaml:2: resolution 1e300 m is out of range 0.001..10 m"},
        {"image: m.pgm\nresolution: 1e999\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: "
         "0.2\n",
         "m.yaml:2: resolution 1e999 m is out of range 0.001..10 m"},
        {"image: m.pgm\nresolution: 0x1p-4\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: "
         "0.2\n",
         "m.yaml:2: resolution needs a decimal number, not '0x1p-4'"},
        {"image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 2e300\nfree_thresh: "
         "0.2\n",
         "m.yaml:4: occupied_thresh must lie in 0..1"},
        /* A long image name says how long, and the limit. */
        {"image: "
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
         "aaaaa"
         ".pgm\nresolution: 0.05\n",
         "m.yaml:1: image: a file name of 604 characters, longer than the 511 taken"},
        {"image: m.pgm\nresolution: 9\norigin: [9999, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: "
         "0.2\n",
         "m.yaml:2: the map (2x2 pixels of 9 m from (9999, 0)) reaches beyond +-10000 m"},
    };
    for (size_t i = 0; i < sizeof maps / sizeof maps[0]; i++) {
        room_t r;
        char err[300] = "";
        assert_int_equal(room_parse_ros(&r, "m.yaml", maps[i].yaml, strlen(maps[i].yaml), "m.pgm",
                                        pgm, sizeof pgm - 1u, NULL, err, sizeof err),
                         -1);
        if (strstr(err, maps[i].says) == NULL) {
            fail_msg("map %zu: got \"%s\", want \"%s\"", i, err, maps[i].says);
        }
    }
}

/* B9: a crop applies to building maps only; one that holds no pixel says so. */
static void test_crops(void **state)
{
    (void)state;
    const char *room = test_write("c.room", "wall 0 0 4 0\nstart 1 1 0\n");
    room_crop_t crop = {0.0, 0.0, 1.0, 1.0};
    test_load_refused(room, &crop,
                      ": a crop takes part of a ROS map (.yaml); a .room file is taken whole");
    unlink(room);
    static const char pgm[] = "P5\n4 4\n255\n"
                              "\x00\x00\x00\x00\x00\xff\xff\x00\x00\xff\xff\x00\x00\x00\x00\x00";
    static const char yaml[] = "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n"
                               "occupied_thresh: 0.65\nfree_thresh: 0.2\n";
    room_t r;
    char err[300] = "";
    room_crop_t tiny = {0.3, 0.3, 0.1, 0.1};
    assert_int_equal(room_parse_ros(&r, "m.yaml", yaml, sizeof yaml - 1u, "m.pgm", pgm,
                                    sizeof pgm - 1u, &tiny, err, sizeof err),
                     -1);
    assert_string_equal(err, "m.yaml: the crop (0.3 0.3 0.1 0.1) holds no pixel centre (the "
                             "pixels are 0.5 m)");
    room_crop_t beside = {5.0, 0.0, 1.0, 1.0};
    assert_int_equal(room_parse_ros(&r, "m.yaml", yaml, sizeof yaml - 1u, "m.pgm", pgm,
                                    sizeof pgm - 1u, &beside, err, sizeof err),
                     -1);
    assert_string_equal(err, "m.yaml: the crop (5 0 1 1) lies outside the map (0 0 .. 2 2)");
    /* The same map whole, from memory: its frame is occupied. */
    assert_int_equal(room_parse_ros(&r, "m.yaml", yaml, sizeof yaml - 1u, "m.pgm", pgm,
                                    sizeof pgm - 1u, NULL, err, sizeof err),
                     0);
    assert_int_equal(r.occ_w, 4u);
    assert_int_equal(r.occ[0], 1u);
    assert_int_equal(r.occ[5], 0u);
    room_free(&r);
}

/* A room in memory is the room of the same file. */
static void test_parse_equals_load(void **state)
{
    (void)state;
    static const char text[] = "# a room\nwall 0 0 5 0\nwall 5 0 5 4\nwall 5 4 0 4\nwall 0 4 0 0\n"
                               "box 1 1 0.5 0.5\ncircle 3 3 0.2\n\nstart 2.5 2 90\n";
    room_t a;
    room_t b;
    test_room(&a, text);
    char err[300] = "";
    assert_int_equal(room_parse(&b, "mem.room", text, sizeof text - 1u, err, sizeof err), 0);
    assert_int_equal(a.nsegs, b.nsegs);
    assert_memory_equal(a.segs, b.segs, a.nsegs * sizeof *a.segs);
    assert_memory_equal(a.circles, b.circles, a.ncircles * sizeof *a.circles);
    assert_true(a.start_x == b.start_x && a.start_th == b.start_th);
    assert_int_equal(b.start_line, 9u);
    room_free(&a);
    room_free(&b);
}

/* B10: a point is inside the room when every one of eight rays meets a wall. */
static void test_encloses(void **state)
{
    (void)state;
    room_t r;
    test_room(&r, "wall 0 0 5 0\nwall 5 0 5 4\nwall 5 4 0 4\nwall 0 4 0 0\nstart 2 2 0\n");
    double open = -1.0;
    assert_true(room_encloses(&r, 2.0, 2.0, &open));
    assert_true(open == -1.0);
    assert_false(room_encloses(&r, 6.0, 2.0, &open));
    assert_true(open == 0.0); /* east: nothing there */
    assert_false(room_encloses(&r, 2.0, -1.0, &open));
    assert_true(open == 180.0 || open == 225.0 || open == 270.0 || open == 315.0 || open == 0.0);
    room_free(&r);
    /* A doorway in the south wall does not open the room to rays from inside. */
    test_room(&r, "wall 0 0 2 0\nwall 2.8 0 5 0\nwall 5 0 5 4\nwall 5 4 0 4\nwall 0 4 0 0\n"
                  "start 1 2 0\n");
    assert_true(room_encloses(&r, 1.0, 2.0, NULL));
    room_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_size_limits),
        cmocka_unit_test(test_nul_bytes),
        cmocka_unit_test(test_huge_numbers),
        cmocka_unit_test(test_crops),
        cmocka_unit_test(test_parse_equals_load),
        cmocka_unit_test(test_encloses),
        cmocka_unit_test(test_messages_escape_control_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
