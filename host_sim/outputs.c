/* SPDX-License-Identifier: MIT */
/* Output files of a run: directories, PGM maps with their ROS YAML, checked writes. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hal_common/mapexport.h"
#include "host_sim.h"

/* "00" "01" ... "99": the digits of a number two at a time. */
static const char digit_pairs[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* The @p n lowest decimal digits of w, leading zeros included, written to end - n .. end:
 * in 32 bits, where a division by a constant costs half the 64-bit one. */
static inline void put_digits(char *end, uint32_t w, int n)
{
    for (; n >= 2; n -= 2) {
        uint32_t pair = w % 100u;
        w /= 100u;
        end -= 2;
        memcpy(end, &digit_pairs[2u * pair], 2u);
    }
    if (n == 1) {
        end[-1] = (char)('0' + w % 10u);
    }
}

/* The same for a 64-bit v, nine digits at a time. */
static void put_digits_u64(char *end, uint64_t v, int n)
{
    for (; n > 9; n -= 9) {
        put_digits(end, (uint32_t)(v % 1000000000u), 9);
        v /= 1000000000u;
        end -= 9;
    }
    put_digits(end, (uint32_t)v, n);
}

char *fmt_fixed(char *out, double v, int decimals, char sep)
{
    static const double scale[11] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10};
    static const uint64_t unit[11] = {1u,         10u,         100u,        1000u,
                                      10000u,     100000u,     1000000u,    10000000u,
                                      100000000u, 1000000000u, 10000000000u};
    double s = v * scale[decimals];
    long long n = (long long)(s < 0 ? s - 0.5 : s + 0.5);
    if (n < 0) {
        *out++ = '-';
        n = -n;
    } else if (n == 0 && v < 0) {
        *out++ = '-'; /* printf keeps the sign of a negative that rounds to zero */
    }
    /* The whole part, then every decimal, each written straight in place. */
    uint64_t whole = (uint64_t)n / unit[decimals];
    uint64_t frac = (uint64_t)n - whole * unit[decimals];
    int digits = 1;
    for (uint64_t w = whole; w >= 10u; w /= 10u) {
        digits++;
    }
    if (whole <= UINT32_MAX) {
        put_digits(out + digits, (uint32_t)whole, digits);
    } else {
        put_digits_u64(out + digits, whole, digits);
    }
    out += digits;
    if (decimals > 0) {
        *out++ = '.';
        if (decimals <= 9) {
            put_digits(out + decimals, (uint32_t)frac, decimals);
        } else {
            put_digits_u64(out + decimals, frac, decimals);
        }
        out += decimals;
    }
    if (sep != 0) {
        *out++ = sep;
    }
    return out;
}

const char *reading_status(const sonar_t *s, bool echo, uint32_t range_um)
{
    if (!echo) {
        return "timeout";
    }
    if (range_um >= s->confidence_um) {
        return "far";
    }
    return range_um < s->range_min_um ? "near" : "ok";
}

/* The folders make_dirs() created, removed again when a run fails. */
#define DIRS_MAX 16
static char dirs[DIRS_MAX][4096];
static size_t ndirs;

int make_dirs(const char *path)
{
    char buf[4096];
    if (strlen(path) >= sizeof buf) {
        fprintf(stderr, "host_sim: output path too long: %s\n", path);
        return -1;
    }
    strcpy(buf, path);
    for (char *p = buf + 1;; p++) {
        if (*p == '/' || *p == '\0') {
            char c = *p;
            *p = '\0';
            if (mkdir(buf, 0777) == 0) {
                if (ndirs < DIRS_MAX) {
                    snprintf(dirs[ndirs++], sizeof dirs[0], "%s", buf);
                }
            } else if (errno != EEXIST) {
                fprintf(stderr, "host_sim: cannot create %s: %s\n", buf, strerror(errno));
                return -1;
            }
            *p = c;
            if (c == '\0') {
                break;
            }
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "host_sim: %s is not a directory\n", path);
        return -1;
    }
    return 0;
}

/* ---- checks before anything is written -------------------------------------------------- */

/* The directory part of a path ("." for a bare name). */
static void dir_of(const char *path, char *out, size_t n)
{
    const char *slash = strrchr(path, '/');
    if (slash == NULL) {
        snprintf(out, n, ".");
    } else if (slash == path) {
        snprintf(out, n, "/");
    } else {
        snprintf(out, n, "%.*s", (int)(slash - path), path);
    }
}

static int bad_output(const char *what, const char *path, const char *why, const char *more)
{
    fprintf(stderr, "host_sim: %s %s: %s%s\n", what, path, why, more != NULL ? more : "");
    return -1;
}

/* A directory we may create files in. */
static int writable_dir(const char *what, const char *path, const char *dir)
{
    struct stat st;
    if (stat(dir, &st) != 0) {
        fprintf(stderr, "host_sim: %s %s: %s: %s\n", what, path, dir, strerror(errno));
        return -1;
    }
    if (!S_ISDIR(st.st_mode)) {
        fprintf(stderr, "host_sim: %s %s: %s is not a directory\n", what, path, dir);
        return -1;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        fprintf(stderr, "host_sim: %s %s: cannot create files in %s: %s\n", what, path, dir,
                strerror(errno));
        return -1;
    }
    /* access() answers yes to root in /proc and /sys, where nothing can be created: a
     * folder made and removed at once is the only test that holds everywhere. */
    char probe[4096 + 64];
    snprintf(probe, sizeof probe, "%s/.host_sim-probe-%ld", dir, (long)getpid());
    if (mkdir(probe, 0700) != 0) {
        fprintf(stderr, "host_sim: %s %s: cannot create files in %s: %s\n", what, path, dir,
                strerror(errno));
        return -1;
    }
    (void)rmdir(probe);
    return 0;
}

int check_out_dir(const char *what, const char *dir, const char *const *names)
{
    char buf[4096];
    if (dir[0] == '\0' || strlen(dir) >= sizeof buf - 256u) {
        return bad_output(what, dir, "not a usable folder name", NULL);
    }
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode)) {
            return bad_output(what, dir, "exists and is not a directory", NULL);
        }
        if (writable_dir(what, dir, dir) != 0) {
            return -1;
        }
        for (size_t i = 0; names != NULL && names[i] != NULL; i++) {
            snprintf(buf, sizeof buf, "%s/%s", dir, names[i]);
            if (stat(buf, &st) == 0 && !S_ISREG(st.st_mode)) {
                return bad_output(what, dir, names[i], " is there and is not a regular file");
            }
        }
        return 0;
    }
    if (errno != ENOENT && errno != ENOTDIR) {
        return bad_output(what, dir, strerror(errno), NULL);
    }
    /* It will be created: the nearest existing folder above it must take new folders. */
    snprintf(buf, sizeof buf, "%s", dir);
    for (;;) {
        char parent[4096];
        dir_of(buf, parent, sizeof parent);
        if (stat(parent, &st) == 0 || (errno != ENOENT && errno != ENOTDIR) ||
            strcmp(parent, buf) == 0) {
            return writable_dir(what, dir, parent);
        }
        snprintf(buf, sizeof buf, "%s", parent);
    }
}

int check_out_file(const char *what, const char *path)
{
    struct stat st;
    if (path[0] == '\0') {
        return bad_output(what, "''", "an empty file name", NULL);
    }
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            return bad_output(what, path, "is a directory", NULL);
        }
        if (access(path, W_OK) != 0) {
            return bad_output(what, path, strerror(errno), NULL);
        }
        if (!S_ISREG(st.st_mode)) {
            return 0; /* a device or a pipe is written in place */
        }
    } else if (errno != ENOENT && errno != ENOTDIR) {
        return bad_output(what, path, strerror(errno), NULL);
    }
    char dir[4096];
    dir_of(path, dir, sizeof dir);
    return writable_dir(what, path, dir);
}

/* ---- the outputs of a run ---------------------------------------------------------------- */

/* The files a run writes into --out. */
static const char *const out_names[] = {
    "config.txt",
    "readings.csv",
    "trajectory.csv",
    "metrics.json",
    "timing.json",
    "om.pgm",
    "om.yaml",
    "om_post.pgm",
    "om_post.yaml",
    "om_ideal.pgm",
    "om_ideal.yaml",
    "tm.pgm",
    "truth.pgm",
    "truth.yaml",
    "figure.png",
    "scoring_truth.pgm",
    "scoring_observable.pgm",
    "scoring_estimate.csv",
    EXPERIMENTER_CSV,
    NULL,
};

/* A path with its folder resolved, to tell whether two options name the same file. */
static void resolved(const char *path, char *out, size_t n)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    snprintf(dir, sizeof dir, "%.*s", slash == NULL ? 1 : (int)(slash - path),
             slash == NULL ? "." : (slash == path ? "/" : path));
    char *real = realpath(dir, NULL);
    if (real != NULL) {
        snprintf(out, n, "%s/%s", real, slash != NULL ? slash + 1 : path);
        free(real);
    } else {
        snprintf(out, n, "%s", path);
    }
}

/* --storage DIR must hold no slot yet: the simulated robot starts with blank storage, and
 * its saves would replace the maps of an earlier run or a real robot's (a run that began
 * from another run's storage would also no longer follow from its options alone). */
static int check_storage(const char *dir)
{
    static const char *const slots[] = {"slot0.bin", "slot1.bin", NULL};
    if (check_out_dir("--storage", dir, slots) != 0) {
        return -1;
    }
    char found[2][4200];
    size_t n = 0u;
    for (size_t i = 0; slots[i] != NULL; i++) {
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", dir, slots[i]);
        struct stat st;
        if (lstat(path, &st) == 0) {
            snprintf(found[n++], sizeof found[0], "%s", path);
        }
    }
    if (n > 0u) {
        fprintf(stderr,
                "host_sim: --storage %s holds map slots already (%s%s%s): a run would replace "
                "them. Move them away (plot_run.py draws them), or give an empty folder\n",
                dir, found[0], n > 1u ? ", " : "", n > 1u ? found[1] : "");
        return -1;
    }
    return 0;
}

int check_outputs(const options_t *o)
{
    if (check_out_dir("--out", o->out, out_names) != 0 ||
        (o->storage != NULL && check_storage(o->storage) != 0) ||
        (o->trace != NULL && check_out_file("--trace", o->trace) != 0) ||
        (o->telemetry != NULL && check_out_file("--telemetry", o->telemetry) != 0)) {
        return -1;
    }
    char a[8192];
    char b[8192];
    const char *files[2] = {o->trace, o->telemetry};
    const char *opts[2] = {"--trace", "--telemetry"};
    for (int i = 0; i < 2; i++) {
        if (files[i] == NULL) {
            continue;
        }
        resolved(files[i], a, sizeof a);
        if (i == 0 && files[1] != NULL) {
            resolved(files[1], b, sizeof b);
            if (strcmp(a, b) == 0) {
                fprintf(stderr, "host_sim: --trace and --telemetry name the same file %s\n", a);
                return -1;
            }
        }
        for (size_t k = 0; out_names[k] != NULL; k++) {
            char p[4400];
            snprintf(p, sizeof p, "%s/%s", o->out, out_names[k]);
            resolved(p, b, sizeof b);
            if (strcmp(a, b) == 0) {
                fprintf(stderr, "host_sim: %s %s is a file the run writes into --out\n", opts[i],
                        files[i]);
                return -1;
            }
        }
    }
    return 0;
}

/* ---- what an earlier run left ------------------------------------------------------------- */

/* The pid of a temporary file open_out() named ".NAME.tmpPID" for @p name; 0 if it is not one. */
static long temp_pid(const char *entry, const char *name)
{
    size_t n = strlen(name);
    if (entry[0] != '.' || strncmp(entry + 1, name, n) != 0 ||
        strncmp(entry + 1 + n, ".tmp", 4) != 0) {
        return 0;
    }
    const char *digits = entry + 1 + n + 4;
    long pid = 0;
    for (const char *p = digits; *p != '\0'; p++) {
        if (*p < '0' || *p > '9' || pid > 99999999) {
            return 0;
        }
        pid = pid * 10 + (*p - '0');
    }
    return digits[0] != '\0' ? pid : 0;
}

/* Removes from @p dir the temporary files of @p names whose run is gone (killed at once, a
 * power cut): they are never anyone's result, and they pile up. A live run's are left. */
static void sweep_dir(const char *dir, const char *const *names)
{
    DIR *d = opendir(dir);
    if (d == NULL) {
        return;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        for (size_t i = 0; names[i] != NULL; i++) {
            long pid = temp_pid(e->d_name, names[i]);
            if (pid > 0 && pid != (long)getpid() && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
                char path[8192];
                snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
                (void)unlink(path);
            }
        }
    }
    closedir(d);
}

void outputs_sweep(const options_t *o)
{
    static const char *const slots[] = {"slot0.bin", "slot1.bin", NULL};
    sweep_dir(o->out, out_names);
    if (o->storage != NULL) {
        sweep_dir(o->storage, slots);
    }
    if (o->trace != NULL) {
        char dir[4096];
        dir_of(o->trace, dir, sizeof dir);
        const char *slash = strrchr(o->trace, '/');
        const char *const one[] = {slash != NULL ? slash + 1 : o->trace, NULL};
        sweep_dir(dir, one);
    }
}

/* ---- files written whole or not at all ---------------------------------------------------- */

#define OUT_MAX 32

/* Files opened for writing: their temporary and their final names. */
static struct {
    char tmp[4096]; /* "" when written in place */
    char final[4096];
} outs[OUT_MAX];
static size_t nouts;

static void join(char *out, size_t n, const char *dir, const char *name)
{
    if (dir != NULL) {
        snprintf(out, n, "%s/%s", dir, name);
    } else {
        snprintf(out, n, "%s", name);
    }
}

FILE *open_out(const char *dir, const char *name)
{
    if (nouts == OUT_MAX) {
        fprintf(stderr, "host_sim: more than %d output files\n", OUT_MAX);
        return NULL;
    }
    char *final = outs[nouts].final;
    char *tmp = outs[nouts].tmp;
    join(final, sizeof outs[0].final, dir, name);
    struct stat st;
    tmp[0] = '\0';
    if (stat(final, &st) != 0 || S_ISREG(st.st_mode)) {
        char d[4096];
        dir_of(final, d, sizeof d);
        const char *slash = strrchr(final, '/');
        snprintf(tmp, sizeof outs[0].tmp, "%.3800s/.%.200s.tmp%ld", d,
                 slash != NULL ? slash + 1 : final, (long)getpid());
    }
    FILE *f = tmp[0] != '\0' ? fopen(tmp, "wb") : open_stream(final);
    if (f == NULL) {
        if (tmp[0] != '\0') {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", final, strerror(errno));
        }
        return NULL;
    }
    nouts++;
    return f;
}

FILE *open_stream(const char *path)
{
    /* Non-blocking, so that a FIFO without a reader fails at once (ENXIO) rather than
     * waiting for ever; then blocking again, so that a slow reader only slows the run. */
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd < 0) {
        if (errno == ENXIO) {
            fprintf(stderr,
                    "host_sim: cannot write %s: a FIFO that no program is reading: start "
                    "its reader first\n",
                    path);
        } else {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", path, strerror(errno));
        }
        return NULL;
    }
    int flags = fcntl(fd, F_GETFL);
    FILE *f = flags >= 0 && fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0 ? fdopen(fd, "wb") : NULL;
    if (f == NULL) {
        fprintf(stderr, "host_sim: cannot write %s: %s\n", path, strerror(errno));
        close(fd);
    }
    return f;
}

int close_out(FILE *f, const char *dir, const char *name)
{
    int bad = ferror(f);
    int err = errno;
    if (fclose(f) != 0 || bad) {
        char path[4096];
        join(path, sizeof path, dir, name);
        fprintf(stderr, "host_sim: writing %s failed: %s\n", path, strerror(bad ? err : errno));
        return -1;
    }
    return 0;
}

int outputs_commit(void)
{
    int rc = 0;
    for (size_t i = 0; i < nouts; i++) {
        if (outs[i].tmp[0] != '\0' && rename(outs[i].tmp, outs[i].final) != 0) {
            fprintf(stderr, "host_sim: cannot write %s: %s\n", outs[i].final, strerror(errno));
            (void)unlink(outs[i].tmp);
            rc = -1;
        }
    }
    nouts = 0;
    ndirs = 0;
    return rc;
}

void outputs_discard(void)
{
    for (size_t i = 0; i < nouts; i++) {
        if (outs[i].tmp[0] != '\0') {
            (void)unlink(outs[i].tmp);
        }
    }
    nouts = 0;
    while (ndirs > 0) {
        (void)rmdir(dirs[--ndirs]); /* only what this run created, and only if empty */
    }
}

int write_map(const char *dir, const char *name, const map_geom_t *g, const uint8_t *img, bool yaml)
{
    char file[256];
    snprintf(file, sizeof file, "%s.pgm", name);
    FILE *f = open_out(dir, file);
    if (f == NULL) {
        return -1;
    }
    fprintf(f, "P5\n%lu %lu\n255\n", (unsigned long)g->a, (unsigned long)g->b);
    fwrite(img, 1, (size_t)g->a * g->b, f);
    if (close_out(f, dir, file) != 0) {
        return -1;
    }
    if (!yaml) {
        return 0;
    }
    char text[512];
    if (mapx_yaml(text, sizeof text, file, g->cell_um, g->origin_x_um, g->origin_y_um) < 0) {
        fprintf(stderr, "host_sim: %s/%s.yaml: the map's name is too long\n", dir, name);
        return -1;
    }
    snprintf(file, sizeof file, "%s.yaml", name);
    f = open_out(dir, file);
    if (f == NULL) {
        return -1;
    }
    fputs(text, f);
    return close_out(f, dir, file);
}

int write_storage(const char *dir)
{
    if (make_dirs(dir) != 0) {
        return -1;
    }
    int bad = 0;
    for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
        char name[32];
        snprintf(name, sizeof name, "slot%u.bin", (unsigned)slot);
        FILE *f = open_out(dir, name);
        if (f == NULL) {
            return -1;
        }
        fwrite(hal_host_storage_slot(slot), 1u, hal_storage_size(), f);
        bad |= close_out(f, dir, name);
    }
    return bad;
}
