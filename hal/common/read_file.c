/* SPDX-License-Identifier: MIT */
/* Reading a whole text file with a size limit: for the parsers of configurations and rooms. */
#define _POSIX_C_SOURCE 200809L /* fileno */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hal_common/config_text.h"

char *cfgtext_read_file(const char *path, size_t limit, size_t *len, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        snprintf(err, errlen, "%s: is a directory", path);
        return NULL;
    }
    size_t cap = 4096u;
    size_t n = 0u;
    char *buf = malloc(cap);
    while (buf != NULL) {
        /* Never more than one byte past the limit: /dev/zero must not fill the memory. */
        size_t want = cap - 1u - n;
        want = want > limit + 1u - n ? limit + 1u - n : want;
        size_t got = fread(buf + n, 1u, want, f);
        n += got;
        if (got < want || n > limit) {
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
        snprintf(err, errlen, "%s: out of memory", path);
        return NULL;
    }
    if (bad) {
        free(buf);
        snprintf(err, errlen, "%s: read error", path);
        return NULL;
    }
    if (n > limit) {
        free(buf);
        snprintf(err, errlen, "%s: larger than %zu bytes, the limit of this kind of file", path,
                 limit);
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}
