/*
 * Example for robot 'puma560': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "puma560.h"

int main(void)
{
    const double q[PUMA560_DOF] = { 0.1, 0.2, 0.3, 0.4, 0.5, 0.6 };
    const double p[] = PUMA560_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    puma560_fk(q, p, T);
    printf("T of puma560 at q = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
