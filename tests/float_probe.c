/* SPDX-License-Identifier: MIT */
/* Must NOT compile with the core's flags: proves that floating point in firmware/ fails
 * the build (test core_rejects_float). */
int float_probe(int a);

int float_probe(int a)
{
    double half = a * 0.5;
    return (int)half;
}
