/* SPDX-License-Identifier: MIT */
/* Storage slots as files that are replaced atomically: copy, fsync, rename, fsync the directory. */
#define _POSIX_C_SOURCE 200809L
#include "lhal/store.h"

#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void store_path(const store_t *s, uint8_t slot, const char *ext, char *out, size_t n)
{
    snprintf(out, n, "%s/slot%u.%s", s->dir, (unsigned)slot, ext);
}

static int store_write_all(int fd, const void *data, size_t len, off_t offset)
{
    const uint8_t *p = data;
    while (len > 0u) {
        ssize_t w = pwrite(fd, p, len, offset);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            return -errno;
        }
        p += w;
        len -= (size_t)w;
        offset += w;
    }
    return 0;
}

static int store_fsync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
        return -errno;
    }
    int rc = fsync(fd) == 0 ? 0 : -errno;
    close(fd);
    return rc;
}

/* Makes a written copy durable and puts it in place of dst: fsync, close, rename, fsync
 * the directory. On failure the copy is removed and dst is untouched. Closes fd. */
static int store_replace(int fd, const char *tmp, const char *dst, const char *dir)
{
    int rc = fsync(fd) == 0 ? 0 : -errno;
    if (close(fd) != 0 && rc == 0) {
        rc = -errno;
    }
    if (rc == 0 && rename(tmp, dst) != 0) {
        rc = -errno;
    }
    if (rc != 0) {
        unlink(tmp);
        return rc;
    }
    return store_fsync_dir(dir);
}

int store_open(store_t *s, const char *dir, size_t size, char *err, size_t errlen)
{
    for (unsigned i = 0u; i < HAL_STORAGE_SLOTS; i++) {
        s->tmp_fd[i] = -1;
    }
    s->size = size;
    if (snprintf(s->dir, sizeof s->dir, "%s", dir) >= (int)sizeof s->dir) {
        snprintf(err, errlen, "storage_dir '%s' is too long", dir);
        return -1;
    }
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
        snprintf(err, errlen, "storage_dir '%s': cannot create: %s", dir, strerror(errno));
        return -1;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        snprintf(err, errlen, "storage_dir '%s': not writable: %s", dir, strerror(errno));
        return -1;
    }
    for (uint8_t i = 0u; i < HAL_STORAGE_SLOTS; i++) {
        char path[STORE_DIR_MAX + 32u];
        store_path(s, i, "tmp", path, sizeof path);
        (void)unlink(path); /* a rewrite that never committed */
    }
    return 0;
}

int store_probe(const char *dir, char *note, size_t notelen)
{
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode) || access(dir, W_OK | X_OK) != 0) {
            snprintf(note, notelen, "storage_dir '%s': not a writable directory", dir);
            return -1;
        }
        snprintf(note, notelen, "exists");
        return 0;
    }
    /* The parent must let us create it: everything up to the last '/', or ".". */
    char parent[STORE_DIR_MAX] = ".";
    const char *slash = strrchr(dir, '/');
    if (slash != NULL) {
        size_t n = slash == dir ? 1u : (size_t)(slash - dir); /* "/maps" lives in "/" */
        if (n >= sizeof parent) {
            snprintf(note, notelen, "storage_dir '%s' is too long", dir);
            return -1;
        }
        memcpy(parent, dir, n);
        parent[n] = '\0';
    }
    if (access(parent, W_OK | X_OK) != 0) {
        snprintf(note, notelen, "storage_dir '%s': cannot be created in '%s': %s", dir, parent,
                 strerror(errno));
        return -1;
    }
    snprintf(note, notelen, "will be created");
    return 0;
}

void store_close(store_t *s)
{
    for (uint8_t i = 0u; i < HAL_STORAGE_SLOTS; i++) {
        if (s->tmp_fd[i] >= 0) {
            char path[STORE_DIR_MAX + 32u];
            close(s->tmp_fd[i]);
            s->tmp_fd[i] = -1;
            store_path(s, i, "tmp", path, sizeof path);
            (void)unlink(path);
        }
    }
}

static bool store_range_ok(const store_t *s, uint8_t slot, uint32_t offset, size_t len)
{
    return slot < HAL_STORAGE_SLOTS && offset <= s->size && len <= s->size - offset;
}

int store_begin(store_t *s, uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS) {
        return HAL_EINVAL;
    }
    if (s->tmp_fd[slot] >= 0) {
        close(s->tmp_fd[slot]);
        s->tmp_fd[slot] = -1;
    }
    char path[STORE_DIR_MAX + 32u];
    store_path(s, slot, "tmp", path, sizeof path);
    int fd = open(path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        return HAL_EIO;
    }
    uint8_t erased[4096];
    memset(erased, 0xFF, sizeof erased);
    for (size_t off = 0u; off < s->size; off += sizeof erased) {
        size_t n = s->size - off < sizeof erased ? s->size - off : sizeof erased;
        if (store_write_all(fd, erased, n, (off_t)off) != 0) {
            close(fd);
            unlink(path);
            return HAL_EIO;
        }
    }
    s->tmp_fd[slot] = fd;
    return HAL_OK;
}

int store_write(store_t *s, uint8_t slot, uint32_t offset, const void *data, size_t len)
{
    if (!store_range_ok(s, slot, offset, len) || s->tmp_fd[slot] < 0) {
        return HAL_EINVAL;
    }
    return store_write_all(s->tmp_fd[slot], data, len, (off_t)offset) == 0 ? HAL_OK : HAL_EIO;
}

int store_commit(store_t *s, uint8_t slot)
{
    if (slot >= HAL_STORAGE_SLOTS || s->tmp_fd[slot] < 0) {
        return HAL_EINVAL;
    }
    char tmp[STORE_DIR_MAX + 32u];
    char bin[STORE_DIR_MAX + 32u];
    store_path(s, slot, "tmp", tmp, sizeof tmp);
    store_path(s, slot, "bin", bin, sizeof bin);
    int fd = s->tmp_fd[slot];
    s->tmp_fd[slot] = -1;
    return store_replace(fd, tmp, bin, s->dir) == 0 ? HAL_OK : HAL_EIO;
}

int store_read(const store_t *s, uint8_t slot, uint32_t offset, void *data, size_t len)
{
    if (!store_range_ok(s, slot, offset, len)) {
        return HAL_EINVAL;
    }
    memset(data, 0xFF, len);
    char path[STORE_DIR_MAX + 32u];
    store_path(s, slot, "bin", path, sizeof path);
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return errno == ENOENT ? HAL_OK : HAL_EIO;
    }
    uint8_t *p = data;
    size_t got = 0u;
    while (got < len) {
        ssize_t r = pread(fd, p + got, len - got, (off_t)(offset + got));
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r < 0) {
            close(fd);
            return HAL_EIO;
        }
        if (r == 0) {
            break; /* a shorter file: the rest stays erased */
        }
        got += (size_t)r;
    }
    close(fd);
    return HAL_OK;
}

int store_write_file(const char *dir, const char *name, const void *data, size_t len)
{
    char tmp[STORE_DIR_MAX + 96u];
    char dst[STORE_DIR_MAX + 96u];
    if (snprintf(dst, sizeof dst, "%s/%s", dir, name) >= (int)sizeof dst ||
        snprintf(tmp, sizeof tmp, "%s/%s.tmp", dir, name) >= (int)sizeof tmp) {
        return -ENAMETOOLONG;
    }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        return -errno;
    }
    int rc = store_write_all(fd, data, len, 0);
    if (rc != 0) {
        close(fd);
        unlink(tmp);
        return rc;
    }
    return store_replace(fd, tmp, dst, dir);
}
