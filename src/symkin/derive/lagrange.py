"""Lagrange's equations from the energies (for teaching and small robots).

Spong, Hutchinson, Vidyasagar, eqs. (7.49)-(7.60)::

    M = sum_i  m_i Jv_ci^T Jv_ci + Jw_i^T (R_i I_ci R_i^T) Jw_i
    P = sum_i -m_i g^T p_ci,            G_k = dP/dq_k
    C_kj = sum_i 1/2 (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) dq_i

``p_ci`` is the centre of mass of link i in the base frame, ``Jv_ci = dp_ci/dq`` and ``Jw_i``
the angular-velocity Jacobian of link i (joint axes up to i).  The algebra runs in SymEngine,
which is two orders of magnitude faster than SymPy on these products and derivatives; results
come back to SymPy, contracted into sums of angles.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import symengine as se
import sympy as sp

from symkin.derive.dynamics import (
    Dynamics,
    friction_vector,
    link_inertial_data,
    motor_inertia_matrix,
)
from symkin.derive.kinematics import Kinematics
from symkin.derive.simplify import (
    exact_from_floats,
    floats_from_exact,
    reduce_trig,
    symengine_matrix,
)
from symkin.robot import Robot
from symkin.symbols import unused_prefix

# Up to this many joints the results are expanded and contracted into readable sums.
READABLE_DOF = 3


def lagrange_dynamics(
    robot: Robot,
    kinematics: Kinematics,
    dq: Sequence[sp.Symbol],
    ddq: Sequence[sp.Symbol],
    coriolis_matrix: bool = True,
) -> Dynamics:
    """``M``, ``C``, ``c``, ``G`` from kinetic and potential energy.

    The readable form (up to ``READABLE_DOF`` joints) is computed in exact arithmetic, the
    robot's floats (inertial data, gravity, lengths) as decimal rationals, and printed back as
    floats where the robot gave floats: float algebra would leave ``1e-16`` remainders of
    ``sin^2 + cos^2 = 1`` in C."""
    n = robot.dof
    readable = n <= READABLE_DOF
    q = [se.sympify(s) for s in kinematics.q]
    # Gravity's floats (9.81) reach G only: M and C keep their fractions when the robot's
    # own data are exact.
    exact, exact_gravity = (_ExactArithmetic(), _ExactArithmetic()) if readable else (_same,) * 2
    mass, potential, free_symbols = _mass_and_potential(
        robot, kinematics, exact, exact_gravity(sp.Matrix(robot.gravity))
    )
    free_symbols |= set(kinematics.q) | set(dq)
    # SymEngine drops SymPy's assumptions; map the plain names back to our symbols.
    restore = {sp.Symbol(s.name): s for s in free_symbols}

    dq_se = se.DenseMatrix([se.sympify(v) for v in dq])
    christoffel = _christoffel(mass, q, list(dq_se))
    matrices = {
        "mass_matrix": mass,
        "coriolis_vector": christoffel * dq_se,
        "gravity_vector": se.DenseMatrix([potential.diff(qk) for qk in q]),
    }
    if coriolis_matrix:
        matrices["coriolis_matrix"] = christoffel
    if readable:
        decimals = dict.fromkeys(matrices, exact.met_float)
        decimals["gravity_vector"] = exact.met_float or exact_gravity.met_float
        converted = {
            name: _readable(matrix, restore, kinematics.q, decimals[name])
            for name, matrix in matrices.items()
        }
        assignments = ()
    else:
        converted, assignments = _shared(matrices, restore)
    return Dynamics(
        method="lagrange",
        q=kinematics.q,
        dq=tuple(dq),
        ddq=tuple(ddq),
        friction=friction_vector(robot, dq),
        assignments=assignments,
        **converted,
    )


def _mass_and_potential(
    robot: Robot,
    kinematics: Kinematics,
    exact: Callable[[sp.Basic], sp.Basic],
    gravity_vector: sp.Matrix,
) -> tuple[se.DenseMatrix, se.Basic, set[sp.Symbol]]:
    """``M`` and ``P`` of (7.49)-(7.53) in SymEngine, each robot quantity passed through
    ``exact`` first; and the SymPy symbols they contain (to restore assumptions later)."""
    n = robot.dof
    q = [se.sympify(s) for s in kinematics.q]
    gravity = symengine_matrix(gravity_vector)
    mass = se.zeros(n, n)
    potential = se.Integer(0)
    free_symbols: set[sp.Symbol] = set()
    for i in range(n):
        data = link_inertial_data(robot, i)
        frame = exact(kinematics.frame_transforms[i + 1])
        com = sp.Matrix(frame[:3, :3]) * exact(sp.Matrix(data.com)) + sp.Matrix(frame[:3, 3])
        rotation = symengine_matrix(sp.Matrix(frame[:3, :3]))
        inertia = symengine_matrix(exact(sp.Matrix(data.inertia_matrix)))
        free_symbols |= com.free_symbols | data.inertia_matrix.free_symbols
        free_symbols |= sp.sympify(data.mass).free_symbols
        com_se = symengine_matrix(com)
        linear = com_se.jacobian(se.DenseMatrix(q))
        angular = se.zeros(3, n)
        for j, joint_frame in enumerate(kinematics.joint_frames[: i + 1]):
            if robot.joints[j].type == "revolute":
                for r in range(3):
                    angular[r, j] = se.sympify(exact(joint_frame[r, 2]))
        world_inertia = rotation * inertia * rotation.T
        mass_i = se.sympify(exact(sp.sympify(data.mass)))
        mass += mass_i * linear.T * linear + angular.T * world_inertia * angular
        potential -= mass_i * (gravity.T * com_se)[0, 0]
    mass += symengine_matrix(exact(motor_inertia_matrix(robot)))
    free_symbols |= motor_inertia_matrix(robot).free_symbols
    return mass, potential, free_symbols


def _same(expr: sp.Basic) -> sp.Basic:
    return expr


class _ExactArithmetic:
    """:func:`exact_from_floats` that remembers whether it met a float: only then are the
    results' rationals printed back as floats (a robot given in exact numbers keeps its
    ``1/12`` and ``1/2``)."""

    def __init__(self) -> None:
        self.met_float = False

    def __call__(self, expr: sp.Basic) -> sp.Basic:
        self.met_float = self.met_float or bool(expr.atoms(sp.Float))
        return exact_from_floats(expr)


def _readable(
    matrix: se.DenseMatrix, restore: dict, q: Sequence[sp.Symbol], decimals: bool
) -> sp.ImmutableMatrix:
    """Expanded and contracted into sums of angles: for reading (small robots only); with
    ``decimals`` the exact coefficients are printed back as floats."""
    back = floats_from_exact if decimals else _same
    entries = [back(reduce_trig(sp.sympify(se.expand(e)).xreplace(restore), q)) for e in matrix]
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, entries)


def _shared(
    matrices: dict[str, se.DenseMatrix], restore: dict
) -> tuple[dict[str, sp.ImmutableMatrix], tuple[tuple[sp.Symbol, sp.Expr], ...]]:
    """Common subexpressions named ``l0, l1, ...`` (SymEngine's CSE; ``l_0, ...`` if the robot
    has a symbol ``l<k>``), then converted.

    Expanding a 6-DOF Coriolis matrix gives ~10^5 terms, and converting SymEngine's shared
    trees to SymPy term by term copies every shared subtree: minutes for the Panda.  Naming
    the shared parts first keeps each conversion small (seconds).
    """
    entries = [e for matrix in matrices.values() for e in matrix]
    found, reduced = se.cse(entries)
    prefix = unused_prefix("l", (symbol.name for symbol in restore.values()))
    names = {}
    assignments = []
    for k, (symbol, expr) in enumerate(found):
        names[sp.sympify(symbol)] = name = sp.Symbol(f"{prefix}{k}", real=True)
        assignments.append((name, sp.sympify(expr).xreplace(restore).xreplace(names)))
    values = iter(sp.sympify(e).xreplace(restore).xreplace(names) for e in reduced)
    converted = {
        key: sp.ImmutableMatrix(m.rows, m.cols, [next(values) for _ in range(m.rows * m.cols)])
        for key, m in matrices.items()
    }
    return converted, tuple(assignments)


def _christoffel(mass: se.DenseMatrix, q: list, dq: list) -> se.DenseMatrix:
    n = len(q)
    partial = [[[mass[r, c].diff(q[k]) for k in range(n)] for c in range(n)] for r in range(n)]
    result = se.zeros(n, n)
    for k in range(n):
        for j in range(n):
            result[k, j] = sum(
                (partial[k][j][i] + partial[k][i][j] - partial[i][j][k]) * dq[i] / 2
                for i in range(n)
            )
    return result
