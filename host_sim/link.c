/* SPDX-License-Identifier: MIT */
/* host_sim --link: the simulated robot's UART live on a pseudo-terminal, both ways. */
#define _GNU_SOURCE /* posix_openpt, ptsname_r, fopencookie */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include "host/sim.h"
#include "viewers.h"

/* Ctrl-C or SIGTERM during a linked run: the run ends at the next tick, its outputs
 * written, as at the end of --duration; a second one ends the program at once. */
static volatile sig_atomic_t link_interrupted;

static void link_interrupt(int sig)
{
    (void)sig;
    link_interrupted = 1;
}

int link_check(const char *path)
{
    struct stat st;
    if (lstat(path, &st) == 0 && !S_ISLNK(st.st_mode)) {
        fprintf(stderr,
                "host_sim: --link %s: it exists and is not a symbolic link; give a "
                "new path (host_sim makes the link and removes it at the end)\n",
                path);
        return -1;
    }
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash == dir) {
        slash[1] = '\0';
    } else if (slash != NULL) {
        *slash = '\0';
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    if (access(dir, W_OK | X_OK) != 0) {
        fprintf(stderr, "host_sim: --link %s: cannot make a link in %s: %s\n", path, dir,
                strerror(errno));
        return -1;
    }
    return 0;
}

/* The UART's bytes: to --telemetry whole, to the terminal as far as it takes them. A UART
 * never waits for its reader, so neither does this; it always reports every byte taken. */
static ssize_t link_write(void *cookie, const char *data, size_t len)
{
    link_t *l = cookie;
    if (l->tee != NULL) {
        (void)fwrite(data, 1u, len, l->tee);
    }
    size_t done = 0;
    while (done < len) {
        ssize_t w = write(l->fd, data + done, len - done);
        if (w > 0) {
            done += (size_t)w;
        } else if (w < 0 && errno == EINTR) {
            continue;
        } else {
            break; /* full, or no one there */
        }
    }
    l->sent += done;
    l->dropped += len - done;
    return (ssize_t)len;
}

static int link_fail(link_t *l, const char *what)
{
    fprintf(stderr, "host_sim: --link %s: %s: %s\n", l->path, what, strerror(errno));
    link_close(l);
    return -1;
}

int link_open(link_t *l, const char *path, bool quiet)
{
    *l = (link_t){.fd = -1, .peer = -1, .path = path};
    l->fd = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (l->fd < 0) {
        return link_fail(l, "cannot open a pseudo-terminal");
    }
    if (grantpt(l->fd) != 0 || unlockpt(l->fd) != 0 ||
        ptsname_r(l->fd, l->device, sizeof l->device) != 0) {
        return link_fail(l, "cannot set up the pseudo-terminal");
    }
    /* Raw bytes: the frames are binary. Holding this end open keeps the terminal there
     * between viewers. */
    struct termios t;
    l->peer = open(l->device, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (l->peer < 0 || tcgetattr(l->peer, &t) != 0) {
        return link_fail(l, "cannot open the pseudo-terminal's other end");
    }
    cfmakeraw(&t);
    if (tcsetattr(l->peer, TCSANOW, &t) != 0) {
        return link_fail(l, "cannot make the pseudo-terminal raw");
    }
    (void)unlink(path); /* a link an earlier run left (link_check() allowed only that) */
    if (symlink(l->device, path) != 0) {
        return link_fail(l, "cannot make the link");
    }
    struct sigaction sa = {.sa_handler = link_interrupt, .sa_flags = (int)SA_RESETHAND};
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    if (!quiet) {
        fprintf(stderr,
                "host_sim: the robot's UART is %s (linked from %s): watch it with "
                "tools/telemetry.py serve %s; Ctrl-C ends the run\n",
                l->device, path, path);
    }
    return 0;
}

int link_start(link_t *l, FILE *tee)
{
    l->tee = tee;
    l->sink = fopencookie(l, "w", (cookie_io_functions_t){.write = link_write});
    if (l->sink == NULL) {
        return link_fail(l, "cannot make the UART's stream");
    }
    setvbuf(l->sink, NULL, _IONBF, 0); /* each write out at once, as the UART sends it */
    hal_host_uart_sink(l->sink);
    return 0;
}

bool link_poll(link_t *l)
{
    if (l->path == NULL || l->fd < 0) {
        return true;
    }
    uint8_t buf[256];
    ssize_t n = read(l->fd, buf, sizeof buf);
    if (n > 0) {
        size_t taken = hal_host_uart_receive(buf, (size_t)n);
        l->lost += (size_t)n - taken;
    }
    return link_interrupted == 0;
}

void link_close(link_t *l)
{
    if (l->path == NULL) {
        return; /* never opened (a zeroed link_t), or closed already */
    }
    if (l->sink != NULL) {
        hal_host_uart_sink(l->tee); /* the run's end still reaches --telemetry */
        fclose(l->sink);
        l->sink = NULL;
        if (l->lost != 0u) {
            fprintf(stderr,
                    "host_sim: --link: %llu command bytes found the UART full and "
                    "were lost\n",
                    (unsigned long long)l->lost);
        }
    }
    if (l->peer >= 0) {
        close(l->peer);
        l->peer = -1;
    }
    if (l->fd >= 0) {
        close(l->fd);
        l->fd = -1;
        (void)unlink(l->path);
    }
    l->path = NULL;
}
