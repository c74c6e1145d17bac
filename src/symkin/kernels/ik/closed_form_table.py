"""A robot's DH table in the one form the closed-form solvers read, with SymPy entries
(:class:`SymbolicChain`, the source of every constant) and as numbers (:class:`NumericChain`,
that chain evaluated at the parameter values, read by the recognisers).

The closed forms (``docs/ik-closed-form.md``) are written for **standard (distal) DH**,
``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``.  A modified-DH (Craig) table becomes a
standard one with the same kinematics: in ``base · Π Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i)
Tz(d_i) · tool`` the leading ``Rx(alpha_0) Tx(a_0)`` joins the base, and row i of the
standard table takes ``theta_i, d_i`` from row i and ``a_i, alpha_i`` from row i+1 (``Rx`` and
``Tx`` commute, both act along x); the last row gets ``a_n = alpha_n = 0``.

The recognisers ask the small predicates below (``is_zero``, ``twist_sign``) of the numbers.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from symkin.robot import Robot
from symkin.spatial import rot_x, transform_from_rotation_translation
from symkin.symbols import parameter_symbol

#: A twist angle counts as 0 or +-90 deg when its sine or cosine is this close to 0.
ANGLE_TOL = 1e-12
#: A DH length counts as zero when it is below this fraction of the robot's size.
LENGTH_TOL = 1e-12
#: Stand-in for a parameter that has no value when only the structure is asked for: an
#: irrational-looking, non-zero length, so it is never mistaken for a special value.
GENERIC_LENGTH = 0.5772156649015329

#: Parameter symbols -> values, the numbers a chain or a constant is evaluated at.
Numbers = Mapping[sp.Symbol, float]


def translation_rotation(rotation: sp.Matrix, x: sp.Expr = sp.S.Zero) -> sp.Matrix:
    """``Tx(x) R`` as a 4x4 transform (``Tx(a) Rx(alpha)`` for ``R = Rx(alpha)``)."""
    return sp.Matrix(transform_from_rotation_translation(rotation, sp.Matrix([x, 0, 0])))


def number(expr: sp.Expr, numbers: Numbers) -> float:
    """``expr`` at the parameter values ``numbers``, as a float."""
    return float(sp.sympify(expr).xreplace(numbers))


@dataclass(frozen=True)
class SymbolicChain:
    """``T = base · A_1(q_1) ⋯ A_n(q_n) · tool`` in standard DH, entries in the parameters.

    Revolute joint i: ``theta_i = q_i + theta[i]``, ``d[i]`` constant; prismatic joint i:
    ``d_i = q_i + d[i]``, ``theta[i]`` constant (radians, SI).  ``base`` includes the
    ``Rx(alpha_0) Tx(a_0)`` of a modified-DH table.
    """

    kinds: tuple[str, ...]
    theta: tuple[sp.Expr, ...]
    d: tuple[sp.Expr, ...]
    a: tuple[sp.Expr, ...]
    alpha: tuple[sp.Expr, ...]
    base: sp.Matrix
    tool: sp.Matrix

    @property
    def size(self) -> sp.Expr:
        """A length scale of the robot (at least 1): sum of |a|, |d|, base and tool offsets."""
        lengths = sum(sp.Abs(x) for x in (*self.a, *self.d))
        offsets = self.base[:3, 3].norm() + self.tool[:3, 3].norm()
        return sp.Max(1, lengths + offsets)

    def at(self, numbers: Numbers) -> NumericChain:
        """This chain at the parameter values ``numbers``."""

        def floats(values: tuple[sp.Expr, ...]) -> tuple[float, ...]:
            return tuple(number(x, numbers) for x in values)

        def matrix(value: sp.Matrix) -> np.ndarray:
            return np.array(value.xreplace(numbers).evalf(), dtype=float)

        return NumericChain(
            kinds=self.kinds,
            theta=floats(self.theta),
            d=floats(self.d),
            a=floats(self.a),
            alpha=floats(self.alpha),
            base=matrix(self.base),
            tool=matrix(self.tool),
            size=number(self.size, numbers),
        )


@dataclass(frozen=True, eq=False)
class NumericChain:
    """:class:`SymbolicChain` with float entries; ``size`` its length scale (at least 1)."""

    kinds: tuple[str, ...]
    theta: tuple[float, ...]
    d: tuple[float, ...]
    a: tuple[float, ...]
    alpha: tuple[float, ...]
    base: np.ndarray
    tool: np.ndarray
    size: float

    @property
    def dof(self) -> int:
        return len(self.kinds)

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


def parameter_numbers(
    robot: Robot, overrides: Mapping[str, float] | None, generic: bool
) -> dict[sp.Symbol, float]:
    """Parameter symbols -> values.  With ``generic`` a parameter without a value gets
    :data:`GENERIC_LENGTH` instead of an error (used to judge structure only)."""
    if generic:
        given = dict(overrides or {})
        return {
            parameter_symbol(name): float(
                given.get(name, value if value is not None else GENERIC_LENGTH)
            )
            for name, value in robot.parameters
        }
    values = robot.parameter_values(overrides)
    return {parameter_symbol(name): values[name] for name in values}


@lru_cache(maxsize=64)
def symbolic_chain(robot: Robot) -> SymbolicChain:
    """The robot's table as a standard-DH :class:`SymbolicChain` (module docstring)."""
    joints = robot.joints
    theta = tuple(sp.sympify(j.theta) for j in joints)
    d = tuple(sp.sympify(j.d) for j in joints)
    base, tool = sp.Matrix(robot.base), sp.Matrix(robot.tool)
    if robot.convention == "modified":
        first = joints[0]
        base = base @ translation_rotation(rot_x(sp.sympify(first.alpha)), first.a)
        a = (*(sp.sympify(j.a) for j in joints[1:]), sp.S.Zero)
        alpha = (*(sp.sympify(j.alpha) for j in joints[1:]), sp.S.Zero)
    else:
        a = tuple(sp.sympify(j.a) for j in joints)
        alpha = tuple(sp.sympify(j.alpha) for j in joints)
    return SymbolicChain(tuple(j.type for j in joints), theta, d, a, alpha, base, tool)
