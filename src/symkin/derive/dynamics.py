"""The equations of motion as one type, whichever method derived them.

    tau = M(q) ddq + C(q, dq) dq + G(q) + F(dq)

``M`` includes the reflected rotor inertias ``Ia`` on its diagonal.  ``C`` is the Coriolis
matrix built from Christoffel symbols (so ``dM/dt - 2C`` is skew-symmetric) and ``c = C dq``.
Expressions may refer to named intermediates (``assignments``, in order of definition): the
recursive Newton–Euler method names every quantity as it goes so nothing blows up.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.robot import Link, Robot
from symkin.symbols import link_inertial_symbols


def link_inertial_data(robot: Robot, index: int) -> Link:
    """Inertial data of link ``index`` (0-based): the file's, or symbols ``m1, cx1, ixx1, ...``.

    Symbols are real; masses and principal moments are also positive, which lets SymPy
    simplify ``sqrt(m1**2)`` and the like.
    """
    link = robot.joints[index].link
    if link is not None:
        return link
    s = link_inertial_symbols(index + 1)
    return Link(
        mass=s["m"],
        com=(s["cx"], s["cy"], s["cz"]),
        inertia=(s["ixx"], s["iyy"], s["izz"], s["ixy"], s["ixz"], s["iyz"]),
    )


def friction_torque(link: Link, dq: sp.Symbol) -> sp.Expr:
    """Joint friction ``F_i(dq_i)`` (docs/conventions.md, Dynamics).

    Coulomb + viscous: ``fc sign(dq) + fv dq``; Stribeck, when given:
    ``(fc + (fs - fc) exp(-|dq / dq_s|)) sign(dq) + fv dq``.  Direction-dependent Coulomb
    friction (``fc+`` for ``dq > 0``, ``fc-`` for ``dq < 0``) takes the level of the side
    ``dq`` is on, ``fc = (fc+ + fc-)/2 + (fc+ - fc-)/2 sign(dq)``, so ``F = fc+`` for
    ``dq > 0``, ``-fc-`` for ``dq < 0`` and 0 at rest (``sign(0) = 0``).  With a
    ``coulomb_width`` w the Coulomb and Stribeck terms use the smooth ``tanh(dq / w)`` in place
    of ``sign(dq)`` (differentiable, for optimisers: 76 % of the level at ``|dq| = w``, 99.9 %
    at ``4 w``).
    """
    coulomb = link.coulomb
    if link.coulomb_negative is not None:
        mean = (link.coulomb + link.coulomb_negative) / 2
        coulomb = mean + (link.coulomb - link.coulomb_negative) / 2 * sp.sign(dq)
    if link.stribeck_static is not None and link.stribeck_velocity is not None:
        decay = sp.exp(-sp.Abs(dq / link.stribeck_velocity))
        coulomb = coulomb + (link.stribeck_static - coulomb) * decay
    direction = sp.sign(dq) if link.coulomb_width is None else sp.tanh(dq / link.coulomb_width)
    return coulomb * direction + link.viscous * dq


@dataclass(frozen=True)
class Dynamics:
    """``M``, ``C``, ``c``, ``G`` and friction ``F`` of a robot, from one method.

    ``coriolis_matrix`` may be ``None`` when it was not asked for (it costs the most).
    """

    method: str
    q: tuple[sp.Symbol, ...]
    dq: tuple[sp.Symbol, ...]
    ddq: tuple[sp.Symbol, ...]
    mass_matrix: sp.ImmutableMatrix
    coriolis_vector: sp.ImmutableMatrix
    gravity_vector: sp.ImmutableMatrix
    friction: sp.ImmutableMatrix
    coriolis_matrix: sp.ImmutableMatrix | None = None
    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()

    @property
    def inverse_dynamics(self) -> sp.ImmutableMatrix:
        """``tau = M ddq + c + G + F``."""
        ddq = sp.Matrix(self.ddq)
        return sp.ImmutableMatrix(
            self.mass_matrix * ddq + self.coriolis_vector + self.gravity_vector + self.friction
        )

    def expanded(self, matrix: sp.MatrixBase) -> sp.ImmutableMatrix:
        """``matrix`` with every named intermediate substituted back (small robots only)."""
        values: dict[sp.Symbol, sp.Expr] = {}
        for symbol, expr in self.assignments:
            values[symbol] = expr.xreplace(values)
        return sp.ImmutableMatrix(matrix.xreplace(values))


def motor_inertia_matrix(robot: Robot) -> sp.ImmutableMatrix:
    """``diag(Ia_1, ..., Ia_n)`` of the reflected rotor inertias (0 where not given).

    An elastic joint's rotor sits behind its spring, on the motor side (inertia ``B``, see
    :mod:`symkin.derive.elastic`), so it is 0 here.
    """
    return sp.ImmutableMatrix(
        sp.diag(
            *(
                j.link.motor_inertia if j.link and not j.link.is_elastic else sp.Integer(0)
                for j in robot.joints
            )
        )
    )


def friction_vector(robot: Robot, dq: Sequence[sp.Symbol]) -> sp.ImmutableMatrix:
    """``F(dq)`` for every joint (0 for a joint without friction data)."""
    return sp.ImmutableMatrix(
        [
            friction_torque(joint.link, v) if joint.link else sp.Integer(0)
            for joint, v in zip(robot.joints, dq, strict=True)
        ]
    )
