/*
 * Example for robot 'rpr': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "rpr.h"

int main(void)
{
    const double q[RPR_DOF] = { 0.1, 0.2, 0.3 };
    const double p[] = RPR_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    rpr_fk(q, p, T);
    printf("T of rpr at q = (0.1, 0.2, 0.3):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
