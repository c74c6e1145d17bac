/*
 * Example for robot 'panda': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "panda.h"

int main(void)
{
    const double q[PANDA_DOF] = { 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7 };
    const double p[] = PANDA_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    panda_fk(q, p, T);
    printf("T of panda at q = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
