/* SPDX-License-Identifier: MIT */
/* Runs a fuzz target once over every file of its corpus folders: make test's regression run. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"

static int run_file(const char *path, unsigned *runs)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "run_corpus: %s: %s\n", path, strerror(errno));
        return -1;
    }
    size_t cap = 4096u;
    size_t n = 0u;
    uint8_t *buf = malloc(cap);
    while (buf != NULL) {
        n += fread(buf + n, 1u, cap - n, f);
        if (n < cap) {
            break;
        }
        uint8_t *grown = realloc(buf, 2u * cap);
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
    if (buf == NULL || bad) {
        fprintf(stderr, "run_corpus: %s: cannot read\n", path);
        free(buf);
        return -1;
    }
    /* An exact copy, so that reading one byte past the input is caught. */
    uint8_t *exact = malloc(n > 0u ? n : 1u);
    if (exact == NULL) {
        free(buf);
        return -1;
    }
    memcpy(exact, buf, n);
    free(buf);
    (void)LLVMFuzzerTestOneInput(exact, n);
    free(exact);
    (*runs)++;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s CORPUS_DIR_OR_FILE...\n", argv[0]);
        return 2;
    }
    unsigned runs = 0;
    for (int i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "run_corpus: %s: %s\n", argv[i], strerror(errno));
            return 2;
        }
        if (!S_ISDIR(st.st_mode)) {
            if (run_file(argv[i], &runs) != 0) {
                return 1;
            }
            continue;
        }
        DIR *d = opendir(argv[i]);
        if (d == NULL) {
            fprintf(stderr, "run_corpus: %s: %s\n", argv[i], strerror(errno));
            return 2;
        }
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            if (e->d_name[0] == '.') {
                continue;
            }
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            if (run_file(path, &runs) != 0) {
                closedir(d);
                return 1;
            }
        }
        closedir(d);
    }
    if (runs == 0u) {
        fprintf(stderr, "run_corpus: no inputs in %s\n", argv[1]);
        return 1;
    }
    printf("%u inputs ran\n", runs);
    return 0;
}
