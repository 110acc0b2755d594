/* SPDX-License-Identifier: MIT */
/* Opening input files (regular files only) and reading one whole with a size limit: for the
 * parsers of configurations, rooms and logs. */
#define _POSIX_C_SOURCE 200809L /* O_CLOEXEC, fdopen */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hal_common/config_text.h"

FILE *cfgtext_open_file(const char *path, char *err, size_t errlen)
{
    /* Non-blocking: opening a FIFO that no program writes would otherwise wait for ever. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        cfgtext_escape(err, errlen);
        return NULL;
    }
    struct stat st;
    const char *why = NULL;
    if (fstat(fd, &st) != 0) {
        why = strerror(errno);
    } else if (S_ISDIR(st.st_mode)) {
        why = "is a directory";
    } else if (!S_ISREG(st.st_mode)) {
        why = "is not a regular file (a FIFO, a device or a socket): give a file";
    }
    int flags = why == NULL ? fcntl(fd, F_GETFL) : -1;
    FILE *f = NULL;
    if (why == NULL && (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0 ||
                        (f = fdopen(fd, "rb")) == NULL)) {
        why = strerror(errno);
    }
    if (f == NULL) {
        close(fd);
        snprintf(err, errlen, "%s: %s", path, why);
        cfgtext_escape(err, errlen);
    }
    return f;
}

char *cfgtext_read_file(const char *path, size_t limit, size_t *len, char *err, size_t errlen)
{
    FILE *f = cfgtext_open_file(path, err, errlen);
    if (f == NULL) {
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
