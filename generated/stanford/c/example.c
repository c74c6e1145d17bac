/*
 * Example for robot 'stanford': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "stanford.h"

int main(void)
{
    const double q[STANFORD_DOF] = { 0.1, 0.2, 0.3, 0.4, 0.5, 0.6 };
    const double p[] = STANFORD_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    stanford_fk(q, p, T);
    printf("T of stanford at q = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
