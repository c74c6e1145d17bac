"""``symkin identify``: base parameters from logged data, or an exciting trajectory to log.

A thin layer over :mod:`symkin.solve.identify` (the fit),
:mod:`symkin.solve.identify_data` (the CSV file and the filter),
:mod:`symkin.solve.identify_consistency` and :mod:`symkin.solve.identify_excite`.
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np
import sympy as sp

from symkin.cli.report import json_text, progress
from symkin.cli.values import limit_values, parameter_overrides, robot_from_args, sampled_rows
from symkin.derive import derive
from symkin.derive.regressor_base import base_regressor
from symkin.errors import RobotError, SymkinError
from symkin.output_folder import replace_file
from symkin.solve.identify import Identification, identify
from symkin.solve.identify_consistency import Consistency, physical_consistency
from symkin.solve.identify_data import FILTER_ORDER, filtered_samples, logged_samples
from symkin.solve.identify_excite import (
    Excitation,
    check_excitation,
    check_noise,
    exciting_trajectory,
    simulated_torques,
)


def command_identify(args: argparse.Namespace) -> None:
    robot = robot_from_args(args)
    # The geometry's parameters become numbers: the base parameters need numeric geometry.
    robot = robot.with_parameter_values(parameter_overrides(args.set, robot))
    if (args.data is None) == (not args.excite):
        raise SymkinError("identify needs --data FILE.csv (a fit) or --excite (a trajectory)")
    model = derive(robot)
    if args.excite:
        _excite(args, model)
        return
    path = Path(args.data)
    if args.filter is not None:
        samples = filtered_samples(path, robot.dof, args.filter)
    else:
        samples = logged_samples(path, robot.dof)
    weights = _weights(args.weights, robot.dof)
    progress(f"identifying {robot.name} from {len(samples.q)} samples ...")
    fit = identify(model, samples.q, samples.dq, samples.ddq, samples.tau, weights)
    base = base_regressor(model.robot, model.kinematics)
    consistency = physical_consistency(base, fit.estimate, fit.std)
    method = (
        f"differentiated: {FILTER_ORDER}th-order Butterworth low-pass at {args.filter:g} Hz, "
        "zero phase (filtfilt), central differences"
        if args.filter is not None
        else "logged q, dq, ddq"
    )
    if args.json:
        print(json_text(_fit_json(fit, consistency, method)))
    else:
        print(_fit_text(robot.name, fit, consistency, method))


def base_parameters_json(model) -> dict:
    """``{"base_parameters": [{"name", "definition", "value"}]}`` for ``show --dynamics``:
    the base regressor's parameters, defined in the robot's inertial symbols (null value where
    the file has no inertial data); empty when a geometry parameter has no value."""
    try:
        base = base_regressor(model.robot, model.kinematics)
    except RobotError:
        return {"base_parameters": []}
    values = base.values or [None] * len(base.names)
    return {
        "base_parameters": [
            {"name": n, "definition": sp.sstr(d), "value": v}
            for n, d, v in zip(base.names, base.definitions, values, strict=True)
        ]
    }


def base_parameters_text(model) -> str:
    """The base parameters and their definitions, for ``show --dynamics``."""
    rows = base_parameters_json(model)["base_parameters"]
    if not rows:
        return ""
    lines = ["", f"Base parameters ({len(rows)}; tau = Y_b beta, 'symkin identify' fits them):"]
    for row in rows:
        value = "" if row["value"] is None else f"  [{row['value']:.6g}]"
        lines.append(f"  {row['name']} = {row['definition']}{value}")
    return "\n".join(lines)


def _weights(text: str | None, dof: int) -> list[float] | str | None:
    if text is None or text == "auto":
        return text
    try:
        weights = [float(w) for w in text.split(",")]
    except ValueError:
        raise SymkinError(f"--weights: 'auto' or {dof} numbers, got {text!r}") from None
    if len(weights) != dof or not all(np.isfinite(w) and w > 0 for w in weights):
        raise SymkinError(f"--weights: {dof} positive numbers (one per joint), got {text!r}")
    return weights


def _fit_json(fit: Identification, consistency: Consistency, method: str) -> dict:
    return {
        "base_parameters": [
            {"name": n, "definition": d, "estimate": float(e), "std": float(s)}
            for n, d, e, s in zip(fit.names, fit.definitions, fit.estimate, fit.std, strict=True)
        ],
        "condition_number": fit.condition_number,
        "residual_rms": [float(r) for r in fit.residual_rms],
        "samples": fit.samples,
        "weights": [float(w) for w in fit.weights],
        "derivatives": method,
        "physically_consistent": consistency.consistent,
        "inconsistent_parameters": [
            {"name": n, "estimate": e, "nearest_consistent": c, "tolerance": t}
            for n, e, c, t in consistency.misses
        ],
    }


def _fit_text(name: str, fit: Identification, consistency: Consistency, method: str) -> str:
    rms = ", ".join(f"{r:.3g}" for r in fit.residual_rms)
    lines = [
        f"{name}: {len(fit.names)} base parameters from {fit.samples} samples ({method})",
        f"condition number of the stacked base regressor: {fit.condition_number:.4g}",
        f"residual RMS per joint: {rms}",
        "",
        f"{'name':8} {'estimate':>14} {'std':>10}  definition",
    ]
    lines += [
        f"{n:8} {e:14.6g} {s:10.2g}  {d}"
        for n, d, e, s in zip(fit.names, fit.definitions, fit.estimate, fit.std, strict=True)
    ]
    lines.append("")
    if consistency.consistent:
        lines.append(
            "physically consistent: link parameters with non-negative masses, valid inertias "
            "(pseudo-inertia positive semidefinite) and non-negative drive parameters give "
            "these base parameters within three standard deviations"
        )
    else:
        lines.append("physically inconsistent: the nearest consistent link parameters miss")
        lines += [
            f"  {n}: estimate {e:.6g}, nearest consistent {c:.6g} (tolerance {t:.2g})"
            for n, e, c, t in consistency.misses
        ]
    return "\n".join(lines)


def _excite(args: argparse.Namespace, model) -> None:
    robot = model.robot
    if args.out is None:
        raise SymkinError("--excite writes the trajectory to --out FILE.csv")
    check_excitation(args.harmonics, args.period)
    sampled_rows(args.rate, args.period, "--rate", "--period")
    if args.simulate:
        check_noise(args.noise)  # before the optimisation, not after it
    velocity = limit_values(args.velocity_limit, "--velocity-limit", robot, rates=True)
    progress(f"optimising a {args.harmonics}-harmonic motion of period {args.period:g} s ...")
    excitation = exciting_trajectory(
        model,
        args.harmonics,
        args.period,
        None if velocity is None else np.array(velocity),
        args.seed,
    )
    t = np.arange(0.0, args.period, 1.0 / args.rate)
    q, dq, ddq = excitation.states(t)
    columns = [t[:, None], q, dq, ddq]
    header = ["t", *(f"{p}{i}" for p in ("q", "dq", "ddq") for i in range(1, robot.dof + 1))]
    if args.simulate:
        columns.append(simulated_torques(model, q, dq, ddq, args.noise, args.seed))
        header += [f"tau{i}" for i in range(1, robot.dof + 1)]
    buffer = io.StringIO()
    np.savetxt(
        buffer, np.hstack(columns), delimiter=",", header=",".join(header), comments="", fmt="%.17g"
    )
    out = Path(args.out)
    replace_file(out.parent, out.name, buffer.getvalue())
    print(_excitation_text(excitation, len(t), out))


def _excitation_text(excitation: Excitation, rows: int, out: Path) -> str:
    return (
        f"wrote {rows} samples of one period ({excitation.period:g} s) to {out}\n"
        f"condition number of the stacked base regressor: {excitation.condition_number:.4g} "
        f"(the random starting motion: {excitation.initial_condition_number:.4g})"
    )
