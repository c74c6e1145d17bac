/*
 * Example for robot 'planar_2r': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "planar_2r.h"

int main(void)
{
    const double q[PLANAR_2R_DOF] = { 0.1, 0.2 };
    const double p[] = PLANAR_2R_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    planar_2r_fk(q, p, T);
    printf("T of planar_2r at q = (0.1, 0.2):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
