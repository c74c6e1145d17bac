"""Kinetic and potential energy and the Lagrangian of the rigid-body model.

    T = 1/2 dq^T M(q) dq                        (rotor inertias included, as in M)
    V = -sum_i m_i g^T p_ci                     (g: the gravity vector, e.g. (0, 0, -9.81))
    L = T - V

``p_ci`` is the centre of mass of link i in the base frame.  With this sign ``V`` grows as a
mass rises against gravity and ``G = dV/dq`` (Spong, Hutchinson, Vidyasagar, eqs. 7.53,
7.57), and along any motion ``dT/dt + dV/dt = dq^T (tau - F)`` (the power balance the tests
check).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.derive.dynamics import Dynamics, link_inertial_data
from symkin.derive.kinematics import Kinematics
from symkin.robot import Robot


def kinetic_energy(mass_matrix: sp.MatrixBase, dq: Sequence[sp.Symbol]) -> sp.Expr:
    """``T = 1/2 dq^T M dq``, the symmetric quadratic form written once per pair of joints."""
    n = len(dq)
    diagonal = sum(mass_matrix[i, i] * dq[i] ** 2 for i in range(n)) / 2
    return diagonal + sum(mass_matrix[i, j] * dq[i] * dq[j] for i in range(n) for j in range(i))


def potential_energy(robot: Robot, kinematics: Kinematics) -> sp.Expr:
    """``V = -sum_i m_i g^T p_ci`` (zero at the base origin's height)."""
    gravity = sp.Matrix(robot.gravity)
    total = sp.Integer(0)
    for i in range(robot.dof):
        data = link_inertial_data(robot, i)
        frame = kinematics.frame_transforms[i + 1]
        centre = sp.Matrix(frame[:3, :3]) * sp.Matrix(data.com) + sp.Matrix(frame[:3, 3])
        total -= data.mass * (gravity.T * centre)[0, 0]
    return total


@dataclass(frozen=True)
class Energies:
    """``T``, ``V`` and ``L = T - V``; ``T`` may use the named intermediates ``assignments``
    of the Newton–Euler mass matrix (``Dynamics.expanded`` substitutes them back)."""

    kinetic: sp.Expr
    potential: sp.Expr
    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()

    @property
    def lagrangian(self) -> sp.Expr:
        """``L = T - V``."""
        return self.kinetic - self.potential


def energies_from_dynamics(robot: Robot, kinematics: Kinematics, dynamics: Dynamics) -> Energies:
    """:class:`Energies` of ``robot`` from the mass matrix of ``dynamics``."""
    return Energies(
        kinetic=kinetic_energy(dynamics.mass_matrix, dynamics.dq),
        potential=potential_energy(robot, kinematics),
        assignments=dynamics.assignments,
    )
