/*
 * C-loop timing harness for the generated closed-form IK (<robot>_ik_closed.c,
 * docs/ik-generated.md).
 *
 * Build against one robot's generated C files, for example the PUMA 560:
 *   gcc -std=c99 -O2 -DROBOT=puma560 -DROBOT_MACRO=PUMA560 \
 *       -DROBOT_IK_CLOSED_HEADER='"puma560_ik_closed.h"' -I DIR \
 *       ik_closed_loop.c DIR/puma560_ik_closed.c DIR/puma560.c -lm
 * The solver and the kernels are in their own translation units (no LTO), as a user links
 * them.
 *
 * Usage: ik_closed_loop REPEATS < problems
 *   problems: a line "COUNT DOF", then COUNT lines of 16 numbers: the target pose (4x4,
 *             row-major).
 *   REPEATS:  solves per problem in the timed block (each one identical); the time per solve
 *             is the block's CPU time over REPEATS.
 * Prints one line per problem: "count ns_per_solve" and then, solution by solution,
 * "branch within_limits q1 ... qDOF", with the robot file's parameters.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include ROBOT_IK_CLOSED_HEADER

#define JOIN2(a, b) a##b
#define JOIN(a, b) JOIN2(a, b)
#define MAX_SOLUTIONS JOIN(ROBOT_MACRO, _IK_CLOSED_MAX_SOLUTIONS)
#define DOF JOIN(ROBOT_MACRO, _DOF)

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: not the other programs' */
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    static const double parameters[] = JOIN(ROBOT_MACRO, _DEFAULT_PARAMETERS);
    double target[16], q[MAX_SOLUTIONS * DOF];
    int branch[MAX_SOLUTIONS], within_limits[MAX_SOLUTIONS];
    long repeats, problem, count, r;
    int dof, solutions = 0, i, k;

    if (argc != 2 || (repeats = atol(argv[1])) < 1) {
        fprintf(stderr, "usage: %s REPEATS < problems\n", argv[0]);
        return 2;
    }
    if (scanf("%ld %d", &count, &dof) != 2 || dof != DOF) {
        fprintf(stderr, "expected a first line \"COUNT DOF\" with DOF = %d\n", DOF);
        return 2;
    }
    for (problem = 0; problem < count; ++problem) {
        double start, elapsed;
        for (i = 0; i < 16; ++i) {
            if (scanf("%lf", &target[i]) != 1) {
                fprintf(stderr, "problem %ld: expected 16 numbers\n", problem + 1);
                return 2;
            }
        }
        start = now_ns();
        for (r = 0; r < repeats; ++r) {
            solutions = JOIN(ROBOT, _ik_closed)(target, parameters, q, branch, within_limits);
        }
        elapsed = now_ns() - start;
        printf("%d %.1f", solutions, elapsed / (double)repeats);
        for (k = 0; k < solutions; ++k) {
            printf(" %d %d", branch[k], within_limits[k]);
            for (i = 0; i < DOF; ++i) {
                printf(" %.17g", q[k * DOF + i]);
            }
        }
        printf("\n");
    }
    return 0;
}
