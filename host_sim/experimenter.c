/* SPDX-License-Identifier: MIT */
/* The simulated experimenter of UMBmark: measures each run's return error with a tape
 * (the true pose, ±5 mm) while the robot pauses, and carries the robot back to the start. */
#include <math.h>
#include <string.h>

#include "host_sim.h"

/* The tape: each coordinate of the true position read to within ±5 mm, uniformly. */
#define TAPE_MM 5.0

/* splitmix64: the tape's own random stream, so the firmware's and the world's draws are
 * the same with and without the experimenter. */
static uint64_t next_u64(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double tape_noise_mm(uint64_t *s)
{
    return ((double)(next_u64(s) >> 11) * 0x1.0p-53 * 2.0 - 1.0) * TAPE_MM;
}

void experimenter_init(experimenter_t *x, const char *dir, uint64_t seed, double start_x,
                       double start_y, double start_th, bool quiet)
{
    memset(x, 0, sizeof *x);
    x->dir = dir;
    x->rng = seed ^ 0x7A9E5EEDull;
    x->start_x = start_x;
    x->start_y = start_y;
    x->start_th = start_th;
    x->quiet = quiet;
}

/* The file of the measurements, begun at the first one. */
static FILE *csv(experimenter_t *x)
{
    if (x->csv == NULL && !x->failed) {
        x->csv = open_out(x->dir, EXPERIMENTER_CSV);
        x->failed = x->csv == NULL;
        if (x->csv != NULL) {
            fprintf(x->csv,
                    "# UMBmark return errors measured by host_sim's experimenter with a tape of\n"
                    "# +-%.0f mm: the true final position minus odometry's, in the start pose's\n"
                    "# frame (x ahead along the start heading, y to its left), mm.\n"
                    "direction,x_mm,y_mm\n",
                    TAPE_MM);
        }
    }
    return x->csv;
}

int experimenter_tick(experimenter_t *x, sim_t *sim, const robot_t *rb)
{
    const umbmark_t *u = &rb->umbmark;
    if (!u->on) {
        return 0;
    }
    sim_truth_t tr = sim_truth(sim);
    if (tr.collisions != 0u) {
        fprintf(stderr,
                "host_sim: UMBmark run %u ran into something: the square of %.2f m "
                "does not fit here (a smaller square_side_um, or another --start)\n",
                (unsigned)u->run, u->side_um * 1e-6);
        return -1;
    }
    /* A run is over, and the robot stands: measure where it stopped, then put it back. */
    if (u->state != UMB_PAUSE || u->run <= x->measured) {
        return 0;
    }
    odom_pose_t od = odom_pose(&rb->odom);
    double c = cos(x->start_th), s = sin(x->start_th);
    double wx = (tr.x - od.x_um * 1e-6) * 1e3 + tape_noise_mm(&x->rng);
    double wy = (tr.y - od.y_um * 1e-6) * 1e3 + tape_noise_mm(&x->rng);
    double ex = c * wx + s * wy;
    double ey = -s * wx + c * wy;
    bool cw = umbmark_run_cw(u, u->run);
    FILE *f = csv(x);
    if (f == NULL) {
        return -1;
    }
    fprintf(f, "%s,%.1f,%.1f\n", cw ? "cw" : "ccw", ex, ey);
    if (!x->quiet) {
        fprintf(stderr, "  UMBmark run %2u/%u %-3s: return error x %7.1f mm, y %7.1f mm\n",
                (unsigned)u->run, 2u * u->runs, cw ? "cw" : "ccw", ex, ey);
    }
    x->measured = u->run;
    if (sim_place(sim, x->start_x, x->start_y, x->start_th) != 0) {
        fprintf(stderr, "host_sim: cannot put the robot back at the start pose\n");
        return -1;
    }
    return x->measured >= 2u * u->runs ? 2 : 1;
}

int experimenter_close(experimenter_t *x)
{
    int rc = x->csv != NULL ? close_out(x->csv, x->dir, EXPERIMENTER_CSV) : 0;
    x->csv = NULL;
    return x->failed ? -1 : rc;
}
