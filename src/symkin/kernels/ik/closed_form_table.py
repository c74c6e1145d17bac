"""A robot's DH table as numbers, in the one form the closed-form solvers read.

The closed forms (``docs/ik-closed-form.md``) are written for **standard (distal) DH**,
``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``.  A modified-DH (Craig) table becomes a
standard one with the same kinematics: in ``base · Π Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i)
Tz(d_i) · tool`` the leading ``Rx(alpha_0) Tx(a_0)`` joins the base, and row i of the
standard table takes ``theta_i, d_i`` from row i and ``a_i, alpha_i`` from row i+1 (``Rx`` and
``Tx`` commute, both act along x); the last row gets ``a_n = alpha_n = 0``.

Only numbers live here: parameter values are substituted once per robot, so nothing per pose
touches SymPy.  The recognisers ask the small predicates below (``is_zero``, ``twist_sign``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from symkin.robot import Robot

#: A twist angle counts as 0 or +-90 deg when its sine or cosine is this close to 0.
ANGLE_TOL = 1e-12
#: A DH length counts as zero when it is below this fraction of the robot's size.
LENGTH_TOL = 1e-12
#: Stand-in for a parameter that has no value when only the structure is asked for: an
#: irrational-looking, non-zero length, so it is never mistaken for a special value.
GENERIC_LENGTH = 0.5772156649015329


@dataclass(frozen=True, eq=False)
class NumericChain:
    """``T = base · A_1(q_1) ⋯ A_n(q_n) · tool`` in standard DH, all entries floats.

    Revolute joint i: ``theta_i = q_i + theta[i]``, ``d[i]`` constant; prismatic joint i:
    ``d_i = q_i + d[i]``, ``theta[i]`` constant (radians, SI).  ``base`` includes the
    ``Rx(alpha_0) Tx(a_0)`` of a modified-DH table.
    """

    kinds: tuple[str, ...]
    theta: tuple[float, ...]
    d: tuple[float, ...]
    a: tuple[float, ...]
    alpha: tuple[float, ...]
    base: np.ndarray
    tool: np.ndarray

    @property
    def dof(self) -> int:
        return len(self.kinds)

    @property
    def size(self) -> float:
        """A length scale of the robot (at least 1): sum of |a|, |d|, base and tool offsets."""
        lengths = sum(abs(x) for x in (*self.a, *self.d))
        offsets = float(np.linalg.norm(self.base[:3, 3]) + np.linalg.norm(self.tool[:3, 3]))
        return max(1.0, lengths + offsets)

    def is_zero_length(self, value: float) -> bool:
        return abs(value) <= LENGTH_TOL * self.size


def is_zero(value: float) -> bool:
    """True if ``value`` (a sine or cosine of a twist) is zero up to :data:`ANGLE_TOL`."""
    return abs(value) <= ANGLE_TOL


def twist_sign(alpha: float) -> int:
    """+1 or -1 for a twist of +-90 deg (``sin alpha = +-1``), 0 for any other twist."""
    if not is_zero(math.cos(alpha)):
        return 0
    return 1 if math.sin(alpha) > 0 else -1


def is_parallel(alpha: float) -> bool:
    """True for a twist of 0 (mod 2 pi): the next joint axis is parallel, same direction."""
    return is_zero(math.sin(alpha)) and math.cos(alpha) > 0


def rot_x(angle: float) -> np.ndarray:
    """``Rx(angle)`` as a 3x3 float array."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_z(angle: float) -> np.ndarray:
    """``Rz(angle)`` as a 3x3 float array."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def homogeneous(rotation: np.ndarray, translation: np.ndarray | tuple = (0, 0, 0)) -> np.ndarray:
    """The 4x4 transform ``[R p; 0 0 0 1]``."""
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = translation
    return transform


def rigid_inverse(transform: np.ndarray) -> np.ndarray:
    """``[R^T, -R^T p; 0 1]``: the inverse of a rigid transform without a general inverse."""
    rotation = transform[:3, :3].T
    return homogeneous(rotation, -rotation @ transform[:3, 3])


def parameter_numbers(
    robot: Robot, overrides: Mapping[str, float] | None, generic: bool
) -> dict[sp.Symbol, float]:
    """Parameter symbols -> values.  With ``generic`` a parameter without a value gets
    :data:`GENERIC_LENGTH` instead of an error (used to judge structure only)."""
    if generic:
        given = dict(overrides or {})
        return {
            sp.Symbol(name, real=True): float(
                given.get(name, value if value is not None else GENERIC_LENGTH)
            )
            for name, value in robot.parameters
        }
    values = robot.parameter_values(overrides)
    return {sp.Symbol(name, real=True): values[name] for name in values}


def chain_from_robot(
    robot: Robot, overrides: Mapping[str, float] | None = None, generic: bool = False
) -> NumericChain:
    """The robot's table as a standard-DH :class:`NumericChain` (module docstring)."""
    numbers = parameter_numbers(robot, overrides, generic)

    def number(expr: sp.Expr) -> float:
        return float(sp.sympify(expr).xreplace(numbers))

    def matrix(expr: sp.MatrixBase) -> np.ndarray:
        return np.array(expr.xreplace(numbers).evalf(), dtype=float)

    joints = robot.joints
    rows = [(number(j.theta), number(j.d), number(j.a), number(j.alpha)) for j in joints]
    base, tool = matrix(robot.base), matrix(robot.tool)
    theta = tuple(r[0] for r in rows)
    d = tuple(r[1] for r in rows)
    if robot.convention == "modified":
        prefix = homogeneous(rot_x(rows[0][3]), (rows[0][2], 0.0, 0.0))
        base = base @ prefix
        a = (*(r[2] for r in rows[1:]), 0.0)
        alpha = (*(r[3] for r in rows[1:]), 0.0)
    else:
        a = tuple(r[2] for r in rows)
        alpha = tuple(r[3] for r in rows)
    return NumericChain(
        kinds=tuple(j.type for j in joints),
        theta=theta,
        d=d,
        a=a,
        alpha=alpha,
        base=base,
        tool=tool,
    )
