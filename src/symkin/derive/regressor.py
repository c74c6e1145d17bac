"""The dynamic regressor: ``tau(q, dq, ddq) = Y(q, dq, ddq) pi``, linear in the parameters.

``pi`` holds, link by link, the ten barycentric parameters of
:mod:`symkin.derive.base_parameters` (inertia about the link frame's origin, first moment
``m c``, mass; Khalil & Dombre, *Modeling, Identification and Control of Robots*, eq. 9.98)
and then the joint's drive parameters the robot file gives: the reflected rotor inertia
``ia`` (column ``ddq_i``), viscous friction ``fv`` (column ``dq_i``) and Coulomb friction
``fc`` (column ``sign(dq_i)``; direction-dependent Coulomb friction has one column per side,
``fcp`` with ``(sign + sign^2)/2`` and ``fcn`` with ``(sign - sign^2)/2``; with
``friction.smoothing`` ``w`` the columns take ``tanh(dq_i / w)`` for ``sign(dq_i)``).  An
elastic joint's rotor is on the motor side, not in the link torques: it has no column.

The columns of the link parameters are the partial derivatives of the Newton–Euler torques
of :func:`symkin.derive.recursion.joint_torques` run with symbolic barycentric parameters,
taken through its named intermediates (forward mode), so ``Y`` shares the recursion's
subexpressions and never expands.  ``tau`` is linear in ``pi``, so the derivative is exact.

:func:`barycentric_dynamics` is that recursion itself with ``pi`` as its input: ``tau`` and
``M`` of any parameter vector ``pi`` (an identified one, say), without the parallel-axis terms
the robot file's centre-of-mass form costs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from symkin.derive.base_parameters import (
    PARAMETER_NAMES,
    barycentric_links,
    barycentric_symbols,
)
from symkin.derive.dynamics import link_inertial_data
from symkin.derive.kinematics import Kinematics
from symkin.derive.recursion import barycentric_definitions, joint_torques, robot_recorder
from symkin.derive.regressor_mass import composite_mass_matrix
from symkin.errors import RobotError
from symkin.robot import Link, Robot
from symkin.symbols import joint_symbols, link_inertial_symbols

# Columns per link in Khalil's order (Khalil & Dombre, Ch. 9): the base parameters keep the
# earlier of dependent columns, so inertia and first moments stay and masses fold into them.
COLUMN_ORDER = ("xx", "xy", "xz", "yy", "yz", "zz", "mx", "my", "mz", "m")


@dataclass(frozen=True)
class Regressor:
    """``Y`` (n x P) with its named intermediates, and per column the parameter's symbol
    and its definition in the robot's inertial symbols (``xx2 = ixx2 + m2 (cy2^2 + cz2^2)``).

    ``links[k]`` is the 0-based link (or joint) a column belongs to; ``values`` are the robot
    file's numbers for ``pi`` (None when its inertial data are symbols).
    """

    symbols: tuple[sp.Symbol, ...]
    definitions: tuple[sp.Expr, ...]
    links: tuple[int, ...]
    matrix: sp.ImmutableMatrix
    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    values: tuple[float, ...] | None

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.symbols)


def _drive_columns(
    link: Link | None, number: int, dq: sp.Symbol, ddq: sp.Symbol
) -> list[tuple[sp.Symbol, sp.Expr, sp.Expr, sp.Expr]]:
    """``(symbol, definition, value, column entry)`` of the drive parameters joint ``number``
    has in the file: rotor inertia, viscous and Coulomb friction (module docstring)."""
    if link is None:
        return []
    if link.stribeck_static is not None and link.stribeck_velocity is not None:
        raise RobotError(
            f"joint {number}: Stribeck friction is not linear in its parameters; the regressor "
            "covers rotor inertia, viscous and Coulomb friction only"
        )
    sign = sp.sign(dq)
    # As symkin.derive.dynamics.friction_torque: tanh(dq / w) for a smoothed Coulomb term; an
    # elastic joint's rotor is on the motor side and not in the link torques.
    direction = sign if link.coulomb_width is None else sp.tanh(dq / link.coulomb_width)
    rotor = sp.Integer(0) if link.is_elastic else link.motor_inertia
    drive = [("ia", rotor, ddq), ("fv", link.viscous, dq)]
    if link.coulomb_negative is None:
        drive.append(("fc", link.coulomb, direction))
    else:
        drive.append(("fcp", link.coulomb, (direction + sign * direction) / 2))
        drive.append(("fcn", link.coulomb_negative, (direction - sign * direction) / 2))
    return [
        (sp.Symbol(f"{name}{number}", real=True), sp.Symbol(f"{name}{number}", real=True),
         value, entry)
        for name, value, entry in drive
        if sp.sympify(value) != 0
    ]  # fmt: skip


# The names of Y's columns: PARAMETER_NAMES and the drive columns of _drive_columns, per link.
DRIVE_NAMES = ("ia", "fv", "fc", "fcp", "fcn")
_COLUMN_NAME = re.compile(rf"({'|'.join(PARAMETER_NAMES + DRIVE_NAMES)})([1-9][0-9]*)")


def check_column_names(robot: Robot) -> None:
    """A parameter named like a column of ``Y`` (``m1``, ``xx2``, ``fv3``) would be that
    column's symbol in the derivation and a second variable of that name in generated code:
    a :class:`RobotError` naming it."""
    for name, _ in robot.parameters:
        match = _COLUMN_NAME.fullmatch(name)
        if match and 1 <= int(match.group(2)) <= robot.dof:
            where = f"{robot.file}: " if robot.file else ""
            raise RobotError(
                f"{where}parameter {name!r} has the name of a barycentric or drive parameter "
                f"of link {int(match.group(2))}, a column of the identification kernels; "
                "rename it"
            )


@lru_cache(maxsize=16)
def regressor(robot: Robot, kinematics: Kinematics) -> Regressor:
    """``Y`` of the robot: per link the columns of :data:`PARAMETER_NAMES`, then its joint's
    drive columns (module docstring)."""
    check_column_names(robot)
    n = robot.dof
    dq, ddq = joint_symbols(n, "dq"), joint_symbols(n, "ddq")
    delta = barycentric_symbols(n)
    recorder = robot_recorder(robot, "y")
    torque = joint_torques(
        robot, kinematics, recorder, dq, ddq, robot.gravity, barycentric_links(delta)
    )
    symbols, definitions, links, values, columns = [], [], [], [], []
    count = len(PARAMETER_NAMES)
    for i in range(n):
        inertial = link_inertial_data(robot, i)
        link_values = _numeric_barycentric(inertial)
        definition = barycentric_definitions(_symbolic_link(i + 1))
        for name in COLUMN_ORDER:
            symbol = delta[i * count + PARAMETER_NAMES.index(name)]
            column = [
                recorder.derivative(torque[r], symbol) if r <= i else sp.Integer(0)
                for r in range(n)
            ]
            symbols.append(symbol)
            definitions.append(definition[name])
            values.append(None if link_values is None else link_values[name])
            columns.append(column)
            links.append(i)
        for symbol, defined, value, entry in _drive_columns(
            robot.joints[i].link, i + 1, dq[i], ddq[i]
        ):
            symbols.append(symbol)
            definitions.append(defined)
            values.append(float(value) if sp.sympify(value).is_number else None)
            columns.append([entry if r == i else sp.Integer(0) for r in range(n)])
            links.append(i)
    matrix = sp.ImmutableMatrix(n, len(columns), lambda r, c: columns[c][r])
    known = None if any(v is None for v in values) else tuple(float(v) for v in values)
    return Regressor(
        tuple(symbols),
        tuple(definitions),
        tuple(links),
        matrix,
        _needed(recorder.assignments, matrix),
        known,
    )


def parameter_symbols(robot: Robot) -> tuple[sp.Symbol, ...]:
    """``pi`` in the regressor's column order (:func:`regressor`'s ``symbols``), without
    deriving ``Y``: per link :data:`COLUMN_ORDER`, then its joint's drive parameters."""
    n = robot.dof
    dq, ddq = joint_symbols(n, "dq"), joint_symbols(n, "ddq")
    delta = barycentric_symbols(n)
    count = len(PARAMETER_NAMES)
    symbols: list[sp.Symbol] = []
    for i in range(n):
        symbols += [delta[i * count + PARAMETER_NAMES.index(name)] for name in COLUMN_ORDER]
        drive = _drive_columns(robot.joints[i].link, i + 1, dq[i], ddq[i])
        symbols += [symbol for symbol, *_ in drive]
    return tuple(symbols)


@dataclass(frozen=True)
class BarycentricDynamics:
    """``tau(q, dq, ddq; pi)`` and ``M(q; pi)`` with the regressor's parameter vector ``pi``
    (``symbols``, in :func:`parameter_symbols` order) as symbols: ``tau = Y pi`` exactly.

    Each comes with its own named intermediates (one Newton–Euler pass for ``tau``; the
    composite-rigid-body algorithm of :mod:`symkin.derive.regressor_mass` for ``M``), plus
    the drive terms.
    """

    symbols: tuple[sp.Symbol, ...]
    torque_assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    torque: sp.ImmutableMatrix
    mass_assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    mass_matrix: sp.ImmutableMatrix


@lru_cache(maxsize=16)
def barycentric_dynamics(robot: Robot, kinematics: Kinematics) -> BarycentricDynamics:
    """``tau`` and ``M`` of the recursion run on the symbols of :func:`parameter_symbols`
    (the class docstring): the drive parameters add ``ia_i ddq_i``, ``fv_i dq_i`` and the
    Coulomb terms to ``tau_i``, and ``ia_i`` to ``M_ii``."""
    check_column_names(robot)
    n = robot.dof
    dq, ddq = joint_symbols(n, "dq"), joint_symbols(n, "ddq")
    links = barycentric_links(barycentric_symbols(n))
    torque_recorder, mass_recorder = robot_recorder(robot, "s"), robot_recorder(robot, "s")
    torque = sp.Matrix(
        joint_torques(robot, kinematics, torque_recorder, dq, ddq, robot.gravity, links)
    )
    mass = composite_mass_matrix(robot, kinematics, links, mass_recorder)
    for i in range(n):
        for symbol, _, _, entry in _drive_columns(robot.joints[i].link, i + 1, dq[i], ddq[i]):
            torque[i] += symbol * entry
            mass[i, i] += symbol * sp.diff(entry, ddq[i])
    return BarycentricDynamics(
        parameter_symbols(robot),
        tuple(torque_recorder.assignments),
        sp.ImmutableMatrix(torque),
        tuple(mass_recorder.assignments),
        sp.ImmutableMatrix(mass),
    )


def _needed(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrix: sp.MatrixBase
) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
    """The intermediates ``matrix`` needs, in definition order: the torques themselves
    (which hold the parameter symbols) are left behind."""
    wanted = set(matrix.free_symbols)
    kept = []
    for symbol, expr in reversed(assignments):
        if symbol in wanted:
            kept.append((symbol, expr))
            wanted |= expr.free_symbols
    return tuple(reversed(kept))


def _symbolic_link(number: int) -> Link:
    s = link_inertial_symbols(number)
    return Link(
        mass=s["m"],
        com=(s["cx"], s["cy"], s["cz"]),
        inertia=(s["ixx"], s["iyy"], s["izz"], s["ixy"], s["ixz"], s["iyz"]),
    )


def _numeric_barycentric(link: Link) -> dict[str, float] | None:
    """The link's barycentric parameters as floats, or None when its data hold symbols."""
    exact = barycentric_definitions(link)
    if not all(sp.sympify(v).is_number for v in exact.values()):
        return None
    return {name: float(v) for name, v in exact.items()}


def regressor_function(robot: Robot, kinematics: Kinematics):
    """``(q, dq, ddq, p) -> Y`` (n x P floats) for one state: the symbolic ``Y`` through
    ``lambdify`` with its intermediates, for the base-parameter analysis (not a kernel)."""
    result = regressor(robot, kinematics)
    n = robot.dof
    function = sp.lambdify(
        [kinematics.q, joint_symbols(n, "dq"), joint_symbols(n, "ddq"), robot.parameter_symbols],
        result.matrix,
        modules="numpy",
        cse=lambda e: (list(result.assignments), e),
    )

    def evaluate(q, dq, ddq, p=()) -> np.ndarray:
        return np.array(function(q, dq, ddq, p), dtype=float).reshape(n, -1)

    return evaluate
