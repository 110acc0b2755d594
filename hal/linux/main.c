/* SPDX-License-Identifier: MIT */
/* The entry point of sonarslam-linux: the program itself is app_main(). */
#include <stdio.h>

#include "lhal/app.h"

int main(int argc, char **argv)
{
    return app_main(argc, argv, stdout, stderr);
}
