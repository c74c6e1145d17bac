"""Inverse kinematics: success rate, time per solve and peak memory, symkin against Robotics
Toolbox, each table comparing calls made from the same language.

For the PUMA 560, the UR5 and the Panda, ``--poses`` (default 1000) random reachable targets
are drawn: each target is the pose of random joint values within the limits, each seed other
random joint values within the limits, so every solve is of a distinct pose.  Every solver gets
the same targets and seeds, alternated round by round: in each round of ``--round`` poses
(10) every solver in turn solves them, in an order that rotates from round to round, so machine
load falls on all alike; ``--round 1`` alternates pose by pose.  Each solver is judged by the
same checks on symkin's forward kinematics of the returned ``q`` (every joint within its
limits): to 1e-9 m and 1e-9 rad, and by Robotics Toolbox's own stopping rule
``E = e^T e / 2 < tol`` (``e``: position error and rotation vector, RTB ``ik.cpp``) for its
``tol=1e-12`` (``|e|`` below about 1.4e-6) and its default ``tol=1e-6`` (about 1.4e-3).  The
solver's own success flag is reported beside them.

Table 1, Python calls (``SOLVERS``; add a :class:`Solver` to measure another one):

* symkin ``solve_ik``: by default (``backend="auto"``) the generated C solver through the
  CPython extension (damped least squares, tolerance 1e-10, up to 30 random restarts); without
  the rest posture (which only redundant arms have, and the peers do not do), and on the Panda
  also with it; the same algorithm in NumPy (``backend="numpy"``, the fallback without a
  compiler) and the general Python solver (``backend="python"``);
* symkin ``closed_form_ik`` (Python, all solutions; success when one of them meets the check);
* Robotics Toolbox ``ik_LM`` (C++ called from Python) with ``tol=1e-12`` and with its default
  ``1e-6``, and ``ikine_LM`` (Python) with ``tol=1e-12``; their default limits of 30 iterations
  and 100 searches, joint limits on.  Their robots are built from symkin's DH table so that all
  solve the same arm (checked to 1e-12 at 20 random configurations before timing);
* Robotics Toolbox ``ikine_a`` (Python, the analytic PUMA 560 solution) for all eight
  configurations, on its ``DH.Puma560()`` with the target lifted by the pedestal.

Times are CPU time of the timing thread (``time.thread_time_ns``) around one call; medians and
the ratio symkin ``solve_ik`` / solver (below 1: symkin is faster) are reported.  Peak memory:
each solver runs again alone in a child process (derive, build, solve ``MEMORY_POSES`` poses)
that reports its own peak resident set (``VmHWM``), beside a child that only derives the model.

Table 2, C loops: symkin's generated C solvers (``c/<robot>_ik.c``, default options, and
``c/<robot>_ik_closed.c``, all solutions) run by ``bench/ik_c_loop.c`` and
``bench/ik_closed_loop.c`` (``gcc -O2``) over the same targets and seeds, each pose solved once
and timed alone by the thread CPU clock.  No peer has a C-callable solver here, so this table
has no peer row; it shows what the Python call adds.

The tables go into ``docs/benchmarks.md`` between ``<!-- ik:begin -->`` and ``<!-- ik:end -->``
with the machine and the load average (1 min) at the start and end of each robot's run.

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
PEER_TOL = 1e-12
PEER_DEFAULT_TOL = 1e-6  # RTB's default tol
MEMORY_POSES = 50  # poses solved by each child that measures peak memory
# Poses each solver solves in turn per round: a user's loop of calls, not one call between
# another library's (which leaves the caches cold for the short calls; see --round 1).
ROUND = 10
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


def symkin_python(
    rest_posture: str | None, backend: str = "auto", redundant_only: bool = False
) -> Callable[[object], Solve | None]:
    """``solve_ik`` with its defaults but ``rest_posture`` and ``backend``; with
    ``redundant_only`` only for arms with more joints than task rows (elsewhere the rest
    posture never applies, so the row would repeat another)."""
    from symkin.solve.ik.numeric import solve_ik

    def prepare(model) -> Solve | None:
        if redundant_only and model.robot.dof <= 6:
            return None

        def solve(target: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, bool]:
            result = solve_ik(model, target, seed, rest_posture=rest_posture, backend=backend)
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
    Solver("symkin `solve_ik` (generated C via the extension)", symkin_python(None), True),
    Solver(
        "symkin `solve_ik`, default rest posture `middle` (null-space moves in Python)",
        symkin_python("middle", redundant_only=True),
    ),
    Solver('symkin `solve_ik`, `backend="numpy"` (fallback)', symkin_python(None, "numpy")),
    Solver('symkin `solve_ik`, `backend="python"` (general LM)', symkin_python(None, "python")),
    Solver("symkin `closed_form_ik` (Python, all solutions)", symkin_closed_form),
    Solver("RTB `ik_LM` (C++ from Python), tol 1e-12", rtb_solver("ik_LM", PEER_TOL), peer=True),
    Solver(
        "RTB `ik_LM` (C++ from Python), default tol 1e-6",
        rtb_solver("ik_LM", PEER_DEFAULT_TOL),
        peer=True,
    ),
    Solver("RTB `ikine_LM` (Python), tol 1e-12", rtb_solver("ikine_LM", PEER_TOL), peer=True),
    Solver(
        "RTB `ikine_a` (Python, closed form, 8 configurations)", rtb_puma_closed_form, peer=True
    ),
]
C_LOOP = Path(__file__).resolve().with_name("ik_c_loop.c")
C_LOOP_ROW = "symkin generated C `<robot>_ik` (C loop, gcc -O2)"
C_LOOP_REPEATS = 1  # each pose solved once, timed alone (no repeated solves of one pose)
C_CLOSED_LOOP = C_LOOP.with_name("ik_closed_loop.c")
C_CLOSED_ROW = "symkin generated C `<robot>_ik_closed` (C loop, gcc -O2, all solutions)"


def success_check(
    model, tolerance: float = CHECK, peer_tol: float | None = None
) -> Callable[[np.ndarray, np.ndarray], bool]:
    """``check(q, target)``: ``q`` is within the limits and symkin's FK of ``q`` meets
    ``target`` to ``tolerance`` in m and in rad, or, with ``peer_tol``, by Robotics Toolbox's
    stopping rule ``(|p_t - p|^2 + angle^2) / 2 < peer_tol``."""
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
        position = float(np.linalg.norm(T[:3, 3] - target[:3, 3]))
        if peer_tol is not None:
            return (position**2 + angle**2) / 2 < peer_tol
        return position < tolerance and angle < tolerance

    return check


CHECK_COLUMNS = (
    "FK within 1e-9 m and 1e-9 rad",
    "RTB rule, tol 1e-12 (about 1.4e-6)",
    "RTB rule, tol 1e-6 (about 1.4e-3)",
)


def checks(model) -> tuple[Callable[[np.ndarray, np.ndarray], bool], ...]:
    """The checks of ``CHECK_COLUMNS``, in that order."""
    return (
        success_check(model),
        success_check(model, peer_tol=PEER_TOL),
        success_check(model, peer_tol=PEER_DEFAULT_TOL),
    )


@dataclass
class Row:
    name: str
    times_ns: list[int] = field(default_factory=list)
    passed: list[int] = field(default_factory=lambda: [0] * len(CHECK_COLUMNS))
    own_flag: int = 0
    peak_mb: float | None = None

    def judge(self, q: np.ndarray | None, target: np.ndarray, tests: tuple) -> None:
        for k, test in enumerate(tests):
            self.passed[k] += test(q, target)

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


def load_model(name: str):
    import symkin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the PUMA file's lumped-inertia warning
        return symkin.derive(symkin.load_robot(name))


def prepared_solvers(model, peers: bool) -> list[tuple[int, Row, Solve]]:
    """(index into SOLVERS, row, solve) for every solver that applies to ``model``."""
    prepared = []
    for index, solver in enumerate(SOLVERS):
        if solver.peer:
            if not peers or version("roboticstoolbox-python") == "not installed":
                continue
            check_same_arm(model, solver.name)
        solve = solver.prepare(model)
        if solve is not None:
            prepared.append((index, Row(solver.name), solve))
    return prepared


def measure(
    name: str, count: int, seed: int, peers: bool, round_size: int
) -> tuple[list[Row], list[Row]]:
    """The Python-call rows (with their peak memory) and the C-loop rows of one robot: each
    round, every solver in turn solves the round's ``round_size`` poses."""
    from symkin.kernels import kinematics_kernels

    model = load_model(name)
    tests = checks(model)
    prepared = prepared_solvers(model, peers)
    pairs = poses(model, count, seed)
    for _, _, solve in prepared:  # build extensions and generated modules outside the timing
        solve(*pairs[0])
    for k, first in enumerate(range(0, count, round_size)):
        shift = k % len(prepared)  # the order rotates: no solver always runs first
        for _, row, solve in prepared[shift:] + prepared[:shift]:
            for target, start in pairs[first : first + round_size]:
                begin = time.thread_time_ns()
                q, flag = solve(target, start)
                row.times_ns.append(time.thread_time_ns() - begin)
                row.judge(q, target, tests)
                row.own_flag += flag
        if (k + 1) % max(1, 100 // round_size) == 0:
            print(f"  {name}: {first + round_size}/{count} poses", file=sys.stderr, flush=True)
    baseline = Row("(no solver: Python, symkin, the derived model and the targets)")
    baseline.peak_mb = child_peak_mb(name, -1, seed, peers)
    for index, row, _ in prepared:
        row.peak_mb = child_peak_mb(name, index, seed, peers)
    kernels = kinematics_kernels(model)
    c_rows = [c_loop_row(model, kernels, pairs, tests)]
    closed = c_closed_loop_row(model, kernels, pairs, tests)
    return [row for _, row, _ in prepared] + [baseline], c_rows + ([closed] if closed else [])


def child_peak_mb(name: str, index: int, seed: int, peers: bool) -> float:
    """Peak resident memory (MB) of a child that derives ``name`` and solves
    ``MEMORY_POSES`` poses with ``SOLVERS[index]`` alone (``-1``: no solver)."""
    import subprocess

    command = [sys.executable, __file__, "--memory-child", name, str(index), str(seed)]
    command += [] if peers else ["--no-peers"]
    out = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    return float(out.split()[-1])


def memory_child(name: str, index: int, seed: int, peers: bool) -> None:
    """The child of :func:`child_peak_mb`: prints its own peak RSS in MB."""
    from derivation_time import peak_rss_mb

    model = load_model(name)
    pairs = poses(model, MEMORY_POSES, seed)
    if index >= 0:
        solver = SOLVERS[index]
        if solver.peer:
            check_same_arm(model, solver.name)
        solve = solver.prepare(model)
        for target, start in pairs:
            solve(target, start)
    print(f"{peak_rss_mb():.1f}")


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
    model, kernels: tuple, pairs: list[tuple[np.ndarray, np.ndarray]], tests: tuple
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
        row.judge(np.array([float(v) for v in q]), target, tests)
        row.own_flag += status == "0"
    return row


def c_closed_loop_row(
    model, kernels: tuple, pairs: list[tuple[np.ndarray, np.ndarray]], tests: tuple
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
        within = [s[2:] for s in solutions if s[1] == 1]
        for k, test in enumerate(tests):  # one solution within the limits that passes
            row.passed[k] += any(test(q, target) for q in within)
        row.own_flag += int(count) > 0
    return row


def time_text(ns: float) -> str:
    if ns < 1e4:  # the C rows: a few microseconds
        return f"{ns / 1e3:.1f} us"
    return f"{ns / 1e3:,.0f} us" if ns < 1e7 else f"{ns / 1e6:,.1f} ms"


def percent(passed: int, row: Row) -> str:
    return f"{100 * passed / row.count:.1f} %"


def python_table(rows: list[Row]) -> tuple[list[str], Row]:
    """Table 1 of one robot and its reference row (symkin ``solve_ik``)."""
    reference_name = next(s.name for s in SOLVERS if s.reference)
    reference = next(r for r in rows if r.name == reference_name)
    base = statistics.median(reference.times_ns)
    lines = [
        "| solver | " + " | ".join(CHECK_COLUMNS) + " | own success flag | median CPU time per "
        "solve | symkin `solve_ik` / solver | peak RSS (own process) |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for row in rows:
        if not row.times_ns:  # the memory baseline
            cells = " — |" * (len(CHECK_COLUMNS) + 3)
            lines.append(f"| {row.name} |{cells} {row.peak_mb:.0f} MB |")
            continue
        median = statistics.median(row.times_ns)
        lines.append(
            f"| {row.name} | {' | '.join(percent(p, row) for p in row.passed)} | "
            f"{percent(row.own_flag, row)} | {time_text(median)} | {base / median:.3g} | "
            f"{row.peak_mb:.0f} MB |"
        )
    return lines, reference


def verdicts(rows: list[Row], reference: Row) -> list[str]:
    """The issue's aim for each ``ik_LM`` row: symkin at least 10x faster at equal or better
    success on every check."""
    base = statistics.median(reference.times_ns)
    lines = []
    for row in rows:
        if not row.name.startswith("RTB `ik_LM`"):
            continue
        ratio = base / statistics.median(row.times_ns)
        equal = all(a >= b for a, b in zip(reference.passed, row.passed, strict=True))
        verdict = "met" if ratio <= 0.1 and equal else "NOT met"
        lines.append(
            f"- symkin `solve_ik` / {row.name}: time ratio {ratio:.3g} "
            f"({1 / ratio:.1f}x faster), success "
            + ", ".join(
                f"{percent(a, reference)} vs {percent(b, row)}"
                for a, b in zip(reference.passed, row.passed, strict=True)
            )
            + f" (columns in order): aim of at least 10x at equal or better success {verdict}."
        )
    return lines


def c_table(rows: list[Row], python_median: float) -> list[str]:
    lines = [
        "| solver | " + " | ".join(CHECK_COLUMNS) + " | own success flag | median CPU time per "
        "solve |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for row in rows:
        lines.append(
            f"| {row.name} | {' | '.join(percent(p, row) for p in row.passed)} | "
            f"{percent(row.own_flag, row)} | {time_text(statistics.median(row.times_ns))} |"
        )
    c_median = statistics.median(rows[0].times_ns)
    lines += [
        "",
        f"The Python call of `solve_ik` costs {time_text(python_median - c_median)} more than "
        f"the C solve alone (medians {time_text(python_median)} and {time_text(c_median)}).",
    ]
    return lines


def render(results: dict, args: argparse.Namespace) -> str:
    today = datetime.date.today().isoformat()
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, NumPy {version('numpy')}, symkin {version('symkin')}, "
        f"roboticstoolbox-python {version('roboticstoolbox-python')}. {args.poses} random "
        f"reachable poses per robot (seed {args.seed}), each solved once per solver; rounds of "
        f"{args.round} poses, in which every solver in turn (in an order that rotates from round "
        "to round) solves the round's poses; thread CPU time per solve; peak RSS of a "
        f"child process that solves {MEMORY_POSES} poses with that solver alone. "
        "Generated by `bench/ik_speed.py`.",
    ]
    for name, (python_rows, c_rows, load) in results.items():
        table, reference = python_table(python_rows)
        lines += [
            "",
            f"### {name}",
            "",
            f"Load average (1 min) at the start and end of this robot's run: {load[0]:.1f} and "
            f"{load[1]:.1f} (2 cores shared with other work).",
            "",
            "Python calls:",
            "",
            *table,
            "",
            *verdicts(python_rows, reference),
            "",
            "C loops (symkin's generated C alone; no peer offers a C solver to loop over):",
            "",
            *c_table(c_rows, statistics.median(reference.times_ns)),
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
    parser.add_argument(
        "--round", type=int, default=ROUND, help=f"poses per round and solver ({ROUND})"
    )
    parser.add_argument("--no-peers", action="store_true", help="skip Robotics Toolbox")
    parser.add_argument("--docs", type=Path, default=DOCS)
    parser.add_argument("--no-write", action="store_true", help="only print the table")
    parser.add_argument("--memory-child", nargs=3, metavar=("ROBOT", "SOLVER", "SEED"),
                        help=argparse.SUPPRESS)  # fmt: skip
    args = parser.parse_args(argv)
    if args.memory_child:
        name, index, seed = args.memory_child
        memory_child(name, int(index), int(seed), not args.no_peers)
        return 0
    if args.quick:
        args.poses = 100
    results = {}
    for name in args.robots:
        start = os.getloadavg()[0]
        python_rows, c_rows = measure(name, args.poses, args.seed, not args.no_peers, args.round)
        results[name] = (python_rows, c_rows, (start, os.getloadavg()[0]))
    table = render(results, args)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs)
        print(f"wrote {args.docs}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
