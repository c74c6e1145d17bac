/*
 * C-loop timing harness for bench/codegen_speed.py: calls one robot's generated kinematics
 * kernel many times over a table of 65,536 joint vectors and reports nanoseconds per call.
 *
 * The robot is chosen at compile time (bench/c_loop.py builds it), against three
 * implementations of the same kernels:
 *   symkin:  gcc -O2 -DROBOT=puma560 -DHEADER='"puma560.h"' -DDOF=6 -DN_P=4
 *                codegen_speed_loop.c puma560.c -lm        (generated C API)
 *   CasADi:  the same with -DBENCH_CASADI and the header and source that casadi.CodeGenerator
 *            writes, either for symkin's generated CasADi module (symkin's expression graph)
 *            or for the independent CasADi model of bench/casadi_peer.py; both take (q, p).
 * The kernels are compiled in their own translation unit (no LTO), as a user links them,
 * so every call is a real call.  Each call's outputs feed a checksum that is printed at the
 * end; the compiler cannot drop the calls, and the script compares the builds' checksums
 * (same joint vectors, so they must agree to rounding).
 *
 * Usage: codegen_speed_loop KERNEL CALLS REPEATS P_1 .. P_{N_P}
 *   KERNEL   fk | fk_jacobian
 *   CALLS    calls per timed repeat
 *   REPEATS  timed repeats (one untimed warm-up repeat runs first)
 *   P        the parameter values, in the generated code's order (N_P >= 1)
 * Prints one line "ns_per_call <value>" per repeat, then "checksum <value>" and
 * "max_rss_kib <value>" (this process's peak resident set, VmHWM of /proc/self/status:
 * unlike getrusage's ru_maxrss, it does not carry the parent's peak across exec).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "loop_common.h"

/* Distinct joint vectors, cycled through in order (3 MiB).  Many, on purpose: with only
 * about a thousand, the CPU learns the repeating arguments (most likely the branches libm's
 * sin and cos take for them), and a call takes a fifth to a third less time than on fresh
 * joint angles (measured on the 2-core development machine). */
#define NQ 65536

#include HEADER

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define FK CAT(ROBOT, _fk)
#define FK_JACOBIAN CAT(ROBOT, _fk_jacobian)

#ifdef BENCH_CASADI
/* CasADi outputs are column-major: the translation column is entries 12, 13, 14. */
#define TX 12
#define TY 13
#define TZ 14
#else
#define TX 3
#define TY 7
#define TZ 11
#endif

static double qs[NQ][DOF]; /* static: 3 MiB for 6 joints, not on the stack */

/* Deterministic joint vectors in [-pi, pi): a 64-bit LCG (Knuth's MMIX constants). */
static void fill_joint_table(void)
{
    unsigned long long state = 560;
    for (int i = 0; i < NQ; ++i) {
        for (int j = 0; j < DOF; ++j) {
            state = state * 6364136223846793005ULL + 1442695040888963407ULL;
            double unit = (double)(state >> 11) / 9007199254740992.0; /* [0, 1) */
            qs[i][j] = (2.0 * unit - 1.0) * 3.141592653589793;
        }
    }
}

int main(int argc, char **argv)
{
    if (argc != 4 + N_P) {
        fprintf(stderr, "usage: %s fk|fk_jacobian CALLS REPEATS and %d parameter values\n",
                argv[0], N_P);
        return 2;
    }
    const int with_jacobian = strcmp(argv[1], "fk_jacobian") == 0;
    if (!with_jacobian && strcmp(argv[1], "fk") != 0) {
        fprintf(stderr, "unknown kernel %s\n", argv[1]);
        return 2;
    }
    const long calls = atol(argv[2]);
    const int repeats = atoi(argv[3]);
    double parameters[N_P + 1]; /* one extra element: a zero-length array is not C */
    for (int k = 0; k < N_P; ++k) {
        parameters[k] = parse_number(argv[4 + k]);
    }
    double T[16], J[6 * DOF];
    double checksum = 0.0;
    fill_joint_table();

#ifdef BENCH_CASADI
    const double *arg[2] = {NULL, parameters};
    double *res[2] = {T, J};
    casadi_int sz_arg, sz_res, sz_iw, sz_w;
    if (with_jacobian) {
        CAT(ROBOT, _fk_jacobian_work)(&sz_arg, &sz_res, &sz_iw, &sz_w);
    } else {
        CAT(ROBOT, _fk_work)(&sz_arg, &sz_res, &sz_iw, &sz_w);
    }
    if (sz_arg > 2 || sz_res > 2) {
        fprintf(stderr, "unexpected CasADi work sizes\n");
        return 1;
    }
    casadi_int *iw = malloc((size_t)(sz_iw > 0 ? sz_iw : 1) * sizeof(casadi_int));
    casadi_real *w = malloc((size_t)(sz_w > 0 ? sz_w : 1) * sizeof(casadi_real));
#endif

    for (int r = -1; r < repeats; ++r) { /* r = -1: warm-up, not reported */
        const double start = now_ns();
        for (long i = 0; i < calls; ++i) {
            const double *q = qs[i & (NQ - 1)];
#ifdef BENCH_CASADI
            arg[0] = q;
            if (with_jacobian) {
                FK_JACOBIAN(arg, res, iw, w, 0);
            } else {
                FK(arg, res, iw, w, 0);
            }
#else
            if (with_jacobian) {
                FK_JACOBIAN(q, parameters, T, J);
            } else {
                FK(q, parameters, T);
            }
#endif
            checksum += T[TX] + T[TY] + T[TZ];
            if (with_jacobian) {
                /* first and last entries: the same in either storage order */
                checksum += J[0] + J[6 * DOF - 1];
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
