"""The ``symkin`` command: a thin layer over the public API.

User mistakes (bad files, bad values) print one ``symkin: error: ...`` line and exit with
status 2; they never show a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import sympy as sp

from symkin.derive import Model, derive
from symkin.derive.kinematics import joint_dh_values
from symkin.derive.lagrange import READABLE_DOF
from symkin.emit.c import PRECISIONS
from symkin.emit.latex import (
    DEFAULT_SECTIONS,
    LANGUAGES,
    SECTIONS,
    TEXT_WIDTH_CM,
    check_sections,
    latex_files,
)
from symkin.emit.python_ext import extension_name
from symkin.errors import SymkinError
from symkin.generate import (
    BACKENDS,
    check_backends,
    files_for_robot,
    generate_catalogue,
)
from symkin.io import catalogue_names, load_robot
from symkin.output_folder import write_folder
from symkin.robot import Robot
from symkin.runtime.extension import build_extension
from symkin.runtime.latex_build import compile_pdf
from symkin.solve.evaluate import DynamicState, KinematicState, dynamic_state, kinematic_state
from symkin.solve.ik.numeric import DEFAULT_RESTARTS, DEFAULT_TOLERANCE, METHODS, IKResult, solve_ik
from symkin.solve.ik.path import (
    CartesianPath,
    NewtonPath,
    follow_path,
    newton_path_table,
    path_table_json,
    path_table_text,
)
from symkin.solve.ik.plot import plot_path, plot_solutions
from symkin.solve.ik.solutions import SolutionSet, all_solutions
from symkin.solve.ik.target import pose_from_target
from symkin.solve.trajopt import (
    OBJECTIVES,
    TRANSCRIPTIONS,
    TrajectoryProblem,
    check_problem,
    optimal_trajectory,
    summary_text,
    write_trajectory,
)
from symkin.text import KEPT, printable

DEFAULT_ROBOT = "scara"
# Every command stops with an error past this (no hang); the largest catalogue derivation
# takes well under a minute, a generic 6R arm about five.
DEFAULT_TIME_LIMIT = 900.0
MAX_TIME_LIMIT = 1e7
# Options whose values may start with a minus sign ("--q -30deg,45deg").
VALUE_OPTIONS = frozenset(
    {
        "--q",
        "--dq",
        "--ddq",
        "--set",
        "--point",
        "--task",
        "--target",
        "--q0",
        "--path-from",
        "--to",
        "--from",
        "--cartesian-goal",
    }
)
# Task rows written without commas: "xy", "xyz", "xywz".
COMPACT_ROWS = re.compile(r"(?:w?[xyz])+")


# ---------------------------------------------------------------- value parsing


def number_from_text(text: str, what: str) -> float:
    """A float from ``"0.5"``, ``"-30deg"`` or ``"pi/2"``-free plain numbers."""
    raw = text.strip()
    scale = 1.0
    if raw.endswith("deg"):
        raw, scale = raw[: -len("deg")], math.pi / 180
    try:
        value = float(raw)
    except ValueError:
        raise SymkinError(f"{what}: expected a number such as 0.5 or 30deg, got {text!r}") from None
    if not math.isfinite(value):
        raise SymkinError(f"{what}: expected a finite number, got {text!r}")
    return value * scale


def time_limit_from_text(text: str) -> float:
    """Seconds for ``--time-limit``: a finite number from 0 (no limit) to about four months."""
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not 0 <= seconds <= MAX_TIME_LIMIT:
        raise argparse.ArgumentTypeError(
            f"expected seconds from 0 (no limit) to {MAX_TIME_LIMIT:g}, got {text!r}"
        )
    return seconds


def seed_from_text(text: str) -> int:
    """A random seed: a whole number >= 0 (what NumPy's generators accept)."""
    try:
        seed = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}") from None
    if seed < 0:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, got {text!r}")
    return seed


def joint_values(text: str, option: str, robot: Robot) -> list[float]:
    """One value per joint from ``"v1,v2,..."``; ``deg`` only for revolute joints."""
    parts = text.split(",")
    if len(parts) != robot.dof:
        raise SymkinError(
            f"{option}: {robot.name} has {robot.dof} joints, got {len(parts)} value(s) in {text!r}"
        )
    values = []
    for i, (part, joint) in enumerate(zip(parts, robot.joints, strict=True), start=1):
        if part.strip().endswith("deg") and joint.type == "prismatic":
            raise SymkinError(f"{option}: joint {i} is prismatic; give a length, not {part!r}")
        values.append(number_from_text(part, f"{option} joint {i}"))
    return values


def parameter_overrides(items: Sequence[str]) -> dict[str, float]:
    """``["L1=0.3", ...]`` as a dict."""
    overrides = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise SymkinError(f"--set: expected NAME=VALUE, got {item!r}")
        overrides[name.strip()] = number_from_text(value, f"--set {name.strip()}")
    return overrides


def point_from_text(text: str, robot: Robot) -> tuple[int, list[float]]:
    """``"LINK:X,Y,Z"`` as ``(link, [x, y, z])``."""
    link_text, sep, coordinates = text.partition(":")
    try:
        link = int(link_text)
    except ValueError:
        link = -1
    if not sep or not 0 <= link <= robot.dof:
        raise SymkinError(
            f"--point: expected LINK:X,Y,Z with LINK from 0 to {robot.dof}, got {text!r}"
        )
    values = coordinates.split(",")
    if len(values) != 3:
        raise SymkinError(f"--point: expected three coordinates X,Y,Z, got {coordinates!r}")
    if any(v.strip().endswith("deg") for v in values):
        raise SymkinError(f"--point: coordinates are lengths in metres, got {coordinates!r}")
    return link, [number_from_text(v, "--point") for v in values]


def task_rows_from_text(text: str | None) -> tuple[str, ...] | None:
    """``"x,y,wz"`` (or ``"xywz"``) as a tuple of row names (validated by the model)."""
    if text is None:
        return None
    rows = tuple(part.strip() for part in text.split(",") if part.strip())
    if len(rows) == 1 and COMPACT_ROWS.fullmatch(rows[0]):
        rows = tuple(re.findall(r"w?[xyz]", rows[0]))
    if not rows:
        raise SymkinError(f"--task: name at least one row of x, y, z, wx, wy, wz, got {text!r}")
    return rows


def target_from_text(text: str, option: str) -> list[float]:
    """``x,y``, ``x,y,z`` or ``x,y,z,rx,ry,rz``: metres, then Z-Y-X Euler angles (rad or deg)."""
    parts = text.split(",")
    if len(parts) not in (2, 3, 6):
        raise SymkinError(
            f"{option}: expected x,y or x,y,z or x,y,z,rx,ry,rz (Z-Y-X Euler angles), "
            f"got {len(parts)} value(s) in {text!r}"
        )
    for part in parts[:3]:
        if part.strip().endswith("deg"):
            raise SymkinError(f"{option}: x, y, z are lengths in metres, got {part.strip()!r}")
    return [number_from_text(part, option) for part in parts]


def limit_values(text: str | None, option: str, robot: Robot, rates: bool) -> list[float] | None:
    """Per-joint limits from ``"v"`` (the same for every joint) or ``"v1,v2,..."``.

    Velocities (``rates``) take ``deg`` (deg/s) for revolute joints; torques and forces do not.
    """
    if text is None:
        return None
    if not rates and "deg" in text:
        raise SymkinError(f"{option}: torques and forces are plain numbers (N m, N), got {text!r}")
    return joint_values(text if "," in text else ",".join([text] * robot.dof), option, robot)


def seconds_from_text(text: str, option: str) -> float:
    """A duration in seconds: a plain number, no ``deg``."""
    if text.strip().endswith("deg"):
        raise SymkinError(f"{option}: a time in seconds, got {text!r}")
    return number_from_text(text, option)


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``["--q", "-30deg"]`` -> ``["--q=-30deg"]`` so argparse does not see an option."""
    joined: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in VALUE_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            joined.append(f"{arg}={argv[i + 1]}")
            i += 2
        else:
            joined.append(arg)
            i += 1
    return joined


# ---------------------------------------------------------------- output


def _first_non_finite(value: object, where: str = "") -> str | None:
    """The JSON path of the first NaN or infinity in ``value``, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return where or "(the value)"
    items = (
        value.items()
        if isinstance(value, dict)
        else enumerate(value)
        if isinstance(value, list | tuple)
        else ()
    )
    for key, item in items:
        found = _first_non_finite(item, f"{where}[{key!r}]" if where else str(key))
        if found:
            return found
    return None


def json_text(data: dict) -> str:
    """Strict JSON (RFC 8259 has no NaN or Infinity): a result that is not a finite number is
    an error naming it, not a silent ``NaN`` in the output."""
    where = _first_non_finite(data)
    if where:
        raise SymkinError(
            f"the result {where} is not a finite number: the inputs overflow double precision "
            "or the configuration is at a pole of the formulas"
        )
    return json.dumps(data, indent=2, allow_nan=False)


def text_matrix(matrix: sp.MatrixBase) -> str:
    """One line per row, entries in SymPy syntax."""
    return "\n".join(
        "  [" + ", ".join(sp.sstr(e) for e in matrix.row(i)) + "]" for i in range(matrix.rows)
    )


def condition_text(condition: sp.Eq) -> str:
    return f"{sp.sstr(condition.lhs)} = {sp.sstr(condition.rhs)}"


def dh_table_text(model: Model) -> str:
    """The DH table with each joint's variable inserted (radians)."""
    columns = ("theta", "d", "a", "alpha")
    lines = [f"  {'i':>2}  {'type':<9}" + "".join(f"  {c:<14}" for c in columns)]
    for i, (joint, q) in enumerate(zip(model.robot.joints, model.q, strict=True), start=1):
        values = joint_dh_values(joint, q)
        lines.append(f"  {i:>2}  {joint.type:<9}" + "".join(f"  {sp.sstr(v):<14}" for v in values))
    return "\n".join(lines)


def show_text(model: Model, rows: tuple[str, ...] | None) -> str:
    robot = model.robot
    parameters = ", ".join(f"{n} = {'(symbol)' if v is None else v}" for n, v in robot.parameters)
    out = [
        f"{robot.name}: {printable(robot.title)}",
        f"source: {printable(robot.source) or '(not given)'}",
        f"{robot.dof} joints, {robot.convention} DH; parameters: {parameters or 'none'}",
        "",
        "DH table (angles in rad):",
        dh_table_text(model),
    ]
    for i, link in enumerate(model.link_transforms, start=1):
        out += ["", f"A_{i} (frame {i} in frame {i - 1}):", text_matrix(link)]
    out += ["", "T (tool in base):", text_matrix(model.forward_kinematics)]
    out += [
        "",
        "Geometric Jacobian (rows x y z wx wy wz, base frame):",
        text_matrix(model.geometric_jacobian),
    ]
    task = rows or model.task_rows
    out += ["", f"Task Jacobian rows: {', '.join(task)}"]
    determinant = model.determinant(task)
    if determinant is None:
        out.append("  not square: no determinant (manipulability sqrt(det(J J^T)) applies)")
    else:
        out.append(f"  det J = {sp.sstr(determinant)}")
        if determinant == 0:
            out.append("  singular in every configuration: these rows are linearly dependent")
        else:
            conditions = model.singular_configurations(task)
            out.append("  singular when:" if conditions else "  no singular configurations")
            out += [f"    {condition_text(c)}" for c in conditions]
    return "\n".join(out)


def dynamics_show_text(model: Model) -> str:
    """The equations of motion: Lagrange's readable M, C, G for small robots, else a summary."""
    n = model.robot.dof
    out = ["", "Equations of motion: tau = M(q) ddq + C(q, dq) dq + G(q) + F(dq)"]
    if n <= READABLE_DOF:
        dynamics = model.lagrange
        out += ["", "M (Lagrange):", text_matrix(dynamics.mass_matrix)]
        out += ["", "C (Christoffel symbols):", text_matrix(dynamics.coriolis_matrix)]
        out += ["", "G:", text_matrix(dynamics.gravity_vector)]
    else:
        dynamics = model.newton_euler
        out.append(
            f"  {n} joints: derived by recursive Newton-Euler with {len(dynamics.assignments)} "
            "named intermediates; too long to print readably. Use 'symkin derive' for code "
            "or 'symkin eval --dynamics' for numbers."
        )
    if any(e != 0 for e in dynamics.friction):
        out += ["", "F (friction):", text_matrix(dynamics.friction)]
    return "\n".join(out)


def dynamics_show_json(model: Model, args: argparse.Namespace) -> dict:
    """``M``, ``C``, ``G`` (Lagrange, SymPy syntax) for small robots; null for larger ones."""
    if not args.dynamics:
        return {}
    if model.robot.dof > READABLE_DOF:
        return {"M": None, "C": None, "G": None}
    dynamics = model.lagrange

    def strings(matrix: sp.MatrixBase) -> list:
        return [[sp.sstr(e) for e in matrix.row(i)] for i in range(matrix.rows)]

    return {
        "M": strings(dynamics.mass_matrix),
        "C": strings(dynamics.coriolis_matrix),
        "G": [sp.sstr(e) for e in dynamics.gravity_vector],
    }


def show_json(model: Model, rows: tuple[str, ...] | None) -> dict:
    determinant = model.determinant(rows)
    return {
        "robot": model.robot.name,
        "q": [s.name for s in model.q],
        "task_rows": list(rows or model.task_rows),
        "T": [[sp.sstr(e) for e in model.forward_kinematics.row(i)] for i in range(4)],
        "jacobian": [[sp.sstr(e) for e in model.geometric_jacobian.row(i)] for i in range(6)],
        "det": None if determinant is None else sp.sstr(determinant),
        "singular": [sp.sstr(c) for c in model.singular_configurations(rows)],
    }


def _array(values: np.ndarray | None) -> list | None:
    return None if values is None else np.asarray(values).tolist()


def eval_json(state: KinematicState) -> dict:
    result = {
        "T": _array(state.transform),
        "position": _array(state.position),
        "euler_zyx": _array(state.euler_zyx),
        "euler_zyx_singular": state.euler_zyx_singular,
        "jacobian": _array(state.jacobian),
        "task_rows": list(state.task_rows),
        "det": state.determinant,
        "manipulability": state.manipulability,
    }
    if state.points:
        result["points"] = [
            {
                "link": p.link,
                "point": list(p.point),
                "position": _array(p.position),
                "velocity": _array(p.velocity),
                "acceleration": _array(p.acceleration),
            }
            for p in state.points
        ]
    return result


def dynamics_json(state: DynamicState | None) -> dict:
    if state is None:
        return {}
    return {
        "M": _array(state.mass_matrix),
        "c": _array(state.coriolis),
        "G": _array(state.gravity),
        "tau": _array(state.torque),
    }


def dynamics_text(state: DynamicState | None) -> str:
    if state is None:
        return ""
    lines = ["", "M =", _format(state.mass_matrix), f"G = {_format(state.gravity)}"]
    if state.coriolis is not None:
        lines.append(f"c = C dq = {_format(state.coriolis)}")
    if state.torque is not None:
        lines.append(f"tau = {_format(state.torque)}")
    return "\n".join(lines)


def _format(values: np.ndarray) -> str:
    # "+ 0.0" turns -0.0 into 0.0 so exact zeros print without a sign.
    return np.array2string(np.asarray(values) + 0.0, precision=6, suppress_small=True)


def eval_text(state: KinematicState) -> str:
    fmt = _format
    psi, theta, phi = state.euler_zyx
    out = [
        "T =",
        fmt(state.transform),
        f"position = {fmt(state.position)}",
        f"euler_zyx [psi, theta, phi] = {fmt(state.euler_zyx)} rad "
        f"({math.degrees(psi):.3f}, {math.degrees(theta):.3f}, {math.degrees(phi):.3f} deg)"
        + ("  (gimbal lock: phi set to 0)" if state.euler_zyx_singular else ""),
        "geometric Jacobian (rows x y z wx wy wz) =",
        fmt(state.jacobian),
        f"task rows {', '.join(state.task_rows)}: "
        + (f"det = {state.determinant:.6g}, " if state.determinant is not None else "")
        + f"manipulability = {state.manipulability:.6g}",
    ]
    for p in state.points:
        out.append(f"point {list(p.point)} on link {p.link}: position {fmt(p.position)}")
        if p.velocity is not None:
            out.append(f"  velocity {fmt(p.velocity)}")
        if p.acceleration is not None:
            out.append(f"  acceleration {fmt(p.acceleration)}")
    return "\n".join(out)


# ---------------------------------------------------------------- commands


def command_list(_: argparse.Namespace) -> None:
    for name in catalogue_names():
        with warnings.catch_warnings():
            # Listing is not the place for data-quality warnings (show and eval give them).
            warnings.simplefilter("ignore")
            robot = load_robot(name)
        print(f"{name:<24} {robot.dof} DOF  {robot.convention:<8}  {robot.title}")


def command_show(args: argparse.Namespace) -> None:
    model = derive(load_robot(args.robot))
    rows = task_rows_from_text(args.task)
    if args.json:
        print(json_text(show_json(model, rows) | dynamics_show_json(model, args)))
    else:
        print(show_text(model, rows) + (dynamics_show_text(model) if args.dynamics else ""))


def command_eval(args: argparse.Namespace) -> None:
    robot = load_robot(args.robot)
    model = derive(robot)
    overrides = parameter_overrides(args.set)
    if not args.dynamics:
        robot.parameter_values(overrides)  # reject unknown names and missing values first
    dq = joint_values(args.dq, "--dq", robot) if args.dq else None
    ddq = joint_values(args.ddq, "--ddq", robot) if args.ddq else None
    if ddq is not None and dq is None:
        raise SymkinError("--ddq needs --dq as well (acceleration depends on both)")
    q = joint_values(args.q, "--q", robot)
    kinematic_overrides = {k: v for k, v in overrides.items() if k in dict(robot.parameters)}
    points = [point_from_text(p, robot) for p in args.point]
    with np.errstate(all="ignore"):  # an overflow is reported once, by json_text below
        dynamics = dynamic_state(model, q, dq, ddq, overrides) if args.dynamics else None
        state = kinematic_state(
            model, q, dq, ddq, kinematic_overrides, points, task_rows_from_text(args.task)
        )
    data = eval_json(state) | dynamics_json(dynamics)
    if args.json:
        print(json_text(data))
    else:
        json_text(data)  # the same check: no NaN or infinity printed as a result
        print(eval_text(state) + dynamics_text(dynamics))


def progress(message: str) -> None:
    print(f"symkin: {message}", file=sys.stderr, flush=True)


def command_derive(args: argparse.Namespace) -> None:
    backends = check_backends(args.emit.split(","))
    robot = load_robot(args.robot)
    if args.numeric_parameters:
        robot = robot.with_parameter_values(parameter_overrides(args.set))
    elif args.set:
        raise SymkinError(
            "--set puts parameter values into the code: use it with --numeric-parameters"
        )
    progress(f"deriving {robot.name} and emitting {', '.join(backends)} ...")
    points = [point_from_text(p, robot) for p in args.point]
    files = files_for_robot(robot, backends, args.precision, points)
    out = Path(args.out)
    build = "python" in backends and not args.no_build

    def compile_extension(staging: Path) -> list[str]:
        progress("compiling the Python extension ...")
        extension = build_extension(
            staging / "python" / f"{extension_name(robot)}.c", staging / "c" / f"{robot.name}.c"
        )
        return [extension.relative_to(staging).as_posix()]

    written = write_folder(out, files, finish=compile_extension if build else None)
    print(f"wrote {len(files)} file{'s' if len(files) != 1 else ''} to {out}/:")
    for relative in files:
        print(f"  {out / relative}")
    for relative in sorted(set(written) - set(files)):
        print(f"built {out / relative} (import it with symkin.runtime.extension.load_extension)")
    if "c" in backends or "python" in backends:
        print(f"compile and run the C example: make -C {out / 'c'} && {out / 'c' / 'example'}")


def command_generate(args: argparse.Namespace) -> None:
    root = Path(args.root)
    diff = generate_catalogue(root, args.check, lambda name: progress(f"rendering {name}"))
    if args.check:
        if diff:
            sys.stdout.write(diff)
            raise SymkinError(f"{root}/ is out of date; run 'symkin generate' and commit")
        print(f"{root}/ is up to date")
    else:
        print(f"wrote {root}/ for {len(catalogue_names())} robots")


def command_latex(args: argparse.Namespace) -> None:
    robot = load_robot(args.robot)
    sections = check_sections(args.sections.split(","))
    q = joint_values(args.q, "--q", robot) if args.q else None
    files = latex_files(
        derive(robot),
        sections=sections,
        shorthand=args.shorthand,
        lang=args.lang,
        q=q,
        overrides=parameter_overrides(args.set),
        text_width_cm=args.text_width,
    )
    out = Path(args.output or f"{robot.name}.tex")
    # snippets/ and <robot>-macros.tex beside the document
    write_folder(out.parent, {out.name: files.pop(f"{robot.name}.tex"), **files}, document=out.stem)
    print(f"wrote {out} and {len(files)} snippet and macro files in {out.parent}/")
    if args.pdf:
        print(f"wrote {compile_pdf(out)}")


def ik_problem(
    values: list[float], task_text: str | None
) -> tuple[np.ndarray, bool, tuple[str, ...] | None]:
    """Pose, position-only flag and task rows of a target: ``x,y`` matches the rows x, y only."""
    pose = pose_from_target([*values, 0.0] if len(values) == 2 else values)
    task = task_rows_from_text(task_text) or (("x", "y") if len(values) == 2 else None)
    return pose, len(values) < 6, task


def target_text(values: list[float]) -> str:
    position = ", ".join(f"{name}={v:g}" for name, v in zip("xyz", values, strict=False))
    if len(values) < 6:
        return f"{position} m (position only)"
    angles = ", ".join(
        f"{name}={math.degrees(v):g}"
        for name, v in zip(("rx", "ry", "rz"), values[3:], strict=True)
    )
    return f"{position} m; {angles} deg (R = Rz(rz) Ry(ry) Rx(rx))"


def joint_lines(robot: Robot, q: np.ndarray) -> list[str]:
    """One line per joint: radians and degrees (revolute) or metres (prismatic)."""
    lines = []
    for i, (joint, value) in enumerate(zip(robot.joints, q + 0.0, strict=True), start=1):
        if joint.type == "revolute":
            lines.append(f"  q{i} = {value:>11.6f} rad = {math.degrees(value):>11.4f} deg")
        else:
            lines.append(f"  q{i} = {value:>11.6f} m")
    return lines


def ik_result_text(robot: Robot, result: IKResult, tolerance: float) -> str:
    method = {"lm": "Levenberg-Marquardt", "newton": "Newton-Raphson"}[result.method]
    outcome = "solved" if result.success else "NOT solved, closest pose reached"
    errors = []
    if set(result.rows) & {"x", "y", "z"}:
        errors.append(f"position error {result.position_error:.3g} m")
    if set(result.rows) & {"wx", "wy", "wz"}:
        errors.append(f"rotation error {result.rotation_error:.3g} rad")
    return "\n".join(
        [
            f"task rows {', '.join(result.rows)}; {method}, tolerance {tolerance:g}",
            f"{outcome} after {result.iterations} iterations ({result.restarts} restarts):",
            *joint_lines(robot, result.q),
            ", ".join(errors),
        ]
    )


def ik_result_json(result: IKResult) -> dict:
    return {
        "success": result.success,
        "q": result.q.tolist(),
        "task_rows": list(result.rows),
        "method": result.method,
        "position_error": result.position_error,
        "rotation_error": result.rotation_error,
        "residual": result.residual,
        "iterations": result.iterations,
        "restarts": result.restarts,
        "T": result.pose.tolist(),
    }


def branch_text(solution_branch: dict, within_limits: bool) -> str:
    flags = " ".join(f"{k}={v}" for k, v in solution_branch.items())
    return flags + ("" if within_limits else " (outside the joint limits)")


def solutions_text(robot: Robot, found: SolutionSet) -> str:
    count = len(found.solutions)
    lines = [
        f"{count} solution{'s' if count != 1 else ''} by {found.method} ({found.description})",
        f"{'#':>4}" + "".join(f"{f'q{i}':>12}" for i in range(1, robot.dof + 1)) + "  branch",
    ]
    for k, solution in enumerate(found.solutions, start=1):
        values = "".join(f"{v + 0.0:>12.6f}" for v in solution.q)
        flags = branch_text(dict(solution.branch), solution.within_limits)
        lines.append(f"{k:>4}{values}  {flags}".rstrip())
    return "\n".join(lines)


def path_follow_text(robot: Robot, path: CartesianPath) -> str:
    """Waypoint, target position, joint values and errors, one line per waypoint."""
    head = ["x", "y", "z", *(f"q{i}" for i in range(1, robot.dof + 1))]
    lines = [f"{'i':>4}" + "".join(f"{h:>12}" for h in head) + f"{'pos err':>10}{'rot err':>10}"]
    for i, (target, result) in enumerate(zip(path.targets, path.results, strict=True)):
        values = [*target[:3, 3], *result.q]
        lines.append(
            f"{i:>4}"
            + "".join(f"{v + 0.0:>12.6f}" for v in values)
            + f"{result.position_error:>10.1e}{result.rotation_error:>10.1e}"
            + ("" if result.success else "  NOT solved")
        )
    return "\n".join(lines)


def ik_path(model: Model, args: argparse.Namespace, q0: list[float] | None, overrides) -> int:
    """``--path-from``: the lecture's table (``--table``) or the path follower."""
    if args.to is None or args.steps is None:
        raise SymkinError("--path-from needs --to and --steps as well")
    if args.all:
        raise SymkinError("--all solves one target; use it with --target, not --path-from")
    start = target_from_text(args.path_from, "--path-from")
    end = target_from_text(args.to, "--to")
    if len(start) != len(end):
        raise SymkinError(
            f"--path-from and --to need the same number of values, got {len(start)} and {len(end)}"
        )
    robot = model.robot
    if args.table:
        return ik_table(model, args, start, end, q0, overrides)
    start_pose, position_only, task = ik_problem(start, args.task)
    end_pose = ik_problem(end, args.task)[0]
    path = follow_path(
        model,
        start_pose,
        end_pose,
        args.steps,
        q0,
        restarts=args.restarts or 0,
        method=args.method,
        position_only=position_only,
        task=task,
        tolerance=args.tolerance,
        seed=args.seed,
        overrides=overrides,
    )
    if args.json:
        waypoints = [
            {"target": t.tolist(), **ik_result_json(r)}
            for t, r in zip(path.targets, path.results, strict=True)
        ]
        print(json_text({"robot": robot.name, "success": path.success, "waypoints": waypoints}))
    else:
        print(
            f"{robot.name}: straight path in {args.steps} steps, each waypoint solved to "
            f"{args.tolerance:g} from the previous solution"
        )
        print(path_follow_text(robot, path))
    if args.plot:
        rows = ("x", "y") if len(start) == 2 else ("x", "y", "z")
        indices = ["xyz".index(r) for r in rows]
        plot_path(
            model,
            np.array([t[indices, 3] for t in path.targets]),
            np.array([r.pose[indices, 3] for r in path.results]),
            np.array([r.q for r in path.results]),
            args.plot,
            task=rows,
            overrides=overrides,
        )
        progress(f"wrote {args.plot}")
    return 0 if path.success else 1


def ik_table(
    model: Model,
    args: argparse.Namespace,
    start: list[float],
    end: list[float],
    q0: list[float] | None,
    overrides,
) -> int:
    """The lecture's Newton path table."""
    if q0 is None:
        raise SymkinError(
            "--table starts from a known pair: give --q0, the joint values at --path-from"
        )
    if len(start) == 6:
        raise SymkinError(
            "--table interpolates positions: give --path-from and --to as x,y or x,y,z"
        )
    rows = task_rows_from_text(args.task) or ("x", "y", "z")[: len(start)]
    if len(rows) != len(start):
        raise SymkinError(
            f"--task {','.join(rows)}: --path-from and --to need one value per row, "
            f"got {len(start)}"
        )
    path: NewtonPath = newton_path_table(
        model,
        start,
        q0,
        end,
        args.steps,
        task=rows,
        tolerance=args.tolerance,
        overrides=overrides,
    )
    robot = model.robot
    if args.json:
        print(json_text({"robot": robot.name, **path_table_json(path)}))
    else:
        corrections = len(path.rows) - args.steps - 1
        print(
            f"{robot.name}: Newton path from ({', '.join(f'{v:g}' for v in start)}) to "
            f"({', '.join(f'{v:g}' for v in end)}) in {args.steps} steps, then "
            f"{corrections} Newton correction{'s' if corrections != 1 else ''} at the end point"
        )
        print(path_table_text(path, [f"q{i}" for i in range(1, robot.dof + 1)]))
        if not path.converged:
            print(f"not converged to tolerance {args.tolerance:g} at the end point")
    if args.plot:
        plot_path(
            model,
            np.array([r.target for r in path.rows]),
            np.array([r.real for r in path.rows]),
            np.array([r.q for r in path.rows]),
            args.plot,
            task=path.task,
            labels=[r.label for r in path.rows],
            overrides=overrides,
        )
        progress(f"wrote {args.plot}")
    return 0 if path.converged else 1


def command_ik(args: argparse.Namespace) -> int:
    robot = load_robot(args.robot)
    model = derive(robot)
    overrides = parameter_overrides(args.set)
    robot.parameter_values(overrides)  # reject unknown names and missing values first
    q0 = joint_values(args.q0, "--q0", robot) if args.q0 else None
    if args.restarts is not None and args.restarts < 0:
        raise SymkinError(f"--restarts: expected a count >= 0, got {args.restarts}")
    if (args.target is None) == (args.path_from is None):
        raise SymkinError("give either --target or --path-from (with --to and --steps)")
    if args.path_from is not None:
        return ik_path(model, args, q0, overrides)
    if args.to is not None or args.steps is not None or args.table:
        raise SymkinError("--to, --steps and --table go with --path-from, not --target")
    values = target_from_text(args.target, "--target")
    pose, position_only, task = ik_problem(values, args.task)
    rows = task or model.task_rows
    if len(values) == 6 and any(values[3:]) and not {"wx", "wy", "wz"} & set(rows):
        warnings.warn(
            f"the target's rotation is not matched: the task rows are {', '.join(rows)}",
            stacklevel=1,
        )
    options = {"position_only": position_only, "task": task, "tolerance": args.tolerance}
    if args.all:
        found = all_solutions(model, pose, q0, seed=args.seed, overrides=overrides, **options)
        if args.json:
            solutions = [
                {"q": s.q.tolist(), "branch": dict(s.branch), "within_limits": s.within_limits}
                for s in found.solutions
            ]
            print(
                json_text(
                    {
                        "robot": robot.name,
                        "method": found.method,
                        "description": found.description,
                        "complete": found.complete,
                        "solutions": solutions,
                    }
                )
            )
        else:
            print(f"{robot.name}: target {target_text(values)}")
            print(solutions_text(robot, found))
        if args.plot and found.solutions:
            labels = [
                f"{k}: {branch_text(dict(s.branch), s.within_limits)}".rstrip(": ")
                for k, s in enumerate(found.solutions, start=1)
            ]
            plot_solutions(
                model,
                [s.q for s in found.solutions],
                args.plot,
                target=pose,
                labels=labels,
                overrides=overrides,
            )
            progress(f"wrote {args.plot}")
        return 0 if found.solutions else 1
    result = solve_ik(
        model,
        pose,
        q0,
        method=args.method,
        restarts=DEFAULT_RESTARTS if args.restarts is None else args.restarts,
        seed=args.seed,
        overrides=overrides,
        **options,
    )
    if args.json:
        print(json_text({"robot": robot.name, **ik_result_json(result)}))
    else:
        print(f"{robot.name}: target {target_text(values)}")
        print(ik_result_text(robot, result, args.tolerance))
    if args.plot:
        plot_solutions(
            model,
            [result.q],
            args.plot,
            target=pose,
            labels=["solution" if result.success else "closest pose reached"],
            overrides=overrides,
        )
        progress(f"wrote {args.plot}")
    return 0 if result.success else 1


def command_trajopt(args: argparse.Namespace) -> None:
    robot = load_robot(args.robot)
    if args.to is None and args.cartesian_goal is None:
        raise SymkinError("give the goal: --to V1,V2,... or --cartesian-goal X,Y,Z")
    if args.plot and args.out is None:
        raise SymkinError("--plot needs --out DIR, the folder for trajectory.png")
    if args.min_time and args.objective == "effort":
        raise SymkinError("--min-time means --objective time, not effort")
    objective = "time" if args.min_time else args.objective or "effort"
    cartesian_goal = None
    if args.cartesian_goal is not None:
        cartesian_goal = target_from_text(args.cartesian_goal, "--cartesian-goal")
        if len(cartesian_goal) != 3:
            raise SymkinError(
                f"--cartesian-goal: expected x,y,z (the tool position in metres), "
                f"got {args.cartesian_goal!r}"
            )
    problem = TrajectoryProblem(
        start=joint_values(args.from_, "--from", robot),
        goal=joint_values(args.to, "--to", robot) if args.to is not None else None,
        cartesian_goal=cartesian_goal,
        intervals=args.intervals,
        final_time=None if args.time is None else seconds_from_text(args.time, "--time"),
        objective=objective,
        method=args.method,
        velocity_limits=limit_values(args.velocity_limit, "--velocity-limit", robot, rates=True),
        torque_limits=limit_values(args.torque_limit, "--torque-limit", robot, rates=False),
        overrides=parameter_overrides(args.set),
    )
    model = derive(robot)
    check_problem(model, problem)  # input mistakes before the progress line
    progress(f"setting up and solving the {problem.method} problem with IPOPT ...")
    trajectory = optimal_trajectory(model, problem)
    print(summary_text(trajectory))
    if args.out is not None:
        paths = write_trajectory(trajectory, args.out, plot=args.plot)
        print(f"wrote {', '.join(str(path) for path in paths)}")


def add_set_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="override a parameter"
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="symkin",
        description="Closed-form kinematics from Denavit-Hartenberg tables.",
        epilog="ROBOT is a built-in name (see 'symkin list') or a path to a .toml robot file.",
    )
    parser.add_argument(
        "--time-limit",
        type=time_limit_from_text,
        default=DEFAULT_TIME_LIMIT,
        metavar="SECONDS",
        help=f"stop with an error after this long (default {DEFAULT_TIME_LIMIT:g}; 0: no limit)",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    listing = commands.add_parser("list", help="list the built-in robots")
    listing.set_defaults(run=command_list)

    task_help = "task Jacobian rows, e.g. x,y,wz (default: the n non-zero rows of x y z wz wx wy)"
    show = commands.add_parser(
        "show", help="DH table, transforms, Jacobian determinant and singularities"
    )
    show.add_argument("robot", metavar="ROBOT")
    show.add_argument("--json", action="store_true", help="print a JSON object (SymPy syntax)")
    show.add_argument("--task", metavar="ROWS", help=task_help)
    show.add_argument(
        "--dynamics", action="store_true", help="also print the equations of motion (M, C, G)"
    )
    show.set_defaults(run=command_show)

    evaluate = commands.add_parser(
        "eval",
        help="numbers at one configuration",
        description="Evaluate pose, Jacobian, determinant and point motion at one state. "
        "Values are radians (or metres for prismatic joints); append 'deg' for degrees.",
    )
    evaluate.add_argument("robot", metavar="ROBOT")
    evaluate.add_argument("--q", required=True, metavar="V1,V2,...", help="joint positions")
    evaluate.add_argument("--dq", metavar="V1,V2,...", help="joint velocities")
    evaluate.add_argument("--ddq", metavar="V1,V2,...", help="joint accelerations")
    add_set_option(evaluate)
    evaluate.add_argument(
        "--point",
        action="append",
        default=[],
        metavar="LINK:X,Y,Z",
        help="a point fixed in link LINK (0 = base), coordinates in that link's frame",
    )
    evaluate.add_argument("--task", metavar="ROWS", help=task_help)
    evaluate.add_argument(
        "--dynamics",
        action="store_true",
        help="add M, c, G and tau (c needs --dq, tau --dq and --ddq); links without inertial "
        "data need --set m1=...,cx1=...",
    )
    evaluate.add_argument("--json", action="store_true", help="print a JSON object")
    evaluate.set_defaults(run=command_eval)

    derive_parser = commands.add_parser(
        "derive", help="write generated code (NumPy, C, CasADi) for one robot"
    )
    derive_parser.add_argument("robot", metavar="ROBOT")
    derive_parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    derive_parser.add_argument(
        "--emit",
        default=",".join(BACKENDS),
        metavar="LIST",
        help=f"backends, comma-separated (default: {','.join(BACKENDS)}; also: latex)",
    )
    derive_parser.add_argument(
        "--precision", choices=PRECISIONS, default="double", help="C floating-point type"
    )
    derive_parser.add_argument(
        "--no-build", action="store_true", help="do not compile the Python extension"
    )
    derive_parser.add_argument(
        "--point",
        action="append",
        default=[],
        metavar="LINK:X,Y,Z",
        help="also a kernel pointK for a point fixed in link LINK (position, velocity, "
        "acceleration)",
    )
    derive_parser.add_argument(
        "--numeric-parameters",
        action="store_true",
        help="put the parameter values (file values, or --set) into the code: no p input, "
        "constants folded, and for robots with full inertial data the dynamics run on base "
        "parameters (fewer operations)",
    )
    add_set_option(derive_parser)
    derive_parser.set_defaults(run=command_derive)

    latex = commands.add_parser(
        "latex",
        help="the derivation as a LaTeX document and snippets (optionally a PDF)",
        description="Write the DH table, transforms, Jacobian, determinant and singularities "
        "as LaTeX: a standalone document plus snippets and macros to \\input into notes.",
    )
    latex.add_argument("robot", metavar="ROBOT")
    latex.add_argument("-o", "--output", metavar="FILE", help="document path (default ROBOT.tex)")
    latex.add_argument("--pdf", action="store_true", help="compile with pdflatex as well")
    latex.add_argument("--shorthand", action="store_true", help="c_1, s_12, ... with a legend")
    latex.add_argument("--lang", choices=LANGUAGES, default="en", help="headings (default: en)")
    latex.add_argument("--q", metavar="V1,V2,...", help="also show numbers at this configuration")
    add_set_option(latex)
    latex.add_argument(
        "--sections",
        default=",".join(DEFAULT_SECTIONS),
        metavar="LIST",
        help=f"comma-separated, from {','.join(SECTIONS)} (default: all but dynamics, which "
        "prints M, C and G by Lagrange up to three joints)",
    )
    latex.add_argument(
        "--text-width",
        type=float,
        default=TEXT_WIDTH_CM,
        metavar="CM",
        help=f"text width that decides where matrices split (default {TEXT_WIDTH_CM})",
    )
    latex.set_defaults(run=command_latex)

    generate = commands.add_parser(
        "generate", help="regenerate generated/<robot>/ for every built-in robot"
    )
    generate.add_argument("--check", action="store_true", help="compare only; exit 2 on a diff")
    generate.add_argument("--root", default="generated", metavar="DIR", help="default: generated")
    generate.set_defaults(run=command_generate)

    ik = commands.add_parser(
        "ik",
        help="inverse kinematics: joint values for a tool pose, or along a straight path",
        description="Solve for joint values that put the tool at a target (numeric "
        "Levenberg-Marquardt or Newton; --all: every solution, in closed form where the robot "
        "has one), or along a straight path (--path-from, --to, --steps; --table prints the "
        "lecture's Newton path table). A target is x,y,z[,rx,ry,rz]: metres, then Z-Y-X "
        "Euler angles, R = Rz(rz) Ry(ry) Rx(rx), in rad or with 'deg'; x,y matches only the "
        "x and y rows. Exit status 1 when the target is not reached.",
    )
    ik.add_argument("robot", metavar="ROBOT")
    ik.add_argument("--target", metavar="X,Y,Z[,RX,RY,RZ]", help="the tool pose to reach")
    ik.add_argument(
        "--q0", metavar="V1,V2,...", help="first guess (with --table: joint values at the start)"
    )
    ik.add_argument(
        "--all",
        action="store_true",
        help="every solution: closed form with branch flags, or numeric from many seeds",
    )
    ik.add_argument(
        "--task", metavar="ROWS", help="rows to match, e.g. x,y or xy (default: the robot's)"
    )
    ik.add_argument(
        "--method", choices=METHODS, default="lm", help="lm (default) or newton (Newton-Raphson)"
    )
    ik.add_argument(
        "--tolerance",
        type=float,
        default=DEFAULT_TOLERANCE,
        metavar="TOL",
        help=f"position error in m and rotation error in rad (default {DEFAULT_TOLERANCE:g})",
    )
    ik.add_argument(
        "--restarts",
        type=int,
        metavar="N",
        help=f"random restarts after a failed attempt (default {DEFAULT_RESTARTS}; along a path 0)",
    )
    ik.add_argument(
        "--seed", type=seed_from_text, default=0, metavar="N", help="seed of the restarts (>= 0)"
    )
    ik.add_argument("--path-from", metavar="X0", help="start of a straight path (as --target)")
    ik.add_argument("--to", metavar="X_END", help="end of the path")
    ik.add_argument("--steps", type=int, metavar="K", help="number of equal steps of the path")
    ik.add_argument(
        "--table",
        action="store_true",
        help="the lecture's scheme: one Newton step per waypoint from (--path-from, --q0)",
    )
    add_set_option(ik)
    ik.add_argument("--json", action="store_true", help="print a JSON object")
    ik.add_argument("--plot", metavar="FILE.png", help="draw the arm (and the path) to a PNG")
    ik.set_defaults(run=command_ik)

    trajopt = commands.add_parser(
        "trajopt",
        help="optimal point-to-point motion on the robot's dynamics (CasADi + IPOPT)",
        description="Plan a rest-to-rest motion from --from to --to (or to the tool position "
        "--cartesian-goal) on the robot's forward dynamics: minimum effort (the integral of "
        "tau^2 over a fixed --time) or minimum time, within the joint limits of the robot file "
        "and the velocity and torque limits given here (default: none). Joint values are "
        "radians (or metres); append 'deg' for degrees.",
    )
    trajopt.add_argument("robot", metavar="ROBOT")
    trajopt.add_argument(
        "--from", dest="from_", required=True, metavar="V1,V2,...", help="start configuration"
    )
    trajopt.add_argument(
        "--to", metavar="V1,V2,...", help="goal configuration (with --cartesian-goal: a guess)"
    )
    trajopt.add_argument(
        "--cartesian-goal", metavar="X,Y,Z", help="goal tool position in metres, base frame"
    )
    trajopt.add_argument(
        "--intervals", type=int, default=40, metavar="N", help="time intervals (default 40)"
    )
    duration = trajopt.add_mutually_exclusive_group()
    duration.add_argument("--time", metavar="T", help="fixed final time in seconds (effort)")
    duration.add_argument(
        "--min-time", action="store_true", help="minimise the final time (= --objective time)"
    )
    trajopt.add_argument(
        "--objective", choices=OBJECTIVES, help="effort (the default) or time (= --min-time)"
    )
    trajopt.add_argument(
        "--method",
        choices=list(TRANSCRIPTIONS),
        default="multiple-shooting",
        help="transcription: multiple-shooting (RK4, default) or collocation (Radau)",
    )
    trajopt.add_argument(
        "--velocity-limit",
        metavar="V[,V2,...]",
        help="|dq| limit, one value for all joints or one per joint (rad/s or m/s; deg ok)",
    )
    trajopt.add_argument(
        "--torque-limit",
        metavar="V[,V2,...]",
        help="|tau| limit, one value for all joints or one per joint (N m or N)",
    )
    add_set_option(trajopt)
    trajopt.add_argument(
        "--out", metavar="DIR", help="write trajectory.csv and trajectory.json to DIR"
    )
    trajopt.add_argument("--plot", action="store_true", help="also write DIR/trajectory.png")
    trajopt.set_defaults(run=command_trajopt)
    return parser


def show_warning(message: Warning | str, *_: object, **__: object) -> None:
    """One ``symkin: warning: ...`` line instead of Python's file-and-line format."""
    print(f"symkin: warning: {printable(str(message))}", file=sys.stderr)


class TimeLimitReached(BaseException):
    """Raised by the alarm; a BaseException, so SymPy's ``except Exception`` cannot swallow it."""


def _stop_at_time_limit(seconds: float) -> None:
    def expire(*_: object) -> None:
        raise TimeLimitReached

    # Signals reach only the main thread (main() may be called from another, e.g. a GUI).
    if seconds > 0 and threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGALRM, expire)
        signal.setitimer(signal.ITIMER_REAL, seconds)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else argv))
    status = 0
    subject = f"{args.command} {printable(getattr(args, 'robot', '') or '')}".rstrip()
    try:
        _stop_at_time_limit(args.time_limit)
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            status = args.run(args) or 0  # ik: 1 when the target is not reached
    except SymkinError as error:
        print(f"symkin: error: {printable(str(error), keep=KEPT)}", file=sys.stderr)
        return 2
    except TimeLimitReached:
        print(
            f"symkin: error: {subject}: stopped at the time limit of {args.time_limit:g} s "
            "(--time-limit SECONDS, 0 for none); the closed form is too large for this budget",
            file=sys.stderr,
        )
        return 2
    except KeyboardInterrupt:
        print(f"symkin: {subject}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # Output piped into `head` and closed early: not an error of ours.
        sys.stderr.close()
    except Exception as error:
        if os.environ.get("SYMKIN_TRACEBACK"):
            raise
        print(
            f"symkin: internal error: {subject}: {type(error).__name__}: "
            f"{printable(str(error))[:300]} (a bug in symkin: please report it with the robot "
            "file; SYMKIN_TRACEBACK=1 shows the traceback)",
            file=sys.stderr,
        )
        return 3
    finally:
        if threading.current_thread() is threading.main_thread():
            signal.setitimer(signal.ITIMER_REAL, 0)
    return status

