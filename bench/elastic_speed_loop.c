/*
 * C-loop timing harness for bench/elastic_speed.py: one robot's generated rigid inverse
 * dynamics ROBOT_inverse_dynamics(q, dq, ddq, [p,] tau) and elastic-joint inverse dynamics
 * ROBOT_elastic_inverse_dynamics(q, dq, ddq, d3q, d4q, [p,] theta, tau_m), each called over
 * the same table of 16,384 states, in CPU nanoseconds per call.
 *
 * Build: gcc -O2 -DROBOT=elastic_2r -DHEADER='"elastic_2r.h"' -DDOF=2 -DN_P=2
 *            elastic_speed_loop.c elastic_2r.c -lm
 * Usage: elastic_speed_loop CALLS REPEATS P_1 .. P_{N_P}
 * Prints "rigid_ns <value>" and "elastic_ns <value>" per repeat, then "checksum <value>"
 * (every output feeds it, so no call can be dropped).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define RIGID CAT(ROBOT, _inverse_dynamics)
#define ELASTIC CAT(ROBOT, _elastic_inverse_dynamics)
#define NQ 16384

static double states[NQ][5][DOF];

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/* q in [-pi, pi), its derivatives in [-2, 2), [-5, 5), [-10, 10), [-20, 20): a 64-bit LCG. */
static void fill(void)
{
    static const double range[5] = {3.141592653589793, 2.0, 5.0, 10.0, 20.0};
    unsigned long long s = 18;
    for (int i = 0; i < NQ; ++i)
        for (int k = 0; k < 5; ++k)
            for (int j = 0; j < DOF; ++j) {
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                states[i][k][j] = (2.0 * ((double)(s >> 11) / 9007199254740992.0) - 1.0) * range[k];
            }
}

int main(int argc, char **argv)
{
    if (argc != 3 + N_P) {
        fprintf(stderr, "usage: %s CALLS REPEATS and %d parameter values\n", argv[0], N_P);
        return 2;
    }
    long calls = atol(argv[1]);
    int repeats = atoi(argv[2]);
    double p[N_P + 1];
    for (int i = 0; i < N_P; ++i)
        p[i] = atof(argv[3 + i]);
    (void)p;
    fill();
    double checksum = 0.0, tau[DOF], theta[DOF], tau_m[DOF];
    for (int r = 0; r <= repeats; ++r) {
        double start = now_ns();
        for (long c = 0; c < calls; ++c) {
            double (*x)[DOF] = states[c % NQ];
#if N_P
            RIGID(x[0], x[1], x[2], p, tau);
#else
            RIGID(x[0], x[1], x[2], tau);
#endif
            checksum += tau[c % DOF];
        }
        double middle = now_ns();
        for (long c = 0; c < calls; ++c) {
            double (*x)[DOF] = states[c % NQ];
#if N_P
            ELASTIC(x[0], x[1], x[2], x[3], x[4], p, theta, tau_m);
#else
            ELASTIC(x[0], x[1], x[2], x[3], x[4], theta, tau_m);
#endif
            checksum += theta[c % DOF] + tau_m[c % DOF];
        }
        double end = now_ns();
        if (r > 0) /* repeat 0 warms up */
            printf("rigid_ns %.3f\nelastic_ns %.3f\n", (middle - start) / calls,
                   (end - middle) / calls);
    }
    printf("checksum %.17g\n", checksum);
    return 0;
}
