/* SPDX-License-Identifier: MIT */
/* host_sim --commands: timed commands to the robot, framed as a host would send them. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hal_common/config_text.h"
#include "hal_common/number.h"
#include "host_sim.h"

/* The key names and their ids (config_fields.h). */
static const struct {
    uint8_t id;
    const char *name;
} key_names[] = {
#define KEY_NAME(name, type, dflt, lo, hi, rule, id, live, words) {id, #name},
    TELEM_CONFIG_KEYS(KEY_NAME)
#undef KEY_NAME
};

/* The mode names as a message lists them: "off, random, ..." (explore_modes.h). */
#define MODE_NAME(id, value, name, ...) ", " #name
static const char mode_list[] = SLAM_EXPLORE_MODES(MODE_NAME);
#undef MODE_NAME

static const struct {
    const char *word;
    uint8_t type;
} words[] = {
    {"start", TELEM_CMD_START},  {"stop", TELEM_CMD_STOP},
    {"mode", TELEM_CMD_MODE},    {"get", TELEM_CMD_GET},
    {"set", TELEM_CMD_SET},      {"save", TELEM_CMD_SAVE},
    {"map", TELEM_CMD_SEND_MAP}, {"calibrate", TELEM_CMD_CALIBRATE},
};

static int key_id(const char *name)
{
    for (size_t i = 0; i < sizeof key_names / sizeof key_names[0]; i++) {
        if (strcmp(key_names[i].name, name) == 0) {
            return key_names[i].id;
        }
    }
    return -1;
}

/* Room for one more line of n bytes, grown geometrically (doubling): a file of N lines
 * costs O(log N) reallocations, not N (each a copy of everything so far). */
static bool reserve(commands_t *c, size_t n)
{
    if (c->n == c->lines_cap) {
        size_t cap = c->lines_cap != 0u ? 2u * c->lines_cap : 64u;
        command_line_t *lines = realloc(c->lines, cap * sizeof *lines);
        if (lines == NULL) {
            return false;
        }
        c->lines = lines;
        c->lines_cap = cap;
        c->grows++;
    }
    if (c->nbytes + n > c->bytes_cap) {
        size_t cap = c->bytes_cap != 0u ? 2u * c->bytes_cap : 1024u;
        while (cap < c->nbytes + n) {
            cap *= 2u;
        }
        uint8_t *bytes = realloc(c->bytes, cap);
        if (bytes == NULL) {
            return false;
        }
        c->bytes = bytes;
        c->bytes_cap = cap;
        c->grows++;
    }
    return true;
}

/* Adds bytes to the list; false when out of memory. */
static bool add(commands_t *c, uint64_t tick, const uint8_t *b, size_t n)
{
    if (!reserve(c, n)) {
        return false;
    }
    memcpy(c->bytes + c->nbytes, b, n);
    c->lines[c->n++] = (command_line_t){tick, c->nbytes, n};
    c->nbytes += n;
    return true;
}

/* One line's command as bytes: a word and its arguments, or `hex` and raw bytes. Returns
 * the byte count, or -1 with a message in err. */
static int encode(char *args, uint8_t *out, size_t max, char *err, size_t errlen)
{
    char *p = strtok(args, " \t");
    if (p != NULL && strcmp(p, "hex") == 0) {
        size_t n = 0;
        for (char *h = strtok(NULL, " \t"); h != NULL; h = strtok(NULL, " \t")) {
            for (; h[0] != '\0'; h += 2) {
                if (!isxdigit((unsigned char)h[0]) || !isxdigit((unsigned char)h[1]) || n == max) {
                    snprintf(err, errlen, "hex: expected pairs of hex digits, at most %zu bytes",
                             max);
                    return -1;
                }
                const char two[3] = {h[0], h[1], '\0'};
                out[n++] = (uint8_t)strtoul(two, NULL, 16);
            }
        }
        return (int)n;
    }
    char *tok[4];
    int ntok = 0;
    for (; p != NULL; p = strtok(NULL, " \t")) {
        if (ntok == 4) {
            snprintf(err, errlen, "too many words");
            return -1;
        }
        tok[ntok++] = p;
    }
    if (ntok == 0) {
        snprintf(err, errlen, "no command");
        return -1;
    }
    int type = -1;
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++) {
        if (strcmp(tok[0], words[i].word) == 0) {
            type = words[i].type;
        }
    }
    int want = type == TELEM_CMD_SET ? 3 : type == TELEM_CMD_GET || type == TELEM_CMD_MODE ? 2 : 1;
    if (type < 0 || ntok != want) {
        snprintf(err, errlen,
                 "'%s': expected start, stop, mode MODE, get KEY, set KEY VALUE, "
                 "save, map, calibrate, or hex BYTES",
                 tok[0]);
        return -1;
    }
    uint8_t payload[TELEM_CMD_PAYLOAD_MAX];
    uint8_t len = 0;
    if (type == TELEM_CMD_MODE) {
        int mode = -1;
        for (int m = 0; m < EXPLORE_MODES; m++) {
            mode = strcmp(tok[1], explore_names[m]) == 0 ? m : mode;
        }
        if (mode < 0) {
            snprintf(err, errlen, "mode: '%s' is not one of %s", tok[1], mode_list + 2);
            return -1;
        }
        payload[len++] = (uint8_t)mode;
    } else if (type == TELEM_CMD_GET || type == TELEM_CMD_SET) {
        int id = key_id(tok[1]);
        if (id < 0) {
            snprintf(err, errlen, "unknown key '%s' (the fields of slam_config_t)", tok[1]);
            return -1;
        }
        payload[len++] = (uint8_t)id;
        if (type == TELEM_CMD_SET) {
            /* The value as config.txt writes it (cal_* as 0.9901); its range is the
             * robot's to judge. */
            slam_config_t scratch;
            slam_config_default(&scratch);
            if (cfgtext_set(&scratch, tok[1], tok[2], err, errlen) != 0) {
                return -1;
            }
            uint32_t v = 0;
            (void)telem_config_get(&scratch, (uint8_t)id, &v);
            for (int k = 0; k < 4; k++) {
                payload[len++] = (uint8_t)(v >> (8 * k));
            }
        }
    }
    if (max < TELEM_CMD_FRAME_MAX) {
        snprintf(err, errlen, "no room");
        return -1;
    }
    return (int)telem_frame(out, (uint8_t)type, payload, len);
}

int commands_load(const char *path, commands_t *c)
{
    *c = (commands_t){0};
    char why[600];
    FILE *f = cfgtext_open_file(path, why, sizeof why);
    if (f == NULL) {
        fprintf(stderr, "host_sim: --commands %s\n", why);
        return EXIT_USAGE;
    }
    char line[1024];
    unsigned lineno = 0;
    uint64_t last = 0;
    int rc = 0;
    while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
        lineno++;
        char err[256] = "";
        line[strcspn(line, "#\r\n")] = '\0';
        char *p = line + strspn(line, " \t");
        if (*p == '\0') {
            continue;
        }
        /* The time is the first word: a decimal number of seconds (hal_common/number.h). */
        char *end = p + strcspn(p, " \t");
        bool more = *end != '\0';
        *end = '\0';
        double t = 0.0;
        uint8_t bytes[256];
        int n = -1;
        if (!more || num_real(p, 0.0, 1e6, &t) != NUM_OK) {
            snprintf(err, sizeof err, "expected a time in seconds (0 .. 1000000), then a command");
        } else if ((uint64_t)llround(t / TICK_S) < last) {
            snprintf(err, sizeof err, "the times must not go back");
        } else {
            n = encode(end + 1, bytes, sizeof bytes, err, sizeof err);
        }
        if (n < 0) {
            cfgtext_escape(err, sizeof err); /* it quotes the line's words */
            fprintf(stderr, "host_sim: %s:%u: %s\n", path, lineno, err);
            rc = EXIT_USAGE;
        } else {
            last = (uint64_t)llround(t / TICK_S);
            if (!add(c, last, bytes, (size_t)n)) {
                fprintf(stderr, "host_sim: %s: out of memory\n", path);
                rc = 1;
            }
        }
    }
    fclose(f);
    if (rc != 0) {
        commands_free(c);
    }
    return rc;
}

void commands_feed(commands_t *c, uint64_t tick)
{
    for (; c->next < c->n && c->lines[c->next].tick <= tick; c->next++) {
        const command_line_t *l = &c->lines[c->next];
        size_t taken = hal_host_uart_receive(c->bytes + l->offset, l->len);
        c->dropped += l->len - taken;
    }
}

void commands_free(commands_t *c)
{
    free(c->lines);
    free(c->bytes);
    *c = (commands_t){0};
}
