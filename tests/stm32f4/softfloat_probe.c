/* SPDX-License-Identifier: MIT */
/* A program the image check must refuse: it multiplies doubles and uses the heap. */
#include <stdlib.h>

volatile double probe_value = 3.0;

int main(void)
{
    double scaled = probe_value * 1.5;
    char *block = malloc(16);
    return (int)scaled + (block != NULL);
}
