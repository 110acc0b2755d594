/* SPDX-License-Identifier: MIT */
/* host_sim --bag: the run's files as a ROS bag, written by tools/rosbag_out.py. */
#define _POSIX_C_SOURCE 200809L
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "viewers.h"

#ifndef SLAM_SOURCE_DIR
#define SLAM_SOURCE_DIR "."
#endif

#define BAG_PYTHON "/usr/bin/python3"
#define BAG_TOOL SLAM_SOURCE_DIR "/tools/rosbag_out.py"

/* Run the tool with these arguments: its exit status, or -1 when it could not run. */
static int bag_tool(char *const argv[])
{
    extern char **environ;
    pid_t pid;
    fflush(stdout); /* the summary first, then what the tool says */
    if (access(BAG_PYTHON, X_OK) != 0 || access(BAG_TOOL, R_OK) != 0 ||
        posix_spawn(&pid, BAG_PYTHON, NULL, NULL, argv, environ) != 0) {
        return -1;
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) {
        return -1;
    }
    return WEXITSTATUS(status);
}

int bag_check(const char *file)
{
    if (check_out_file("--bag", file) != 0) {
        return -1;
    }
    /* Before the run, not after it: a long run must not end in a missing package. The
     * tool says what is missing. */
    char *argv[] = {BAG_PYTHON, BAG_TOOL, "--check", NULL};
    int rc = bag_tool(argv);
    if (rc != 0) {
        fprintf(stderr,
                "host_sim: --bag: %s cannot write bags here%s (tools/install-deps.sh "
                "ros installs python3-rosbag and the ROS message packages)\n",
                BAG_TOOL, rc < 0 ? ": " BAG_PYTHON " cannot run it" : "");
        return -1;
    }
    return 0;
}

int bag_write(const char *dir, const char *file, double cone_deg, double max_m, bool quiet)
{
    char cone[32];
    char max[32];
    snprintf(cone, sizeof cone, "%.6g", cone_deg);
    snprintf(max, sizeof max, "%.6g", max_m);
    char *argv[] = {BAG_PYTHON,    BAG_TOOL, (char *)dir,
                    (char *)file,  "--fov",  cone,
                    "--max-range", max,      quiet ? "--quiet" : NULL,
                    NULL};
    int rc = bag_tool(argv);
    if (rc != 0) {
        fprintf(stderr, "host_sim: --bag: %s failed%s; no bag\n", BAG_TOOL,
                rc < 0 ? " to start" : "");
        return 1;
    }
    return 0;
}
