/*
 * C-loop timing harness for bench/dynamics_speed.py: calls one robot's generated inverse
 * dynamics (or, with -DKERNEL=_forward_dynamics, its forward dynamics) many times over a table
 * of 65,536 states (q, dq, ddq or tau) and reports nanoseconds per call.
 *
 * The robot and the kernel are chosen at compile time, and the script builds them for each
 * generated code (the PUMA 560's with p as input and with numeric parameters, the Panda's)
 * against three implementations of the same kernel (bench/c_loop.py):
 *   symkin:  gcc -O2 -DROBOT=puma560 -DHEADER='"puma560.h"' -DDOF=6 -DN_P=4 -DN_PI=0
 *                dynamics_speed_loop.c puma560.c -lm
 *            (generated C API: ROBOT_inverse_dynamics(q, dq, ddq, p, [pi,] tau))
 *   CasADi:  the same with -DBENCH_CASADI, HEADER "casadi_puma560.h" and casadi_puma560.c,
 *            the code casadi.CodeGenerator writes for the generated CasADi module's
 *            inverse_dynamics_function() (C API: ROBOT_inverse_dynamics(arg, res, iw, w, mem))
 *   CasADi, independent model: the same, for the Newton-Euler model that bench/casadi_peer.py
 *            writes in CasADi from the DH table (not from symkin's expressions).
 * Forward dynamics has the same argument layout, (q, dq, tau, p) -> ddq.
 * N_P is the number of geometric parameters p, N_PI the number of inertial parameters pi
 * (0 when the robot file gives the inertial data).  Code generated for a robot without
 * parameters (Robot.with_parameter_values(), symkin derive --numeric-parameters) has no p
 * argument: with -DN_P=0 the harness passes none (CasADi's function keeps a 0x1 input p,
 * which it does not read).  The kernel is compiled in its own
 * translation unit (no LTO), as a user links it, so every call is a real call.  Each call's
 * torques feed a checksum that is printed at the end; the compiler cannot drop the calls, and
 * the script compares the two builds' checksums (same states, so they agree to rounding).
 *
 * Usage: dynamics_speed_loop CALLS REPEATS P_1 .. P_{N_P} PI_1 .. PI_{N_PI}   (either may be none)
 *   CALLS    calls per timed repeat
 *   REPEATS  timed repeats (one untimed warm-up repeat runs first)
 *   P, PI    the parameter values, in the generated code's order
 * Prints one line "ns_per_call <value>" per repeat, then "checksum <value>" and
 * "max_rss_kib <value>" (this process's peak resident set, VmHWM of /proc/self/status:
 * unlike getrusage's ru_maxrss, it does not carry the parent's peak across exec).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "loop_common.h"

#include HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#ifndef KERNEL
#define KERNEL _inverse_dynamics
#endif
#define INVERSE_DYNAMICS CAT(ROBOT, KERNEL)
#define INVERSE_DYNAMICS_WORK CAT(INVERSE_DYNAMICS, _work)

/* Distinct states, cycled through in order (65,536 x 3 x DOF doubles: 9 MiB for 6 joints).
 * Many, on purpose: with only about a thousand, the CPU learns the repeating arguments of
 * libm's sin and cos and a call gets faster than on fresh states (see codegen_speed_loop.c). */
#define NQ 65536
#define N_PARAMETERS (N_P + N_PI)

static double qs[NQ][3][DOF]; /* static: not on the stack */

/* Deterministic states: q in [-pi, pi), dq in [-2, 2), ddq in [-5, 5) (rad, s), from a 64-bit
 * LCG (Knuth's MMIX constants). */
static void fill_state_table(void)
{
    static const double range[3] = {3.141592653589793, 2.0, 5.0};
    unsigned long long state = 560;
    for (int i = 0; i < NQ; ++i) {
        for (int k = 0; k < 3; ++k) {
            for (int j = 0; j < DOF; ++j) {
                state = state * 6364136223846793005ULL + 1442695040888963407ULL;
                double unit = (double)(state >> 11) / 9007199254740992.0; /* [0, 1) */
                qs[i][k][j] = (2.0 * unit - 1.0) * range[k];
            }
        }
    }
}

int main(int argc, char **argv)
{
    if (argc != 3 + N_PARAMETERS) {
        fprintf(stderr, "usage: %s CALLS REPEATS and %d parameter values\n", argv[0],
                N_PARAMETERS);
        return 2;
    }
    const long calls = atol(argv[1]);
    const int repeats = atoi(argv[2]);
    /* One extra element: a zero-length array is not C. */
    double parameters[N_PARAMETERS + 1];
    for (int k = 0; k < N_PARAMETERS; ++k) {
        parameters[k] = parse_number(argv[3 + k]);
    }
    const double *p = N_P ? parameters : NULL;
    const double *pi = parameters + N_P;
    double tau[DOF];
    double checksum = 0.0;
    fill_state_table();

#ifdef BENCH_CASADI
    const double *arg[5] = {NULL, NULL, NULL, p, pi};
    double *res[1] = {tau};
    casadi_int sz_arg, sz_res, sz_iw, sz_w;
    INVERSE_DYNAMICS_WORK(&sz_arg, &sz_res, &sz_iw, &sz_w);
    if (sz_arg > (N_PI ? 5 : 4) || sz_res > 1) {
        fprintf(stderr, "unexpected CasADi work sizes\n");
        return 1;
    }
    casadi_int *iw = malloc((size_t)(sz_iw > 0 ? sz_iw : 1) * sizeof(casadi_int));
    casadi_real *w = malloc((size_t)(sz_w > 0 ? sz_w : 1) * sizeof(casadi_real));
#else
    (void)p;
    (void)pi;
#endif

    for (int r = -1; r < repeats; ++r) { /* r = -1: warm-up, not reported */
        const double start = now_ns();
        for (long i = 0; i < calls; ++i) {
            double(*state)[DOF] = qs[i & (NQ - 1)];
#ifdef BENCH_CASADI
            arg[0] = state[0];
            arg[1] = state[1];
            arg[2] = state[2];
            INVERSE_DYNAMICS(arg, res, iw, w, 0);
#elif N_P && N_PI
            INVERSE_DYNAMICS(state[0], state[1], state[2], p, pi, tau);
#elif N_P
            INVERSE_DYNAMICS(state[0], state[1], state[2], p, tau);
#elif N_PI
            INVERSE_DYNAMICS(state[0], state[1], state[2], pi, tau);
#else
            INVERSE_DYNAMICS(state[0], state[1], state[2], tau);
#endif
            for (int j = 0; j < DOF; ++j) {
                checksum += tau[j];
            }
        }
        const double elapsed = now_ns() - start;
        if (r >= 0) {
            printf("ns_per_call %.4f\n", elapsed / (double)calls);
        }
    }
    printf("checksum %.17g\n", checksum);
    print_peak_rss();
#ifdef BENCH_CASADI
    free(iw);
    free(w);
#endif
    return 0;
}
