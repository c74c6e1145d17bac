"""The PUMA 560 minimum-effort transfer of docs/trajopt.md on three dynamics implementations,
in one run, alternated: symkin's generated CasADi code, a textbook recursive Newton–Euler
written directly in CasADi from the DH table (``bench/casadi_peer.py``), and adam-robotics'
CasADi dynamics (``adam.casadi.KinDynComputations``, CRBA mass matrix and RNEA bias force)
read from the URDF that ``symkin urdf puma560`` writes.

The problem is the same for all three: 40 intervals, T = 2 s, the docs' torque and velocity
limits, symkin's accuracy control at the default tolerance (1e-4), solved by
:func:`symkin.solve.trajopt.optimal_trajectory` with the robot's functions swapped
(``functions=``): only the dynamics differ.  The URDF has no rotor inertia, so the adam peer
adds the catalogue's reflected rotor inertias ``I_a ddq`` by hand, as a user would.  Each peer
is checked against symkin's inverse dynamics at random states first (the script stops above
1e-9 relative).  Reported: CPU seconds of this process per phase (IPOPT, including CasADi's
derivative set-up; re-simulation), median of ``--repeat`` alternated runs, and the wall time;
the ratio is symkin's IPOPT CPU time over the row's (below 1: symkin is faster).  The machine
is shared: the load average is printed, and CPU time is what it inflates least.  Without
adam-robotics (the ``bench`` extra) its rows say "not installed".

The table goes into ``docs/benchmarks.md`` between ``<!-- trajopt-peers:begin -->`` and
``<!-- trajopt-peers:end -->``.  No test passes or fails on it.

Usage::

    .venv/bin/python bench/trajopt_peers.py                 # 3 repeats, a few minutes
    .venv/bin/python bench/trajopt_peers.py --repeat 1 --no-write
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from casadi_peer import newton_euler_forward_dynamics
from codegen_speed import write_docs
from derivation_time import cpu_model, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
MARKERS = ("<!-- trajopt-peers:begin -->", "<!-- trajopt-peers:end -->")
METHODS = ("inverse-dynamics", "collocation")
START = np.radians([0, 90, -90, 0, 0, 0])
GOAL = np.radians([90, 45, -135, 45, 45, 90])


def puma_problem(method: str):
    from symkin.solve.trajopt import TrajectoryProblem

    return TrajectoryProblem(
        start=START,
        goal=GOAL,
        final_time=2.0,
        intervals=40,
        method=method,
        torque_limits=(100, 180, 90, 25, 20, 20),
        velocity_limits=(3.0,) * 6,
    )


def swapped(ours, inverse, forward):
    """``ours`` with the CasADi dynamics replaced by a peer's ``inverse(q, dq, ddq)`` and
    ``forward(q, dq, tau)`` (one state each; mapped over columns here)."""
    import casadi as ca

    n = ours.dof
    q, dq, v = (ca.SX.sym(name, n) for name in ("q", "dq", "v"))
    inverse_function = ca.Function("peer_id", [q, dq, v], [inverse(q, dq, v)])
    forward_function = ca.Function("peer_fd", [q, dq, v], [forward(q, dq, v)])

    def columns(function):
        def call(a, b, c):
            count = a.shape[1] if len(a.shape) > 1 else 1
            return function(a, b, c) if count == 1 else function.map(count)(a, b, c)

        return call

    return dataclasses.replace(
        ours,
        inverse_dynamics=columns(inverse_function),
        forward_dynamics=columns(forward_function),
        inverse_function=inverse_function,
        forward_function=forward_function,
    )


def newton_euler_peer(model, ours):
    """The generic RNEA of bench/casadi_peer.py: the recursion as the inverse dynamics, and
    its forward dynamics (mass matrix by n unit-acceleration passes, a linear solve)."""
    import casadi as ca

    forward = newton_euler_forward_dynamics(model.robot)
    inverse = newton_euler_forward_dynamics(model.robot, inverse=True)
    p = ca.DM(np.zeros(len(model.robot.parameters)))
    return swapped(ours, lambda a, b, c: inverse(a, b, c, p), lambda a, b, c: forward(a, b, c, p))


def adam_peer(model, ours, urdf: str):
    """adam-robotics' fixed-base dynamics (identity base, zero base velocity): ``tau = M_jj
    ddq + h_j`` plus the rotor inertias; forward by ``solve(M_jj + I_a, tau - h_j)``."""
    import casadi as ca
    from adam.casadi import KinDynComputations

    robot = model.robot
    gravity = np.array([*(float(g) for g in robot.gravity), 0, 0, 0])
    names = [joint.name for joint in robot.joints]
    dynamics = KinDynComputations(urdf, names, gravity=gravity)
    rotor = ca.DM([float(j.link.motor_inertia) for j in robot.joints])
    base, twist = ca.DM.eye(4), ca.DM.zeros(6)

    def parts(q, dq):
        mass = dynamics.mass_matrix(base, q)[6:, 6:] + ca.diag(rotor)
        return mass, dynamics.bias_force(base, q, twist, dq)[6:]

    def inverse(q, dq, ddq):
        mass, bias = parts(q, dq)
        return mass @ ddq + bias

    def forward(q, dq, tau):
        mass, bias = parts(q, dq)
        return ca.solve(mass, tau - bias)

    return swapped(ours, inverse, forward)


def check(ours, peer) -> float:
    """Largest relative difference of the peer's inverse dynamics from symkin's."""
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(20):
        q, dq, ddq = rng.normal(size=(3, ours.dof))
        a = np.asarray(ours.inverse_function(q, dq, ddq)).ravel()
        b = np.asarray(peer.inverse_function(q, dq, ddq)).ravel()
        worst = max(worst, float(np.abs(a - b).max() / max(1.0, np.abs(a).max())))
    if worst > 1e-9:
        raise SystemExit(f"a peer's inverse dynamics differ from symkin's by {worst:.2e}")
    return worst


def measure(repeat: int) -> tuple[dict, dict]:
    """Alternated solves: {(method, implementation): [(ipopt_cpu, check_cpu, wall, cost,
    intervals, consistent)]} and the peers' agreement."""
    import symkin
    from symkin.solve.trajopt import optimal_trajectory, robot_functions

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # link 3's published inertia
        model = symkin.derive(symkin.load_robot("puma560"))
    ours = robot_functions(model)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "puma560.urdf"
        subprocess.run(
            [sys.executable, "-m", "symkin.cli", "urdf", "puma560", "-o", str(path)],
            check=True,
            capture_output=True,
        )
        urdf = str(path)
        implementations = {"symkin": ours, "generic RNEA (CasADi)": newton_euler_peer(model, ours)}
        try:
            implementations["adam-robotics (URDF)"] = adam_peer(model, ours, urdf)
        except ModuleNotFoundError as error:  # the bench extra is not installed
            print(f"adam-robotics: not installed ({error})", file=sys.stderr, flush=True)
        agreement = {name: check(ours, f) for name, f in implementations.items()}
        results: dict = {}
        for round_ in range(repeat):
            for method in METHODS:
                for name, functions in implementations.items():
                    print(f"round {round_ + 1}: {method}, {name}", file=sys.stderr, flush=True)
                    t = optimal_trajectory(model, puma_problem(method), functions=functions)
                    row = (
                        t.stats.cpu_times[1],
                        t.stats.cpu_times[2],
                        t.stats.solve_time + t.stats.build_time + t.stats.check_time,
                        t.cost,
                        len(t.t) - 1,
                        t.consistent,
                    )
                    results.setdefault((method, name), []).append(row)
    return results, agreement


def render(results: dict, agreement: dict, repeat: int, load: tuple[float, float]) -> str:
    today = datetime.date.today().isoformat()
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores shared with other jobs; "
        f"CasADi {version('casadi')}, adam-robotics {version('adam-robotics')}. Load average "
        f"(1 min) at the start and end of the run: {load[0]:.1f} and {load[1]:.1f}. Median of "
        f"{repeat} alternated runs; CPU seconds of the process. Generated by "
        "`bench/trajopt_peers.py`.",
        "",
        "| transcription | dynamics | IPOPT CPU [s] | re-simulation CPU [s] | wall total [s] "
        "| intervals | cost [N²m²s] | consistent to 1e-4 | symkin / this (IPOPT CPU) |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | --- | ---: |",
    ]
    for method in METHODS:
        base = statistics.median(r[0] for r in results[method, "symkin"])
        for name in agreement:
            rows = results[method, name]
            ipopt = statistics.median(r[0] for r in rows)
            lines.append(
                f"| {method} | {name} | {ipopt:.2f} | "
                f"{statistics.median(r[1] for r in rows):.2f} | "
                f"{statistics.median(r[2] for r in rows):.2f} | {rows[-1][4]} | "
                f"{rows[-1][3]:.6g} | {'yes' if rows[-1][5] else 'no'} | {base / ipopt:.2f} |"
            )
        if "adam-robotics (URDF)" not in agreement:
            lines.append(
                f"| {method} | adam-robotics (URDF) | not installed | — | — | — | — | — | — |"
            )
    lines.append("")
    lines.append(
        "Peers' inverse dynamics against symkin's at 20 random states (largest relative "
        "difference): "
        + ", ".join(f"{name} {value:.1e}" for name, value in agreement.items() if value)
        + "."
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, help="alternated rounds (3; --quick 1)")
    parser.add_argument("--quick", action="store_true", help="1 round")
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args(argv)
    if args.repeat is None:
        args.repeat = 1 if args.quick else 3
    start_load = os.getloadavg()[0]
    results, agreement = measure(args.repeat)
    text = render(results, agreement, args.repeat, (start_load, os.getloadavg()[0]))
    print(text)
    if not args.no_write:
        write_docs(text, DOCS, MARKERS)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
