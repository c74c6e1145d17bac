"""Partial derivatives of the inverse dynamics, ``dtau/dq`` and ``dtau/ddq``, by the chain rule
through the Newton–Euler recursion's named intermediates (:mod:`symkin.derive.tangents`).

``tau(q, dq, ddq)`` comes from one recursion (:func:`~symkin.derive.newton_euler.
inverse_dynamics_recursion`); sweeping its trace once per joint coordinate and once per joint
velocity gives the two n x n matrices with entry (i, j) = ``d tau_i / d x_j`` (row = output
index).  ``dtau/dddq`` is the mass matrix ``M`` and is not derived again.  The forward
dynamics' derivatives follow numerically at run time (Carpentier & Mansard, *Analytical
Derivatives of Rigid Body Dynamics Algorithms*, RSS 2018, eq. 9)::

  dddq/dq = -M^-1 dtau/dq,   dddq/ddq = -M^-1 dtau/ddq,   dddq/dtau = M^-1,

each evaluated at ``ddq = FD(q, dq, tau)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.derive.tangents import Assignments, jacobian_columns, tangent_assignments


@dataclass(frozen=True)
class TorqueDerivatives:
    """``tau`` and its partial derivatives, all in the named intermediates ``assignments``."""

    assignments: Assignments
    torque: sp.ImmutableMatrix
    torque_q: sp.ImmutableMatrix  # d tau / d q   (n x n)
    torque_dq: sp.ImmutableMatrix  # d tau / d dq (n x n)


def torque_derivatives(
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    torque: sp.MatrixBase,
    q: Sequence[sp.Symbol],
    dq: Sequence[sp.Symbol],
) -> TorqueDerivatives:
    """``dtau/dq`` and ``dtau/ddq`` of a recursion's ``tau`` (one tangent sweep per column)."""
    by_position, torque_q = jacobian_columns(assignments, torque, q, "sq")
    by_velocity, torque_dq = jacobian_columns(assignments, torque, dq, "sv")
    return TorqueDerivatives(
        assignments=tuple(assignments) + by_position + by_velocity,
        torque=sp.ImmutableMatrix(torque),
        torque_q=torque_q,
        torque_dq=torque_dq,
    )


def time_derivative(
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    matrix: sp.MatrixBase,
    q: Sequence[sp.Symbol],
    dq: Sequence[sp.Symbol],
    prefix: str,
) -> tuple[Assignments, sp.ImmutableMatrix]:
    """``d matrix/dt = sum_k d matrix/dq_k dq_k`` along the motion: ONE tangent sweep with the
    seed ``qdot = dq`` (not n partials), so ``dJ/dt`` costs about one more Jacobian."""
    named, (rate,) = tangent_assignments(
        assignments, [matrix], dict(zip(q, dq, strict=True)), prefix
    )
    return named, rate
