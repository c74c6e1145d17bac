/*
 * Example for robot 'cylindrical_rtt_wrist': forward kinematics at one configuration.
 * Build and run: make && ./example
 */
#include <stdio.h>

#include "cylindrical_rtt_wrist.h"

int main(void)
{
    const double q[CYLINDRICAL_RTT_WRIST_DOF] = { 0.1, 0.2, 0.3, 0.4, 0.5, 0.6 };
    const double p[] = CYLINDRICAL_RTT_WRIST_DEFAULT_PARAMETERS;
    double T[16];
    int i;

    cylindrical_rtt_wrist_fk(q, p, T);
    printf("T of cylindrical_rtt_wrist at q = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):\n");
    for (i = 0; i < 4; ++i) {
        printf("% .6f % .6f % .6f % .6f\n", (double)T[4 * i], (double)T[4 * i + 1],
               (double)T[4 * i + 2], (double)T[4 * i + 3]);
    }
    return 0;
}
