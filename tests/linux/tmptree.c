/* SPDX-License-Identifier: MIT */
/* Temporary directory trees for the Linux backend's tests. */
#define _XOPEN_SOURCE 700 /* mkdtemp, nftw */
#include "tmptree.h"

#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "slam/grid.h"

static void tmptree_die(const char *what, const char *path)
{
    fprintf(stderr, "tmptree: %s %s failed\n", what, path);
    abort();
}

void tmptree_make(char root[TMPTREE_PATH_MAX], const char *tag)
{
    snprintf(root, TMPTREE_PATH_MAX, "/tmp/slam-lx-%s-XXXXXX", tag);
    if (mkdtemp(root) == NULL) {
        tmptree_die("mkdtemp", root);
    }
}

static void tmptree_path(char *out, size_t n, const char *root, const char *rel)
{
    if (snprintf(out, n, "%s/%s", root, rel) >= (int)n) {
        tmptree_die("path", rel);
    }
}

void tmptree_file(const char *root, const char *rel, const char *content)
{
    char path[512];
    tmptree_path(path, sizeof path, root, rel);
    for (char *p = path + strlen(root) + 1u; (p = strchr(p, '/')) != NULL; p++) {
        *p = '\0';
        if (mkdir(path, 0755) != 0 && access(path, F_OK) != 0) {
            tmptree_die("mkdir", path);
        }
        *p = '/';
    }
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        tmptree_die("fopen", path);
    }
    fputs(content, f);
    fclose(f);
}

void tmptree_pwm_channel(const char *root, unsigned chip, unsigned channel)
{
    static const char *const attrs[] = {"period", "duty_cycle", "enable"};
    for (size_t i = 0; i < 3u; i++) {
        char rel[64];
        snprintf(rel, sizeof rel, "pwmchip%u/pwm%u/%s", chip, channel, attrs[i]);
        tmptree_file(root, rel, "");
    }
}

const char *tmptree_read(const char *root, const char *rel)
{
    static char buf[SLAM_GRID_CELLS + 65536u]; /* a PGM of the largest grid, and more */
    char path[512];
    tmptree_path(path, sizeof path, root, rel);
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        return "<missing>";
    }
    size_t n = fread(buf, 1u, sizeof buf - 1u, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

bool tmptree_exists(const char *root, const char *rel)
{
    char path[512];
    tmptree_path(path, sizeof path, root, rel);
    return access(path, F_OK) == 0;
}

void tmptree_unlink(const char *root, const char *rel)
{
    char path[512];
    tmptree_path(path, sizeof path, root, rel);
    if (unlink(path) != 0) {
        tmptree_die("unlink", path);
    }
}

static int tmptree_rm(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st;
    (void)flag;
    (void)ftw;
    return remove(path);
}

void tmptree_remove(const char *root)
{
    if (strncmp(root, "/tmp/slam-lx-", 13u) == 0) { /* never anything else */
        nftw(root, tmptree_rm, 16, FTW_DEPTH | FTW_PHYS);
    }
}
