/*
 * What the C-loop harnesses of bench/ share (codegen_speed_loop.c, dynamics_speed_loop.c):
 * the CPU-time clock, strict parsing of parameter values, and the peak resident set.
 * Included by each harness (static functions: one translation unit each).
 */
#ifndef SYMKIN_BENCH_LOOP_COMMON_H
#define SYMKIN_BENCH_LOOP_COMMON_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* This process's peak resident set in KiB (Linux: VmHWM); nothing printed elsewhere. */
static void print_peak_rss(void)
{
    char line[256];
    FILE *status = fopen("/proc/self/status", "r");
    if (status == NULL) {
        return;
    }
    while (fgets(line, sizeof line, status) != NULL) {
        long kib;
        if (sscanf(line, "VmHWM: %ld", &kib) == 1) {
            printf("max_rss_kib %ld\n", kib);
        }
    }
    fclose(status);
}

/* A parameter value from the command line; exits on anything else (atof would
 * read "np.float64(0.4318)" as 0 without a word). */
static double parse_number(const char *text)
{
    char *end;
    const double value = strtod(text, &end);
    if (end == text || *end != '\0') {
        fprintf(stderr, "not a number: %s\n", text);
        exit(2);
    }
    return value;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: not the other programs' */
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

#endif
