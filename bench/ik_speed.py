"""Inverse kinematics: success rate and time per solve, symkin against Robotics Toolbox.

For the PUMA 560, the UR5 and the Panda, ``--poses`` (default 1000) random reachable targets
are drawn: each target is the pose of random joint values within the limits, each seed other
random joint values within the limits.  Every solver gets the same targets and seeds, one pose at a
time with the solvers interleaved (so machine load falls on all alike), and is judged by the
same check: symkin's forward kinematics of the returned ``q`` must reproduce the target to
1e-9 m and 1e-9 rad, with every joint within its limits.  The solver's own success flag is
reported beside it.

Solvers (``SOLVERS``; add a :class:`Solver` to measure another one):

* symkin ``solve_ik`` (Python, Levenberg–Marquardt, defaults: tolerance 1e-10, up to 30
  random restarts; on the Panda also without the rest-posture preference, which costs extra
  iterations and which the peers do not have);
* symkin ``closed_form_ik`` (Python, all solutions; success when one of them meets the check);
* symkin's generated C solver (``c/<robot>_ik.c``, damped least squares, default options:
  tolerance 1e-10, up to 50 restarts), run by ``bench/ik_c_loop.c`` compiled with ``gcc -O2``
  over the same targets and seeds after the interleaved loop; its times are measured inside C
  (thread CPU time of ``C_LOOP_REPEATS`` identical solves, divided), not around a Python call;
* symkin's generated C closed form (``c/<robot>_ik_closed.c``, all solutions, each checked by
  the generated FK), run the same way by ``bench/ik_closed_loop.c`` on the same targets;
  success as for ``closed_form_ik``;
* Robotics Toolbox ``ik_LM`` (C++) with ``tol=1e-12`` (a threshold on the squared error,
  about the strictest it reaches) and with its default ``1e-6``, and ``ikine_LM`` (Python)
  with ``tol=1e-12``; their default limits of 30 iterations and 100 searches, joint limits
  on.  Their robots are built from symkin's DH table so that all solve the same arm (checked
  to 1e-12 at 20 random configurations before timing);
* Robotics Toolbox ``ikine_a`` (Python, the analytic PUMA 560 solution) for all eight
  configurations, on its ``DH.Puma560()`` with the target lifted by the pedestal.

A second column counts the solutions within 1e-6 m and 1e-6 rad, the accuracy the peers
aim at by default.

Times are CPU time of the timing thread (``time.thread_time_ns``) around one call; medians
and the ratio to symkin's Python solver are reported.  The table goes into
``docs/benchmarks.md`` between ``<!-- ik:begin -->`` and ``<!-- ik:end -->``.

Usage::

    .venv/bin/python bench/ik_speed.py                  # 1000 poses per robot
    .venv/bin/python bench/ik_speed.py --quick          # 100 poses, a first look
    .venv/bin/python bench/ik_speed.py --robots puma560 --no-peers --no-write
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import statistics
import sys
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from derivation_time import cpu_model, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- ik:begin -->"
END = "<!-- ik:end -->"
ROBOTS = ("puma560", "ur5", "panda")
CHECK = 1e-9  # m and rad
LOOSE = 1e-6  # a second, looser check reported beside it
PEER_TOL = 1e-12
# The target for the Python solver's success rate.
SUCCESS_TARGET = 0.995

# A prepared solver: (target 4x4, seed q) -> (q or None, own success flag).
Solve = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray | None, bool]]


@dataclass(frozen=True)
class Solver:
    """One row of the table: ``prepare(model)`` returns the solve function for that robot, or
    ``None`` when the solver does not apply to it (or is not installed: then ``missing``)."""

    name: str
    prepare: Callable[[object], Solve | None]
    reference: bool = False  # the row the ratios refer to
    peer: bool = False  # needs Robotics Toolbox


def symkin_python(rest_posture: str | None) -> Callable[[object], Solve | None]:
    """``solve_ik`` with its defaults; without a rest posture only for redundant arms (on the
    others the posture never applies, so the row would repeat the first)."""
    from symkin.solve.ik.numeric import solve_ik

    def prepare(model) -> Solve | None:
        if rest_posture is None and model.robot.dof <= 6:
            return None

        def solve(target: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, bool]:
            result = solve_ik(model, target, seed, rest_posture=rest_posture)
            return result.q, result.success

        return solve

    return prepare


def symkin_closed_form(model) -> Solve | None:
    from symkin.solve.ik.closed_form import closed_form_ik, has_closed_form

    if not has_closed_form(model.robot):
        return None
    check = success_check(model)

    def solve(target: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray | None, bool]:
        solutions = closed_form_ik(model, target)
        good = [s.q for s in solutions if s.within_limits and check(s.q, target)]
        return (good[0] if good else None), bool(solutions)

    return solve


def rtb_robot(model):
    """A Robotics Toolbox ``DHRobot`` with symkin's DH table, limits, base and tool.

    A tool that only moves along z is folded into the last row's ``d`` of a modified-DH table
    (``Rz(theta) Tz(d)`` then ``Tz(t)`` is ``Rz(theta) Tz(d + t)``), as RTB's own Panda does:
    RTB 1.5's ``ik_LM`` (C++) drops a trailing tool transform and then reports success for
    poses 0.1 m off the Panda's target, while ``fkine`` includes it.
    """
    import roboticstoolbox as rtb
    import sympy as sp
    from spatialmath import SE3

    robot = model.robot
    values = {sp.Symbol(k, real=True): v for k, v in robot.parameter_values().items()}

    def number(value) -> float:
        return float(sp.sympify(value).xreplace(values))

    def matrix(symbolic) -> np.ndarray:
        return np.array(sp.Matrix(symbolic).xreplace(values).evalf(), dtype=float)

    tool = matrix(robot.tool)
    fold = (
        robot.convention == "modified"
        and np.allclose(tool[:3, :3], np.eye(3))
        and (np.allclose(tool[:2, 3], 0))
    )
    kind = rtb.RevoluteDH if robot.convention == "standard" else rtb.RevoluteMDH
    links = []
    for i, joint in enumerate(robot.joints):
        if joint.type != "revolute":
            raise ValueError("only revolute arms are compared")
        d = number(joint.d) + (tool[2, 3] if fold and i == robot.dof - 1 else 0.0)
        links.append(
            kind(
                d=d,
                a=number(joint.a),
                alpha=number(joint.alpha),
                offset=number(joint.theta),
                qlim=list(joint.limits),
            )
        )
    return rtb.DHRobot(
        links,
        name=robot.name,
        base=SE3(matrix(robot.base), check=False),
        tool=SE3(np.eye(4) if fold else tool, check=False),
    )


def rtb_solver(method: str, tol: float) -> Callable[[object], Solve]:
    def prepare(model) -> Solve:
        robot = rtb_robot(model)
        call = robot.ik_LM if method == "ik_LM" else robot.ikine_LM

        def solve(target: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, bool]:
            solution = call(target, q0=seed, tol=tol, joint_limits=True)
            return np.asarray(solution.q, dtype=float), bool(solution.success)

        return solve

    return prepare


def rtb_puma_closed_form(model) -> Solve | None:
    """RTB's analytic PUMA 560 solver ``ikine_a`` for all eight configurations (left/right,
    up/down, flip/no flip).  RTB's ``DH.Puma560()`` stands on a pedestal ``d1``: with
    ``A_1 = Rz(q1) Tz(d1) Rx(90deg)`` and ``Tz`` commuting with ``Rz``, its pose is
    ``Tz(d1)`` times symkin's, so the target is lifted by ``d1`` (checked here)."""
    if model.robot.name != "puma560":
        return None
    import roboticstoolbox as rtb

    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.ik.joints import parameter_vector

    robot = rtb.models.DH.Puma560()
    lift = np.eye(4)
    lift[2, 3] = robot.links[0].d
    fk = generated_numpy_module(model, "kinematics").fk
    q = np.array([0.3, 0.5, -1.0, 0.2, 0.7, -0.4])
    if np.abs(robot.fkine(q).A - lift @ fk(q, parameter_vector(model))).max() > 1e-12:
        raise SystemExit("RTB's DH.Puma560 is not symkin's puma560 on a pedestal")
    configurations = [a + b + c for a in "lr" for b in "ud" for c in "nf"]
    check = success_check(model)

    def solve(target: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray | None, bool]:
        solutions = [robot.ikine_a(lift @ target, config=c) for c in configurations]
        good = [np.asarray(s.q) for s in solutions if s.success and check(np.asarray(s.q), target)]
        return (good[0] if good else None), any(s.success for s in solutions)

    return solve


SOLVERS: list[Solver] = [
    Solver("symkin `solve_ik` (Python, LM)", symkin_python("middle"), reference=True),
    Solver("symkin `solve_ik` (Python, LM), no rest posture", symkin_python(None)),
    Solver("symkin `closed_form_ik` (Python, all solutions)", symkin_closed_form),
    Solver("RTB `ik_LM` (C++), tol 1e-12", rtb_solver("ik_LM", PEER_TOL), peer=True),
    Solver("RTB `ik_LM` (C++), default tol 1e-6", rtb_solver("ik_LM", 1e-6), peer=True),
    Solver("RTB `ikine_LM` (Python), tol 1e-12", rtb_solver("ikine_LM", PEER_TOL), peer=True),
    Solver(
        "RTB `ikine_a` (Python, closed form, 8 configurations)", rtb_puma_closed_form, peer=True
    ),
]
C_LOOP = Path(__file__).resolve().with_name("ik_c_loop.c")
C_LOOP_ROW = "symkin generated C `<robot>_ik` (C loop, gcc -O2)"
C_LOOP_REPEATS = 20  # identical solves per timed block in the C loop
C_CLOSED_LOOP = C_LOOP.with_name("ik_closed_loop.c")
C_CLOSED_ROW = "symkin generated C `<robot>_ik_closed` (C loop, gcc -O2, all solutions)"


def success_check(model, tolerance: float = CHECK) -> Callable[[np.ndarray, np.ndarray], bool]:
    """``check(q, target)``: symkin's FK of ``q`` meets ``target`` to ``tolerance`` in m and in
    rad, and ``q`` is within the limits."""
    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.ik.joints import joint_bounds, parameter_vector

    fk = generated_numpy_module(model, "kinematics").fk
    p = parameter_vector(model)
    lower, upper = joint_bounds(model)

    def check(q: np.ndarray, target: np.ndarray) -> bool:
        if q is None or not np.all(np.isfinite(q)):
            return False
        if np.any(q < lower - 1e-12) or np.any(q > upper + 1e-12):
            return False
        T = fk(q, p)
        relative = target[:3, :3].T @ T[:3, :3]
        skew = relative - relative.T
        angle = math.atan2(
            0.5 * math.sqrt(0.5 * float(np.sum(skew * skew))), (np.trace(relative) - 1) / 2
        )
        return bool(np.linalg.norm(T[:3, 3] - target[:3, 3]) < tolerance and angle < tolerance)

    return check


@dataclass
class Row:
    name: str
    times_ns: list[int] = field(default_factory=list)
    ok: int = 0
    loose: int = 0
    own_flag: int = 0

    @property
    def count(self) -> int:
        return len(self.times_ns)


def poses(model, count: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``count`` (target, seed) pairs from random joint values within the limits."""
    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.ik.joints import parameter_vector, random_configuration

    rng = np.random.default_rng(seed)
    fk = generated_numpy_module(model, "kinematics").fk
    p = parameter_vector(model)
    return [
        (fk(random_configuration(model, rng), p), random_configuration(model, rng))
        for _ in range(count)
    ]


def check_same_arm(model, solver_name: str) -> float:
    """Largest pose difference between symkin's FK and the RTB robot's at 20 random q."""
    from symkin.runtime.modules import generated_numpy_module
    from symkin.solve.ik.joints import parameter_vector, random_configuration

    robot = rtb_robot(model)
    fk = generated_numpy_module(model, "kinematics").fk
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(20):
        q = random_configuration(model, rng)
        worst = max(worst, float(np.abs(robot.fkine(q).A - fk(q, parameter_vector(model))).max()))
    if worst > 1e-12:
        raise SystemExit(f"{solver_name}: its {model.robot.name} differs from symkin's by {worst}")
    return worst


def measure(name: str, count: int, seed: int, peers: bool) -> list[Row]:
    import symkin
    from symkin.kernels import kinematics_kernels

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the PUMA file's lumped-inertia warning
        model = symkin.derive(symkin.load_robot(name))
    check, loose = success_check(model), success_check(model, LOOSE)
    prepared: list[tuple[Row, Solve]] = []
    for solver in SOLVERS:
        if solver.peer:
            if not peers or version("roboticstoolbox-python") == "not installed":
                continue
            check_same_arm(model, solver.name)
        solve = solver.prepare(model)
        if solve is not None:
            prepared.append((Row(solver.name), solve))
    pairs = poses(model, count, seed)
    for _, solve in prepared:  # warm up caches and generated modules outside the timing
        solve(*pairs[0])
    for k, (target, start) in enumerate(pairs):
        for row, solve in prepared:
            begin = time.thread_time_ns()
            q, flag = solve(target, start)
            row.times_ns.append(time.thread_time_ns() - begin)
            row.ok += check(q, target)
            row.loose += loose(q, target)
            row.own_flag += flag
        if (k + 1) % 100 == 0:
            print(f"  {name}: {k + 1}/{count} poses", file=sys.stderr, flush=True)
    kernels = kinematics_kernels(model)
    rows = [row for row, _ in prepared] + [c_loop_row(model, kernels, pairs, check, loose)]
    closed = c_closed_loop_row(model, kernels, pairs, check, loose)
    return rows + ([closed] if closed is not None else [])


def run_c_loop(
    robot, files: dict[str, str], driver: Path, header: tuple[str, str], problems: list[str]
) -> str:
    """Stdout of ``driver`` run on ``problems``: the generated ``files`` written into a
    temporary directory, compiled with ``gcc -O2`` (each file its own translation unit) with
    the solver named by ``header`` (macro, file stem), fed the problems on stdin."""
    import subprocess
    import tempfile

    macro, solver = header
    with tempfile.TemporaryDirectory() as directory:
        root = Path(directory)
        for relative, text in files.items():
            (root / Path(relative).name).write_text(text)
        command = [
            "gcc", "-std=c99", "-O2", f"-DROBOT={robot.name}",
            f"-DROBOT_MACRO={robot.name.upper()}", f'-D{macro}="{solver}.h"',
            f"-I{root}", "-o", str(root / "loop"), str(driver),
            str(root / f"{solver}.c"), str(root / f"{robot.name}.c"), "-lm",
        ]  # fmt: skip
        subprocess.run(command, check=True)
        return subprocess.run(
            [str(root / "loop"), str(C_LOOP_REPEATS)],
            input="\n".join(problems) + "\n",
            capture_output=True,
            text=True,
            check=True,
        ).stdout


def c_loop_row(
    model,
    kernels: tuple,
    pairs: list[tuple[np.ndarray, np.ndarray]],
    check: Callable[..., bool],
    loose: Callable[..., bool],
) -> Row:
    """The generated C solver over ``pairs`` in ``bench/ik_c_loop.c``, on the robot's C
    kinematics ``kernels``."""
    from symkin.emit.c import emit_c
    from symkin.emit.ik_c import emit_ik_c

    robot = model.robot
    problems = [f"{len(pairs)} {robot.dof}"]
    problems += [" ".join(map(repr, [*t.ravel().tolist(), *s.tolist()])) for t, s in pairs]
    files = {**emit_c(robot, kernels), **emit_ik_c(robot, kernels)}
    header = ("ROBOT_IK_HEADER", f"{robot.name}_ik")
    output = run_c_loop(robot, files, C_LOOP, header, problems)
    row = Row(C_LOOP_ROW.replace("<robot>", robot.name))
    for line, (target, _) in zip(output.splitlines(), pairs, strict=True):
        status, _, _, ns, *q = line.split()
        row.times_ns.append(round(float(ns)))
        q = np.array([float(v) for v in q])
        row.ok += check(q, target)
        row.loose += loose(q, target)
        row.own_flag += status == "0"
    return row


def c_closed_loop_row(
    model,
    kernels: tuple,
    pairs: list[tuple[np.ndarray, np.ndarray]],
    check: Callable[..., bool],
    loose: Callable[..., bool],
) -> Row | None:
    """The generated closed form over the targets of ``pairs`` in ``bench/ik_closed_loop.c``,
    or None without one.  Success as for ``closed_form_ik``: the first solution within the
    limits that meets the check."""
    from symkin.emit.c import emit_c
    from symkin.emit.ik_closed_c import emit_ik_closed_c

    robot = model.robot
    closed = emit_ik_closed_c(robot, kernels)
    if not closed:
        return None
    problems = [f"{len(pairs)} {robot.dof}"]
    problems += [" ".join(map(repr, t.ravel().tolist())) for t, _ in pairs]
    header = ("ROBOT_IK_CLOSED_HEADER", f"{robot.name}_ik_closed")
    output = run_c_loop(
        robot, {**emit_c(robot, kernels), **closed}, C_CLOSED_LOOP, header, problems
    )
    row = Row(C_CLOSED_ROW.replace("<robot>", robot.name))
    for line, (target, _) in zip(output.splitlines(), pairs, strict=True):
        count, ns, *values = line.split()
        row.times_ns.append(round(float(ns)))
        solutions = np.array([float(v) for v in values]).reshape(int(count), robot.dof + 2)
        good = [s[2:] for s in solutions if s[1] == 1 and check(s[2:], target)]
        row.ok += bool(good)
        row.loose += bool(good) and loose(good[0], target)
        row.own_flag += int(count) > 0
    return row


def time_text(ns: float) -> str:
    if ns < 1e4:  # the C rows: a few microseconds
        return f"{ns / 1e3:.1f} us"
    return f"{ns / 1e3:,.0f} us" if ns < 1e7 else f"{ns / 1e6:,.1f} ms"


def render(results: dict[str, list[Row]], args: argparse.Namespace, load: tuple) -> str:
    today = datetime.date.today().isoformat()
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, NumPy {version('numpy')}, symkin {version('symkin')}, "
        f"roboticstoolbox-python {version('roboticstoolbox-python')}. {args.poses} random "
        f"reachable poses per robot (seed {args.seed}), solvers interleaved pose by pose; "
        "thread CPU time per solve. Load average (1 min) at the start and end of the run: "
        f"{load[0]:.1f} and {load[1]:.1f}. Generated by `bench/ik_speed.py`.",
    ]
    for name, rows in results.items():
        reference_name = next(s.name for s in SOLVERS if s.reference)
        reference = next((r for r in rows if r.name == reference_name), None)
        base = statistics.median(reference.times_ns) if reference else None
        lines += [
            "",
            f"### {name}",
            "",
            "| solver | success: FK within 1e-9 m and 1e-9 rad, within limits | "
            "within 1e-6 | own success flag | median time per solve | ratio |",
            "| --- | ---: | ---: | ---: | ---: | ---: |",
        ]
        for row in rows:
            median = statistics.median(row.times_ns)
            ratio = f"{median / base:.2g}x" if base else "—"
            lines.append(
                f"| {row.name} | {100 * row.ok / row.count:.1f} % | "
                f"{100 * row.loose / row.count:.1f} % | {100 * row.own_flag / row.count:.1f} % | "
                f"{time_text(median)} | {ratio} |"
            )
        if reference is not None:
            rate = reference.ok / reference.count
            verdict = "met" if rate >= SUCCESS_TARGET else "NOT met"
            lines += [
                "",
                f"Target: success at least {100 * SUCCESS_TARGET:g} % with restarts: "
                f"{100 * rate:.1f} %, {verdict}.",
            ]
    return "\n".join(lines)


def write_docs(table: str, path: Path) -> None:
    """Put ``table`` between the markers in ``path``."""
    text = path.read_text()
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{path} has no {BEGIN} ... {END} section")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    path.write_text(f"{head}{BEGIN}\n{table}\n{END}{tail}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--poses", type=int, default=1000, help="poses per robot (1000)")
    parser.add_argument("--quick", action="store_true", help="100 poses per robot")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=ROBOTS)
    parser.add_argument("--seed", type=int, default=2024)
    parser.add_argument("--no-peers", action="store_true", help="skip Robotics Toolbox")
    parser.add_argument("--docs", type=Path, default=DOCS)
    parser.add_argument("--no-write", action="store_true", help="only print the table")
    args = parser.parse_args(argv)
    if args.quick:
        args.poses = 100
    load_start = os.getloadavg()[0]
    results = {
        name: measure(name, args.poses, args.seed, not args.no_peers) for name in args.robots
    }
    table = render(results, args, (load_start, os.getloadavg()[0]))
    print(table)
    if not args.no_write:
        write_docs(table, args.docs)
        print(f"wrote {args.docs}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
