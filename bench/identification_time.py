"""Identification time of the PUMA 560 from 10^5 logged samples (docs/benchmarks.md).

Torques come from Robotics Toolbox's ``rne`` on the first 2000 states (checked against the
generated inverse dynamics there) and from the generated NumPy inverse dynamics for all of
them, with Gaussian noise; the timed steps are the stacked base regressor (generated NumPy
kernel, batched), the least-squares fit with standard deviations, and the consistency check.
Run: ``python bench/identification_time.py [SAMPLES]``.
"""

from __future__ import annotations

import os
import sys
import time
import warnings

import numpy as np


def timed(function, *arguments):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function(*arguments)
    return result, time.perf_counter() - wall, time.process_time() - cpu


def main(samples: int = 100_000) -> None:
    import roboticstoolbox as rtb

    from symkin import derive, load_robot
    from symkin.derive.regressor_base import base_regressor
    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.identify import base_regressor_function, identify
    from symkin.solve.identify_consistency import physical_consistency

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = derive(load_robot("puma560"))
    rng = np.random.default_rng(0)
    q, dq, ddq = (rng.uniform(-2.0, 2.0, (samples, 6)) for _ in range(3))
    tau = generated_numpy_module(model).inverse_dynamics(
        q, dq, ddq, [0.4318, 0.0203, 0.15005, 0.4318]
    )
    puma = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    check = np.array([puma.rne(*s) for s in zip(q[:2000], dq[:2000], ddq[:2000], strict=True)])
    assert np.abs(check - tau[:2000]).max() < 1e-9
    tau = tau + rng.normal(0.0, 0.05, tau.shape)
    _, wall, cpu = timed(lambda: base_regressor_function(model))
    print(f"base regressor kernel built (derive + CSE + emit): {wall:.2f} s wall, {cpu:.2f} s CPU")
    stacked = base_regressor_function(model)
    _, wall, cpu = timed(stacked, q, dq, ddq)
    print(f"Y_b at {samples} samples: {wall:.2f} s wall, {cpu:.2f} s CPU")
    fit, wall, cpu = timed(identify, model, q, dq, ddq, tau)
    print(f"identify (Y_b + QR fit + std), {samples} samples: {wall:.2f} s wall, {cpu:.2f} s CPU")
    base = base_regressor(model.robot, model.kinematics)
    _, wall, cpu = timed(physical_consistency, base, fit.estimate, fit.std)
    print(f"consistency check: {wall:.2f} s wall, {cpu:.2f} s CPU")
    print(f"condition number {fit.condition_number:.4g}, residual RMS {fit.residual_rms.round(4)}")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
