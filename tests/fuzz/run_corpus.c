/* SPDX-License-Identifier: MIT */
/* Runs a fuzz target once over every file of its corpus folders: make test's regression run. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"
#include "hal_common/config_text.h"

static int run_file(const char *path, unsigned *runs)
{
    size_t n = 0u;
    char err[512];
    char *text = cfgtext_read_file(path, (size_t)1 << 24, &n, err, sizeof err);
    if (text == NULL) {
        fprintf(stderr, "run_corpus: %s\n", err);
        return -1;
    }
    /* An exact copy, so that reading one byte past the input is caught. */
    uint8_t *exact = malloc(n > 0u ? n : 1u);
    if (exact == NULL) {
        free(text);
        return -1;
    }
    memcpy(exact, text, n);
    free(text);
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
