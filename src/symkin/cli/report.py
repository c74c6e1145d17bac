"""What the ``symkin`` command prints: text and JSON reports, progress and warning lines, and
error messages with the library's parameter names spelled as the command's flags.

Text output uses SymPy syntax for formulas and NumPy's printing (6 digits) for numbers; JSON
is strict (no NaN or infinity).
"""

from __future__ import annotations

import json
import math

import numpy as np
import sympy as sp

from symkin.derive import Model
from symkin.derive.budget import NOT_SQUARE, OVER_BUDGET, ClosedForm
from symkin.derive.kinematics import joint_dh_values, placement_xyz_rpy
from symkin.derive.lagrange import READABLE_DOF
from symkin.emit.formula_text import formula_text
from symkin.errors import BudgetWarning, ParameterError, SymkinError
from symkin.progress import note
from symkin.robot import Robot
from symkin.solve.elastic_state import MotorSideState
from symkin.solve.evaluate import DynamicState, KinematicState
from symkin.solve.ik.numeric import IKResult
from symkin.solve.ik.path import CartesianPath, NewtonPath, path_table_text
from symkin.solve.ik.solutions import SolutionSet
from symkin.text import KEPT, printable

# Library parameters a command spells other than by the default rule (``--`` + the name with
# ``_`` -> ``-``: ``cartesian_goal`` -> ``--cartesian-goal``).
FLAGS = {
    "overrides": "--set NAME=VALUE",
    "backends": "--emit",
    "text_width_cm": "--text-width",
    "all_solutions": "--all",
    "final_time": "--time",
    "velocity_limits": "--velocity-limit",
    "torque_limits": "--torque-limit",
}
# Spellings that hold for one command only (a trajectory's start and goal configurations).
COMMAND_FLAGS = {"trajopt": {"start": "--from", "goal": "--to"}}


def flag(parameter: str, command: str) -> str:
    """The option of ``command`` that sets the library's ``parameter``."""
    spelled = COMMAND_FLAGS.get(command, {}).get(parameter) or FLAGS.get(parameter)
    return spelled or "--" + parameter.replace("_", "-")


def error_text(error: SymkinError, command: str) -> str:
    """The ``symkin: error: ...`` line of a user mistake, parameters named as flags."""
    message = str(error)
    if isinstance(error, ParameterError):
        message = error.message_for({name: flag(name, command) for name in error.parameters})
    return f"symkin: error: {printable(message, keep=KEPT)}"


def progress(message: str) -> None:
    """A ``symkin: ...`` line on stderr, through the command's reporter (which also shows
    the library's phases; see :mod:`symkin.cli.reporter`)."""
    note(message)


def show_warning(message: Warning | str, *_: object, **__: object) -> None:
    """One ``symkin: warning: ...`` line instead of Python's file-and-line format, through the
    command's reporter (so it lands above a live progress line, not inside it); a budget
    warning names the ``--budget`` flag."""
    text = (
        message.message_for({"budget": "--budget SECONDS"})
        if isinstance(message, BudgetWarning)
        else str(message)
    )
    note(f"warning: {printable(text)}")


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
        "  [" + ", ".join(formula_text(e) for e in matrix.row(i)) + "]" for i in range(matrix.rows)
    )


def condition_text(condition: sp.Eq) -> str:
    return f"{formula_text(condition.lhs)} = {formula_text(condition.rhs)}"


def dh_table_text(model: Model) -> str:
    """The DH table with each joint's variable inserted (radians)."""
    columns = ("theta", "d", "a", "alpha")
    lines = [f"  {'i':>2}  {'type':<9}" + "".join(f"  {c:<14}" for c in columns)]
    for i, (joint, q) in enumerate(zip(model.robot.joints, model.q, strict=True), start=1):
        values = joint_dh_values(joint, q)
        lines.append(
            f"  {i:>2}  {joint.type:<9}" + "".join(f"  {formula_text(v):<14}" for v in values)
        )
    return "\n".join(lines)


def placement_table_text(model: Model) -> str:
    """The placed joints: each joint frame's placement in the previous frame (xyz, rpy in
    rad) and the joint's motion about or along its z axis."""
    header = f"  {'i':>2}  {'type':<9}  {'name':<20}  {'xyz':<34}  {'rpy':<34}  motion"
    lines = [header]
    for i, (joint, q) in enumerate(zip(model.robot.joints, model.q, strict=True), start=1):
        xyz, rpy = placement_xyz_rpy(joint.placement)
        theta, d, _, _ = joint_dh_values(joint, q)
        motion = (
            f"Rz({formula_text(theta)})" if joint.type == "revolute" else f"Tz({formula_text(d)})"
        )
        triples = [
            " ".join(formula_text(sp.N(v, 6) if v.is_number else v) for v in t) for t in (xyz, rpy)
        ]
        lines.append(
            f"  {i:>2}  {joint.type:<9}  {joint.name or '':<20}  {triples[0]:<34}  "
            f"{triples[1]:<34}  {motion}"
        )
    return "\n".join(lines)


def _joint_table(model: Model) -> list[str]:
    if model.robot.convention == "placement":
        return [
            "Placed joints (A_i = P_i Rz(theta_i) Tz(d_i); angles in rad):",
            placement_table_text(model),
        ]
    return ["DH table (angles in rad):", dh_table_text(model)]


def convention_text(convention: str) -> str:
    """``standard DH``, ``modified DH`` or ``placed joints``."""
    return "placed joints" if convention == "placement" else f"{convention} DH"


def data_notes(robot: Robot) -> list[str]:
    """One line per link whose file documents its inertial data (``inertia_note``)."""
    return [
        f"note: joint {i} link inertia: {printable(joint.link.inertia_note)}"
        for i, joint in enumerate(robot.joints, start=1)
        if joint.link is not None and joint.link.inertia_note
    ]


def show_text(model: Model, rows: tuple[str, ...] | None) -> str:
    robot = model.robot
    parameters = ", ".join(f"{n} = {'(symbol)' if v is None else v}" for n, v in robot.parameters)
    out = [
        f"{robot.name}: {printable(robot.title)}",
        f"source: {printable(robot.source) or '(not given)'}",
        *data_notes(robot),
        f"{robot.dof} joints, {convention_text(robot.convention)}; "
        f"parameters: {parameters or 'none'}",
        "",
        *_joint_table(model),
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
    form = model.determinant_form(task)
    determinant = form.value
    if form.status == NOT_SQUARE:
        out.append("  not square: no determinant (manipulability sqrt(det(J J^T)) applies)")
    elif not form.found:
        out.append(f"  det J: closed form {_not_found_text(form)}; generated code computes it")
        out.append("  numerically from the Jacobian, and so do 'symkin eval' and kinematic_state")
    else:
        out.append(f"  det J = {formula_text(determinant)}")
        if determinant == 0:
            out.append("  singular in every configuration: these rows are linearly dependent")
        else:
            singular = model.singular_form(task)
            conditions = singular.value or ()
            if not singular.found:
                out.append(f"  singular configurations: {_not_found_text(singular)}")
            else:
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


def dynamics_show_json(model: Model) -> dict:
    """``M``, ``C``, ``G`` (Lagrange, SymPy syntax) for small robots; null for larger ones."""
    if model.robot.dof > READABLE_DOF:
        return {"M": None, "C": None, "G": None}
    dynamics = model.lagrange

    def strings(matrix: sp.MatrixBase) -> list:
        return [[formula_text(e) for e in matrix.row(i)] for i in range(matrix.rows)]

    return {
        "M": strings(dynamics.mass_matrix),
        "C": strings(dynamics.coriolis_matrix),
        "G": [formula_text(e) for e in dynamics.gravity_vector],
    }


def _not_found_text(form: ClosedForm) -> str:
    """``not found within the budget`` or ``not attempted``: how a missing closed form reads."""
    return "not found within the budget" if form.status == OVER_BUDGET else "not attempted"


def show_json(model: Model, rows: tuple[str, ...] | None) -> dict:
    """The ``show --json`` object; ``det`` and ``singular`` are null when their closed form is
    missing, and ``det_status``/``singular_status`` say why (``found``, ``not square``,
    ``over budget``, ``not attempted``)."""
    determinant = model.determinant_form(rows)
    singular = model.singular_form(rows)
    return {
        "robot": model.robot.name,
        "q": [s.name for s in model.q],
        "task_rows": list(rows or model.task_rows),
        "T": [[formula_text(e) for e in model.forward_kinematics.row(i)] for i in range(4)],
        "jacobian": [[formula_text(e) for e in model.geometric_jacobian.row(i)] for i in range(6)],
        "det": formula_text(determinant.value) if determinant.found else None,
        "det_status": determinant.status,
        "singular": [formula_text(c) for c in singular.value]
        if singular.found
        else ([] if singular.status == NOT_SQUARE else None),
        "singular_status": singular.status,
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
        # null at a singular configuration (JSON has no infinity)
        "condition_number": _finite_or_none(state.condition_number),
        "smallest_singular_value": state.smallest_singular_value,
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


def _finite_or_none(value: float) -> float | None:
    return value if math.isfinite(value) else None


def dynamics_json(state: DynamicState | None) -> dict:
    if state is None:
        return {}
    return {
        "M": _array(state.mass_matrix),
        "c": _array(state.coriolis),
        "G": _array(state.gravity),
        "tau": _array(state.torque),
        "wrench_torque": _array(state.wrench_torque),
        "static_torque": _array(state.static_torque),
        "kinetic_energy": state.kinetic_energy,
        "potential_energy": state.potential_energy,
        "lagrangian": state.lagrangian,
    }


def motor_side_json(state: MotorSideState | None) -> dict:
    """``theta`` and ``tau_motor`` of a robot with elastic joints (1-based joint numbers)."""
    if state is None:
        return {}
    return {
        "elastic_joints": list(state.elastic_joints),
        "theta": _array(state.theta),
        "tau_motor": _array(state.tau_motor),
    }


def motor_side_text(state: MotorSideState | None) -> str:
    if state is None:
        return ""
    joints = ", ".join(map(str, state.elastic_joints))
    return "\n".join(
        [
            "",
            f"Elastic joints {joints}: motor side (Spong's reduced model)",
            f"theta = q + K^-1 tau = {_format(state.theta)}",
            f"tau_motor = B (ddq + K^-1 d2tau/dt2) + tau = {_format(state.tau_motor)}",
        ]
    )


def dynamics_text(state: DynamicState | None) -> str:
    if state is None:
        return ""
    lines = ["", "M =", _format(state.mass_matrix), f"G = {_format(state.gravity)}"]
    if state.coriolis is not None:
        lines.append(f"c = C dq = {_format(state.coriolis)}")
    if state.torque is not None:
        lines.append(f"tau = {_format(state.torque)}")
    if state.wrench_torque is not None:
        lines.append(f"-J^T w = {_format(state.wrench_torque)}")
        lines.append(f"static torque G - J^T w = {_format(state.static_torque)}")
    energies = (state.kinetic_energy, state.potential_energy, state.lagrangian)
    names = ("T (kinetic energy)", "V (potential energy)", "L = T - V")
    lines += [
        f"{name} = {value:.6g} J"
        for name, value in zip(names, energies, strict=True)
        if value is not None
    ]
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
        f"  condition number = {state.condition_number:.6g}, "
        f"smallest singular value = {state.smallest_singular_value:.6g}",
    ]
    for p in state.points:
        out.append(f"point {list(p.point)} on link {p.link}: position {fmt(p.position)}")
        if p.velocity is not None:
            out.append(f"  velocity {fmt(p.velocity)}")
        if p.acceleration is not None:
            out.append(f"  acceleration {fmt(p.acceleration)}")
    return "\n".join(out)


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


# How the text names the damped-least-squares backends (symkin.solve.ik.backends).
IK_BACKEND_NAMES = {
    "c": "damped least squares, generated C",
    "numpy": "damped least squares, NumPy",
}


def ik_result_text(robot: Robot, result: IKResult, tolerance: float) -> str:
    method = {"lm": "Levenberg-Marquardt", "newton": "Newton-Raphson"}[result.method]
    if result.backend in IK_BACKEND_NAMES:
        method += f" ({IK_BACKEND_NAMES[result.backend]})"
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
        "backend": result.backend,
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


def path_follow_json(path: CartesianPath) -> dict:
    """``success`` and one object per waypoint: its target pose and the IK result."""
    waypoints = [
        {"target": t.tolist(), **ik_result_json(r)}
        for t, r in zip(path.targets, path.results, strict=True)
    ]
    return {"success": path.success, "waypoints": waypoints}


def newton_path_text(
    robot: Robot,
    path: NewtonPath,
    start: list[float],
    end: list[float],
    steps: int,
    tolerance: float,
) -> str:
    """The lecture's Newton path table under a line naming the path and its corrections."""
    corrections = len(path.rows) - steps - 1
    lines = [
        f"{robot.name}: Newton path from ({', '.join(f'{v:g}' for v in start)}) to "
        f"({', '.join(f'{v:g}' for v in end)}) in {steps} steps, then "
        f"{corrections} Newton correction{'s' if corrections != 1 else ''} at the end point",
        path_table_text(path, [f"q{i}" for i in range(1, robot.dof + 1)]),
    ]
    if not path.converged:
        lines.append(f"not converged to tolerance {tolerance:g} at the end point")
    return "\n".join(lines)
