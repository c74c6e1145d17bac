"""Trajectory optimisation: solve times of the worked examples, and the generated dynamics
against a generic CasADi Newton–Euler in the same optimal control problem.

In one run, on the same machine:

* **The worked examples of docs/trajopt.md**: the two-link arm of ``examples/arm_2r.toml``
  swinging from hanging straight down to (30°, 45°), and the PUMA 560 moving between two
  configurations; each for minimum effort (fixed T) and minimum time, with multiple shooting
  and with collocation.  Each is solved ``--repeat`` times with :func:`symkin.solve.trajopt.
  optimal_trajectory` (a fresh ``casadi.Opti`` every time; the rendered CasADi and NumPy
  modules and the robot's CasADi functions are built once per robot beforehand, and that time
  is reported on its own), the cases alternated round by round.  The table gives IPOPT's
  status and iterations, the median time of ``Opti.solve`` in CPU seconds of the process
  (``SolverStats.cpu_times``, what the shared machine's load inflates least) and in wall
  seconds, with their ranges, T, the cost, the fraction of intervals with a torque at its
  limit, and the **replay error**: the optimal torques, held on each interval, integrated by
  SciPy's ``solve_ivp`` (DOP853, rtol = atol = 1e-10) on the generated NumPy forward dynamics,
  and the largest difference of the end state from the goal at rest.
* **Regularisation**: each minimum-time example with multiple shooting solved once more with
  ``regularisation=0``; the relative lengthening of T caused by the default weight.
* **Peer**: a textbook recursive Newton–Euler (Siciliano et al., Robotics: Modelling, Planning
  and Control, 2009, Sec. 7.5) written directly in CasADi ``SX`` from the same numeric DH table
  and inertial data, mass matrix by n unit-acceleration passes, ``ddq = solve(M, tau - b)``:
  what one writes without symkin.  It is checked against symkin's forward dynamics at random
  states first (the script stops above 1e-9 relative), then the same minimum-effort problems
  (multiple shooting) are solved with it swapped in (``functions=``), each peer solve right
  after symkin's in the same round.  The ratios are symkin's median solve time over the
  peer's, in CPU and in wall time.

Plots of the multiple-shooting solutions go to ``docs/images/trajopt_<robot>_<objective>.png``.
The script writes its table into ``docs/benchmarks.md`` between ``<!-- trajopt:begin -->`` and
``<!-- trajopt:end -->``, and the examples' results into ``docs/trajopt.md`` between
``<!-- trajopt-examples:begin -->`` and ``<!-- trajopt-examples:end -->``.  No test passes or
fails on it.

Usage::

    .venv/bin/python bench/trajopt_time.py               # 3 rounds, about 5 minutes
    .venv/bin/python bench/trajopt_time.py --quick --no-write     # 2 rounds, print only
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import sys
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from casadi_peer import newton_euler_forward_dynamics
from codegen_speed import write_docs
from derivation_time import measured_line, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
EXAMPLE_DOCS = ROOT / "docs" / "trajopt.md"
IMAGES = ROOT / "docs" / "images"
MARKERS = ("<!-- trajopt:begin -->", "<!-- trajopt:end -->")
EXAMPLE_MARKERS = ("<!-- trajopt-examples:begin -->", "<!-- trajopt-examples:end -->")
METHODS = ("multiple-shooting", "collocation")
OBJECTIVES = ("effort", "time")


@dataclass(frozen=True)
class Example:
    """A worked example: angles in degrees, limits per joint, T for minimum effort."""

    title: str
    robot: str
    start: tuple[float, ...]
    goal: tuple[float, ...]
    final_time: float
    torque_limits: tuple[float, ...]
    velocity_limits: tuple[float, ...]
    intervals: int = 40


EXAMPLES = (
    Example(
        "2R swing (examples/arm_2r.toml)",
        str(ROOT / "examples" / "arm_2r.toml"),
        start=(-90, 0),
        goal=(30, 45),
        final_time=1.5,
        torque_limits=(20, 10),
        velocity_limits=(8, 8),
    ),
    Example(
        "PUMA 560 transfer (puma560)",
        "puma560",
        start=(0, 90, -90, 0, 0, 0),
        goal=(90, 45, -135, 45, 45, 90),
        final_time=2.0,
        torque_limits=(100, 180, 90, 25, 20, 20),
        velocity_limits=(3, 3, 3, 3, 3, 3),
    ),
)


def problem(example: Example, objective: str, method: str, **changes):
    from symkin.solve.trajopt import TrajectoryProblem

    return TrajectoryProblem(
        start=tuple(math.radians(v) for v in example.start),
        goal=tuple(math.radians(v) for v in example.goal),
        intervals=example.intervals,
        final_time=example.final_time if objective == "effort" else None,
        objective=objective,
        method=method,
        torque_limits=example.torque_limits,
        velocity_limits=example.velocity_limits,
        tolerance=None,  # the fixed 40-interval mesh; bench/trajopt_peers.py times the refined
        **changes,
    )


# --------------------------------------------------------------------------- peer


def check_peer(model, peer) -> float:
    """Largest relative difference of the peer's ddq from symkin's at random states."""
    import casadi as ca

    from symkin.runtime.modules import generated_casadi_module
    from symkin.solve.evaluate import dynamics_arguments

    ours = generated_casadi_module(model).forward_dynamics_function(ca.SX)
    p = dynamics_arguments(model, {})["p"]
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(20):
        q, dq, tau = rng.normal(size=(3, model.robot.dof))
        a = np.asarray(ours(q, dq, tau, p)).ravel()
        b = np.asarray(peer(q, dq, tau, p)).ravel()
        worst = max(worst, float(np.abs(a - b).max() / max(1.0, np.abs(a).max())))
    if worst > 1e-9:
        raise SystemExit(f"the peer's forward dynamics differ from symkin's by {worst:.2e}")
    return worst


# --------------------------------------------------------------------------- measure


@dataclass
class Row:
    example: Example
    objective: str
    method: str
    trajectories: list = field(default_factory=list)
    replay_error: float | None = None

    @property
    def last(self):
        return self.trajectories[-1]

    def solve_times(self) -> list[float]:
        """Wall seconds of ``Opti.solve`` per solve."""
        return [t.stats.solve_time for t in self.trajectories]

    def cpu_times(self) -> list[float]:
        """CPU seconds of this process during ``Opti.solve`` per solve."""
        return [t.stats.cpu_times[1] for t in self.trajectories]


def replay_error(model, trajectory) -> float:
    """End state of the torques integrated by solve_ivp against the goal at rest."""
    from scipy.integrate import solve_ivp

    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.evaluate import dynamics_arguments

    forward = generated_numpy_module(model).forward_dynamics
    args = dynamics_arguments(model, dict(trajectory.problem.overrides))
    n = model.robot.dof
    state = np.concatenate([trajectory.q[0], trajectory.dq[0]])
    for k, tau in enumerate(trajectory.tau):
        state = solve_ivp(
            lambda _, x, tau=tau: np.concatenate([x[n:], forward(x[:n], x[n:], tau, **args)]),
            (trajectory.t[k], trajectory.t[k + 1]),
            state,
            method="DOP853",
            rtol=1e-10,
            atol=1e-10,
        ).y[:, -1]
    goal = np.concatenate([trajectory.problem.goal, np.zeros(n)])
    return float(np.abs(state - goal).max())


def saturation(trajectory) -> float:
    limits = np.array(trajectory.problem.torque_limits)
    return float(np.mean(np.any(np.abs(trajectory.tau) >= 0.98 * limits, axis=1)))


def progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


def measure(example: Example, repeat: int) -> dict:
    """Every case ``repeat`` times, alternated round by round; the peer's minimum-effort
    multiple-shooting solve right after symkin's in each round."""
    import casadi as ca

    import symkin
    from symkin.runtime.modules import generated_casadi_module, generated_numpy_module
    from symkin.solve.trajopt import optimal_trajectory, robot_functions
    from trajopt_peers import newton_euler_peer

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the PUMA's published link-3 inertia
        model = symkin.derive(symkin.load_robot(example.robot))
    began = time.perf_counter()
    generated_casadi_module(model)
    generated_numpy_module(model)
    setup = time.perf_counter() - began
    ours = robot_functions(model)  # built once, for both contenders alike
    peer_functions = newton_euler_peer(model, ours)
    peer_forward = newton_euler_forward_dynamics(model.robot)
    difference = check_peer(model, peer_forward)
    rows = [Row(example, o, m) for o in OBJECTIVES for m in METHODS]
    peer = Row(example, "effort", "multiple-shooting")
    for k in range(repeat):
        for row in rows:
            case = problem(example, row.objective, row.method)
            row.trajectories.append(optimal_trajectory(model, case, functions=ours))
            progress(
                f"{model.robot.name} {row.objective} {row.method} {k + 1}/{repeat}: "
                f"{row.cpu_times()[-1]:.2f} s CPU, {row.last.stats.iterations} iterations"
            )
            if (row.objective, row.method) == ("effort", "multiple-shooting"):
                peer.trajectories.append(optimal_trajectory(model, case, functions=peer_functions))
                progress(
                    f"{model.robot.name} peer effort {k + 1}/{repeat}: "
                    f"{peer.cpu_times()[-1]:.2f} s CPU"
                )
    for row in rows:
        row.replay_error = replay_error(model, row.last)
    unregularised = optimal_trajectory(
        model, problem(example, "time", "multiple-shooting", regularisation=0.0), functions=ours
    )
    progress(f"{model.robot.name} time without regularisation: T = {unregularised.final_time:.6g}")
    fd = generated_casadi_module(model).forward_dynamics_function(ca.SX)
    instructions = (fd.n_instructions(), peer_forward.n_instructions())
    return {
        "example": example,
        "model": model,
        "setup": setup,
        "rows": rows,
        "unregularised": unregularised,
        "peer": {"difference": difference, "row": peer, "instructions": instructions},
    }


# --------------------------------------------------------------------------- report


def seconds(values: list[float]) -> str:
    """``median (min–max)`` of ``values``, two decimals."""
    median = statistics.median(values)
    if len(values) == 1:
        return f"{median:.2f}"
    return f"{median:.2f} ({min(values):.2f}–{max(values):.2f})"


def plot(results: list[dict]) -> list[Path]:
    from symkin.solve.trajopt.plot import plot_trajectory

    paths = []
    for result in results:
        for row in result["rows"]:
            if row.method == "multiple-shooting":
                name = f"trajopt_{result['model'].robot.name}_{row.objective}.png"
                paths.append(plot_trajectory(row.last, IMAGES / name))
    return paths


def examples_table(results: list[dict]) -> str:
    """The worked examples' results (docs/trajopt.md)."""
    lines = [
        "| example | objective | transcription | IPOPT | iterations | solve CPU [s] | T [s] "
        "| cost | replay error |",
        "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for result in results:
        for row in result["rows"]:
            t = row.last
            cost = f"{t.cost:.6g} N²m²s" if row.objective == "effort" else f"{t.cost:.6g} s"
            lines.append(
                f"| {row.example.title} | {'minimum ' + row.objective} | {row.method} "
                f"| {t.stats.status} | {t.stats.iterations} | {seconds(row.cpu_times())} "
                f"| {t.final_time:.6g} | {cost} | {row.replay_error:.1e} |"
            )
    return "\n".join(lines)


def render(results: list[dict], args: argparse.Namespace, load: tuple[float, float]) -> str:
    import casadi

    lines = [
        measured_line(
            f"Python {platform.python_version()}, CasADi {casadi.__version__} (IPOPT bundled), "
            f"NumPy {version('numpy')}, SciPy {version('scipy')}, symkin {version('symkin')}. "
            "Solve time is `Opti.solve` (CasADi's derivative set-up and IPOPT) in CPU seconds of "
            f"the process and in wall seconds, median (min–max) of {args.repeat} rounds, the "
            "cases and the peer alternated round by round.",
            load,
            "trajopt_time.py",
        ),
        "",
        "### Worked examples (docs/trajopt.md), 40 intervals",
        "",
        "| example | objective | transcription | iterations | solve CPU [s] | solve wall [s] "
        "| T [s] | torque at a limit | replay error |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for result in results:
        for row in result["rows"]:
            t = row.last
            lines.append(
                f"| {row.example.title} | minimum {row.objective} | {row.method} "
                f"| {t.stats.iterations} | {seconds(row.cpu_times())} "
                f"| {seconds(row.solve_times())} | {t.final_time:.6g} "
                f"| {saturation(t):.0%} | {row.replay_error:.1e} |"
            )
    lines += [
        "",
        "Once per robot, before the solves: rendering and loading the generated CasADi and "
        "NumPy dynamics modules took "
        + "; ".join(f"{r['model'].robot.name} {r['setup']:.1f} s" for r in results)
        + " (wall). The replay error is the largest difference between the goal at rest and "
        "the end state of the optimal torques integrated by `solve_ivp` (DOP853, tolerances "
        "1e-10).",
        "",
        "Minimum time, multiple shooting, with the default regularisation 0.01 against none: "
        + "; ".join(
            f"{r['model'].robot.name} T = {_time_row(r).last.final_time:.6g} s against "
            f"{r['unregularised'].final_time:.6g} s "
            f"(+{100 * (_time_row(r).last.final_time / r['unregularised'].final_time - 1):.2f} %)"
            for r in results
        )
        + ".",
        "",
        *_peer_table(results),
    ]
    return "\n".join(lines)


def _peer_table(results: list[dict]) -> list[str]:
    lines = [
        "### Generated forward dynamics against a generic CasADi Newton–Euler",
        "",
        "Minimum effort, multiple shooting, the same problem with the forward dynamics swapped "
        "(`optimal_trajectory(..., functions=...)`, both built once before the solves); each "
        "peer solve runs right after symkin's in the same round. Instructions: "
        "`casadi.Function.n_instructions()` of the forward-dynamics function. The ratios are "
        "symkin's median solve time over the peer's (below 1: symkin is faster), in CPU time "
        "(the figure to compare across runs) and in wall time (which the machine's load moves).",
        "",
        "| example | forward dynamics | instructions | iterations | solve CPU [s] "
        "| solve wall [s] | cost | symkin / peer CPU | symkin / peer wall |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for result in results:
        ours = next(
            r for r in result["rows"] if (r.objective, r.method) == ("effort", "multiple-shooting")
        )
        peer, count = result["peer"]["row"], result["peer"]["instructions"]
        cpu = statistics.median(ours.cpu_times()) / statistics.median(peer.cpu_times())
        wall = statistics.median(ours.solve_times()) / statistics.median(peer.solve_times())
        title = result["example"].title
        lines += [
            f"| {title} | symkin generated (`forward_dynamics_function`) | {count[0]} "
            f"| {ours.last.stats.iterations} | {seconds(ours.cpu_times())} "
            f"| {seconds(ours.solve_times())} | {ours.last.cost:.6g} | 1 | 1 |",
            f"| {title} | generic recursive Newton–Euler in CasADi SX | {count[1]} "
            f"| {peer.last.stats.iterations} | {seconds(peer.cpu_times())} "
            f"| {seconds(peer.solve_times())} | {peer.last.cost:.6g} | {cpu:.2f} | {wall:.2f} |",
        ]
    lines += [
        "",
        "The peer's ddq agreed with symkin's at 20 random states to "
        + ", ".join(f"{r['peer']['difference']:.0e}" for r in results)
        + " (relative).",
    ]
    return lines


def _time_row(result: dict) -> Row:
    return next(
        r for r in result["rows"] if (r.objective, r.method) == ("time", "multiple-shooting")
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, help="rounds: solves per case (3; --quick 2)")
    parser.add_argument("--quick", action="store_true", help="2 rounds")
    parser.add_argument("--no-write", action="store_true", help="print only; no docs, no plots")
    args = parser.parse_args(argv)
    if args.repeat is None:
        args.repeat = 2 if args.quick else 3
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")
    load_start = os.getloadavg()[0]
    results = [measure(example, args.repeat) for example in EXAMPLES]
    table = render(results, args, (load_start, os.getloadavg()[0]))
    examples = examples_table(results)
    print(table)
    print()
    print(examples)
    if not args.no_write:
        write_docs(table, DOCS, MARKERS, "Trajectory optimisation")
        write_docs(examples, EXAMPLE_DOCS, EXAMPLE_MARKERS, "Results")
        for path in plot(results):
            progress(f"wrote {path}")
        progress(f"wrote {DOCS} and {EXAMPLE_DOCS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
