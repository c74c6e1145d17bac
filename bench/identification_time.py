"""Identification time of the PUMA 560 from 10^5 logged samples (docs/benchmarks.md).

Torques come from Robotics Toolbox's ``rne`` on the first 2000 states (checked against the
generated inverse dynamics there) and from the generated NumPy inverse dynamics for all of
them, with Gaussian noise; the timed steps are the stacked base regressor (generated NumPy
kernel, batched), the least-squares fit with standard deviations, and the consistency check,
each in wall and CPU seconds of this process.  The table, with the machine and the load
average, goes into ``docs/benchmarks.md`` between ``<!-- identification:begin -->`` and
``<!-- identification:end -->``.

Usage::

    .venv/bin/python bench/identification_time.py                  # 10^5 samples
    .venv/bin/python bench/identification_time.py --samples 20000 --no-write
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from codegen_speed import write_docs
from derivation_time import measured_line, version

DOCS = Path(__file__).resolve().parent.parent / "docs" / "benchmarks.md"
MARKERS = ("<!-- identification:begin -->", "<!-- identification:end -->")


def timed(function, *arguments):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function(*arguments)
    return result, time.perf_counter() - wall, time.process_time() - cpu


def measure(samples: int) -> tuple[list[tuple[str, float, float]], object]:
    """``[(step, wall, cpu)]`` and the fit."""
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
    if np.abs(check - tau[:2000]).max() >= 1e-9:
        raise SystemExit("the generated inverse dynamics disagree with Robotics Toolbox's rne")
    tau = tau + rng.normal(0.0, 0.05, tau.shape)
    steps = []
    _, wall, cpu = timed(lambda: base_regressor_function(model))
    steps.append(
        (
            "build the `base_regressor` NumPy kernel (derivation, CSE, emit; once per "
            "robot and process)",
            wall,
            cpu,
        )
    )
    stacked = base_regressor_function(model)
    _, wall, cpu = timed(stacked, q, dq, ddq)
    steps.append((f"`Y_b` at {samples} samples (generated NumPy kernel, batched)", wall, cpu))
    fit, wall, cpu = timed(identify, model, q, dq, ddq, tau)
    steps.append(
        (
            f"`identify`: `Y_b`, blockwise QR, estimate and standard deviations, {samples} samples",
            wall,
            cpu,
        )
    )
    base = base_regressor(model.robot, model.kinematics)
    _, wall, cpu = timed(physical_consistency, base, fit.estimate, fit.std)
    steps.append(("physical-consistency check (`least_squares`)", wall, cpu))
    return steps, fit


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=100_000, help="logged samples (10^5)")
    parser.add_argument("--docs", type=Path, default=DOCS)
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    load_start = os.getloadavg()[0]
    steps, fit = measure(args.samples)
    lines = [
        measured_line(
            f"NumPy {version('numpy')}, SciPy {version('scipy')}, symkin {version('symkin')}. "
            "One run; wall and CPU seconds of the process (wall is inflated by the load).",
            (load_start, os.getloadavg()[0]),
            "identification_time.py",
        ),
        "",
        "| step | wall [s] | CPU [s] |",
        "| --- | ---: | ---: |",
        *(f"| {step} | {wall:.2f} | {cpu:.2f} |" for step, wall, cpu in steps),
        "",
        f"Condition number of the stacked base regressor {fit.condition_number:.4g}; residual "
        f"RMS {', '.join(f'{v:.3f}' for v in np.ravel(fit.residual_rms))} N m per joint (noise "
        "0.05 N m).",
    ]
    table = "\n".join(lines)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs, MARKERS, "Identification")
        print(f"wrote {args.docs}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
