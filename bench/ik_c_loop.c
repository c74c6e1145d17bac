/*
 * C-loop timing harness for the generated numeric IK (<robot>_ik.c, docs/ik-generated.md).
 *
 * Build against one robot's generated C files, for example the PUMA 560:
 *   gcc -std=c99 -O2 -DROBOT=puma560 -DROBOT_IK_HEADER='"puma560_ik.h"' -I DIR \
 *       ik_c_loop.c DIR/puma560_ik.c DIR/puma560.c -lm
 * The solver and the kernels are in their own translation units (no LTO), as a user links
 * them.
 *
 * Usage: ik_c_loop REPEATS < problems
 *   problems: a line "COUNT DOF", then COUNT lines of 16 + DOF numbers: the target pose
 *             (4x4, row-major) and the seed configuration.
 *   REPEATS:  solves per problem in the timed block (each one identical: the solver is
 *             deterministic); the time per solve is the block's CPU time over REPEATS.
 * Prints one line per problem: "status iterations restarts ns_per_solve q1 ... qDOF", with
 * the robot file's parameters and the default options (<robot>_ik_default_options).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include ROBOT_IK_HEADER

#define JOIN2(a, b) a##b
#define JOIN(a, b) JOIN2(a, b)
#define MAX_DOF 16

typedef JOIN(ROBOT, _ik_options) options_t;
typedef JOIN(ROBOT, _ik_result) result_t;

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: not the other programs' */
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    static const double parameters[] = JOIN(ROBOT_MACRO, _DEFAULT_PARAMETERS);
    options_t options;
    result_t result;
    double target[16], seed[MAX_DOF], q[MAX_DOF];
    long repeats, problem, count, r;
    int dof, i;

    if (argc != 2 || (repeats = atol(argv[1])) < 1) {
        fprintf(stderr, "usage: %s REPEATS < problems\n", argv[0]);
        return 2;
    }
    if (scanf("%ld %d", &count, &dof) != 2 || dof < 1 || dof > MAX_DOF) {
        fprintf(stderr, "expected a first line \"COUNT DOF\" with DOF <= %d\n", MAX_DOF);
        return 2;
    }
    JOIN(ROBOT, _ik_default_options)(&options);
    for (problem = 0; problem < count; ++problem) {
        double start, elapsed;
        for (i = 0; i < 16 + dof; ++i) {
            if (scanf("%lf", i < 16 ? &target[i] : &seed[i - 16]) != 1) {
                fprintf(stderr, "problem %ld: expected %d numbers\n", problem + 1, 16 + dof);
                return 2;
            }
        }
        start = now_ns();
        for (r = 0; r < repeats; ++r) {
            JOIN(ROBOT, _ik)(target, seed, parameters, &options, q, &result);
        }
        elapsed = now_ns() - start;
        printf("%d %d %d %.1f", result.status, result.iterations, result.restarts,
               elapsed / (double)repeats);
        for (i = 0; i < dof; ++i) {
            printf(" %.17g", q[i]);
        }
        printf("\n");
    }
    return 0;
}
