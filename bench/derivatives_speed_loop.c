/*
 * C-loop timing harness for bench/derivatives_speed.py: calls one robot's generated derivative
 * kernels many times over a table of 65,536 states (q, dq, ddq or tau) and reports
 * nanoseconds per call.
 *
 * Built per robot and implementation (the script passes the defines):
 *   symkin:  gcc -O2 -DROBOT=puma560 -DHEADER='"puma560.h"' -DDOF=6 -DN_P=4
 *                derivatives_speed_loop.c puma560.c -lm
 *            KERNEL=1: ROBOT_inverse_dynamics_derivatives(q, dq, ddq, [p,] tau, dtau_dq, dtau_ddq)
 *            KERNEL=2: ROBOT_forward_dynamics_derivatives(q, dq, tau, [p,] ddq, dddq_dq,
 *                      dddq_ddq, dddq_dtau)
 *   CasADi:  -DBENCH_CASADI, HEADER "casadi_ROBOT.h": the C casadi.CodeGenerator writes for
 *            casadi.jacobian of the generated CasADi tau (KERNEL=1) or of its forward dynamics
 *            (KERNEL=2), function ROBOT_ad(arg, res, iw, w, mem).
 * The kernel is compiled in its own translation unit (no LTO), as a user links it.  Every
 * output feeds a checksum printed at the end, so the compiler cannot drop the calls.
 *
 * Usage: derivatives_speed_loop CALLS REPEATS P_1 .. P_{N_P}
 * Prints "ns_per_call <value>" per repeat, then "checksum <value>".
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define NQ 65536
#define NN (DOF * DOF)

static double states[NQ][3][DOF];

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: not the other programs' */
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/* q in [-pi, pi), dq in [-2, 2), third entry (ddq or tau) in [-5, 5), from a 64-bit LCG. */
static void fill_state_table(void)
{
    static const double range[3] = {3.141592653589793, 2.0, 5.0};
    unsigned long long state = 560;
    for (int i = 0; i < NQ; ++i) {
        for (int k = 0; k < 3; ++k) {
            for (int j = 0; j < DOF; ++j) {
                state = state * 6364136223846793005ULL + 1442695040888963407ULL;
                double unit = (double)(state >> 11) / 9007199254740992.0;
                states[i][k][j] = (2.0 * unit - 1.0) * range[k];
            }
        }
    }
}

int main(int argc, char **argv)
{
    if (argc != 3 + N_P) {
        fprintf(stderr, "usage: %s CALLS REPEATS and %d parameter values\n", argv[0], N_P);
        return 2;
    }
    const long calls = atol(argv[1]);
    const int repeats = atoi(argv[2]);
    double parameters[N_P + 1];
    for (int k = 0; k < N_P; ++k) {
        parameters[k] = atof(argv[3 + k]);
    }
    const double *p = parameters;
    double first[DOF], out[3][NN];
    double checksum = 0.0;
    fill_state_table();
#ifdef BENCH_CASADI
    const double *arg[4] = {NULL, NULL, NULL, p};
    double *res[3] = {out[0], out[1], out[2]};
    casadi_int sz_arg, sz_res, sz_iw, sz_w;
    CAT(ROBOT, _ad_work)(&sz_arg, &sz_res, &sz_iw, &sz_w);
    casadi_int *iw = malloc((size_t)(sz_iw > 0 ? sz_iw : 1) * sizeof(casadi_int));
    casadi_real *w = malloc((size_t)(sz_w > 0 ? sz_w : 1) * sizeof(casadi_real));
    (void)first;
#else
    (void)p;
#endif
    for (int r = -1; r < repeats; ++r) { /* r = -1: warm-up, not reported */
        const double start = now_ns();
        for (long i = 0; i < calls; ++i) {
            double(*s)[DOF] = states[i & (NQ - 1)];
#ifdef BENCH_CASADI
            arg[0] = s[0];
            arg[1] = s[1];
            arg[2] = s[2];
            CAT(ROBOT, _ad)(arg, res, iw, w, 0);
#elif KERNEL == 1 && N_P
            CAT(ROBOT, _inverse_dynamics_derivatives)(s[0], s[1], s[2], p, first, out[0], out[1]);
#elif KERNEL == 1
            CAT(ROBOT, _inverse_dynamics_derivatives)(s[0], s[1], s[2], first, out[0], out[1]);
#elif N_P
            CAT(ROBOT, _forward_dynamics_derivatives)(s[0], s[1], s[2], p, first, out[0], out[1], out[2]);
#else
            CAT(ROBOT, _forward_dynamics_derivatives)(s[0], s[1], s[2], first, out[0], out[1], out[2]);
#endif
            checksum += out[0][i % NN] + out[1][(i + 1) % NN];
        }
        const double elapsed = now_ns() - start;
        if (r >= 0) {
            printf("ns_per_call %.4f\n", elapsed / (double)calls);
        }
    }
    printf("checksum %.17g\n", checksum);
#ifdef BENCH_CASADI
    free(iw);
    free(w);
#endif
    return 0;
}
