"""An optimal trajectory as text and files: the summary printed by ``symkin trajopt``, CSV rows,
a JSON object, and the files written into an output folder."""

from __future__ import annotations

import io
import json
from dataclasses import asdict
from pathlib import Path

import numpy as np

from symkin.errors import SymkinError
from symkin.output_folder import replace_file
from symkin.solve.trajopt.functions import RobotFunctions
from symkin.solve.trajopt.plot import plot_path, plot_trajectory
from symkin.solve.trajopt.solve import Trajectory

COST_NAMES = {"effort": "integral of tau^2", "time": "final time"}


def trajectory_rows(trajectory: Trajectory) -> tuple[list[str], np.ndarray]:
    """CSV header and rows ``t, q1..qn, dq1..dqn, tau1..taun`` at the N+1 nodes.

    ``tau`` at node k is the torque held on ``[t_k, t_k+1)``; the last node repeats the last
    interval's torque.
    """
    n = trajectory.robot.dof
    header = ["t"] + [f"{name}{i}" for name in ("q", "dq", "tau") for i in range(1, n + 1)]
    tau = np.vstack([trajectory.tau, trajectory.tau[-1:]])
    rows = np.column_stack([trajectory.t, trajectory.q, trajectory.dq, tau])
    return header, rows


def trajectory_json(trajectory: Trajectory) -> dict:
    """Problem settings, solver statistics and the trajectory, as JSON-ready values."""
    return {
        "robot": trajectory.robot.name,
        "problem": asdict(trajectory.problem) | {"overrides": dict(trajectory.problem.overrides)},
        "solver": asdict(trajectory.stats),
        "final_time": trajectory.final_time,
        "cost": trajectory.cost,
        "effort": trajectory.effort,
        "max_violation": trajectory.max_violation,
        "accuracy": accuracy_json(trajectory),
        "rounds": [asdict(r) for r in trajectory.rounds],
        "initial_guess": None if trajectory.guess is None else asdict(trajectory.guess),
        "t": trajectory.t.tolist(),
        "q": trajectory.q.tolist(),
        "dq": trajectory.dq.tolist(),
        "tau": trajectory.tau.tolist(),
    } | ({} if trajectory.ddq is None else {"ddq": trajectory.ddq.tolist()})


def accuracy_json(trajectory: Trajectory) -> dict | None:
    """The re-simulation's verdict: largest local defect, end error, tolerance, consistency."""
    report = trajectory.accuracy
    if report is None:
        return None
    return {
        "max_defect": report.max_defect,
        "end_error": report.end_error,
        "min_clearance": report.min_clearance,
        "tolerance": trajectory.problem.tolerance,
        "consistent": trajectory.consistent,
        "refinements": max(len(trajectory.rounds) - 1, 0),
        "defects": report.defects.tolist(),
    }


def accuracy_text(trajectory: Trajectory) -> list[str]:
    """The re-simulation's lines of the summary, saying so when refinement stopped short."""
    report, problem = trajectory.accuracy, trajectory.problem
    if report is None:
        return []
    history = " -> ".join(f"{r.intervals} ({r.max_defect:.1e})" for r in trajectory.rounds)
    lines = [
        f"re-simulated (solve_ivp DOP853, tol 1e-10): largest local defect {report.max_defect:.1e}"
        f", open-loop end error {report.end_error:.1e} (joint units)",
        f"mesh: intervals (largest defect) {history}",
    ]
    if report.min_clearance is not None:
        lines.append(f"smallest obstacle clearance along the path: {report.min_clearance:.3g} m")
    if problem.tolerance is not None and not trajectory.consistent:
        lines.append(
            f"warning: not consistent to the tolerance {problem.tolerance:g} after "
            f"{problem.max_refinements} refinements (raise --max-refinements or --intervals)"
        )
    return lines


def guess_text(trajectory: Trajectory) -> list[str]:
    """With obstacles, one line: whether the first guess was clear of them, and how."""
    guess = trajectory.guess
    if guess is None or guess.clear is None:
        return []
    how = f"{guess.vias} via configurations" if guess.source == "detour" else "the straight line"
    if guess.clear:
        spare = f"{guess.min_clearance:.3g} m to spare"
        return [f"first guess: clear of the obstacles ({how}; {spare})"]
    return [f"first guess: not clear of the obstacles ({how}; {guess.note})"]


def summary_text(trajectory: Trajectory) -> str:
    """A few lines: the problem, IPOPT's status and iterations, solve time, T and the cost."""
    problem, stats = trajectory.problem, trajectory.stats
    objective = {"effort": "minimum effort", "time": "minimum time"}[problem.objective]
    method = problem.method.replace("-", " ")
    return "\n".join(
        [
            f"{trajectory.robot.name}: {objective}, {method}, {len(trajectory.t) - 1} intervals",
            f"IPOPT: {stats.status}, {stats.iterations} iterations",
            f"solve time: {stats.solve_time:.3f} s (IPOPT), build {stats.build_time:.3f} s, "
            f"re-simulation {stats.check_time:.3f} s; CPU "
            + ", ".join(f"{value:.3f}" for value in stats.cpu_times)
            + " s",
            f"final time T = {trajectory.final_time:.6g} s",
            f"cost = {trajectory.cost:.6g} ({COST_NAMES[problem.objective]})",
            f"effort = {trajectory.effort:.6g}",
            f"max constraint violation = {trajectory.max_violation:.1e}",
            *guess_text(trajectory),
            *accuracy_text(trajectory),
        ]
    )


def write_trajectory(
    trajectory: Trajectory,
    out: str | Path,
    plot: bool = False,
    functions: RobotFunctions | None = None,
) -> list[Path]:
    """``trajectory.csv``, ``trajectory.json`` and, with ``plot``, ``trajectory.png`` in ``out``
    (and, given the robot's ``functions``, ``trajectory_path.png``, the tool path)."""
    out = Path(out)
    header, rows = trajectory_rows(trajectory)
    paths = [out / "trajectory.csv", out / "trajectory.json"]
    csv = io.StringIO()
    np.savetxt(csv, rows, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    try:
        text = json.dumps(trajectory_json(trajectory), indent=2, allow_nan=False) + "\n"
    except ValueError:
        raise SymkinError("the trajectory holds values that are not finite numbers") from None
    replace_file(out, paths[0].name, csv.getvalue())  # never through a link (security.md)
    replace_file(out, paths[1].name, text)
    if plot:
        paths.append(plot_trajectory(trajectory, out / "trajectory.png"))
        if functions is not None:
            paths.append(plot_path(trajectory, functions, out / "trajectory_path.png"))
    return paths


def resampled_rows(samples: dict[str, np.ndarray]) -> tuple[list[str], np.ndarray]:
    """CSV header and rows ``t, q1..qn, dq1..dqn, ddq1..ddqn, tau1..taun`` of
    :func:`~symkin.solve.trajopt.resample.resampled` samples."""
    n = samples["q"].shape[1]
    names = ("q", "dq", "ddq", "tau")
    header = ["t"] + [f"{name}{i}" for name in names for i in range(1, n + 1)]
    return header, np.column_stack([samples["t"], *(samples[name] for name in names)])


def write_resampled(samples: dict[str, np.ndarray], out: str | Path) -> list[Path]:
    """``trajectory_resampled.csv`` and ``.json`` in ``out``: the samples a controller plays
    back (the JSON holds the same arrays under their names)."""
    header, rows = resampled_rows(samples)
    csv = io.StringIO()
    np.savetxt(csv, rows, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    text = json.dumps({k: v.tolist() for k, v in samples.items()}, allow_nan=False) + "\n"
    replace_file(Path(out), "trajectory_resampled.csv", csv.getvalue())
    replace_file(Path(out), "trajectory_resampled.json", text)
    return [Path(out) / "trajectory_resampled.csv", Path(out) / "trajectory_resampled.json"]
