"""A small, deliberately naive NumPy model of a DH robot, written from the conventions text.

It is the *independent* reference for the derivation tests: nothing here calls symkin's
derivations or its closed-form DH matrices.

* Link transforms are products of elementary 4x4 matrices, exactly as the conventions state
  them: standard DH ``A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha)``, modified DH
  ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta) Tz(d)``.
* Revolute: ``theta_i = q_i + theta``; prismatic: ``d_i = q_i + d``.
* ``T = base A_1 ... A_n tool``.
* The geometric Jacobian comes from differentiating the pose numerically: linear rows are
  ``dp/dq_i``, angular rows ``vee(dR/dq_i R^T)``.  No cross-product column formula is used.
  Two differentiation schemes: central differences (the default) and the complex step
  (``Im f(q + i h e_k) / h``, exact to rounding because the pose is analytic in ``q``), used
  where a test needs machine-precision derivatives (determinants at singularities).

Only the inputs are taken from a loaded :class:`symkin.robot.Robot`: its DH entries with the
parameter values substituted (SymPy -> float) and, unless given explicitly, base and tool.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache

import numpy as np
import sympy as sp

from symkin.derive import Model, derive
from symkin.io.robot_file import load_robot, robot_from_toml
from symkin.robot import Robot

# ---------------------------------------------------------------------------------------------
# Elementary transforms (work for float and complex arguments)
# ---------------------------------------------------------------------------------------------


def _dtype(*values: complex) -> type:
    return complex if any(isinstance(v, complex) or np.iscomplexobj(v) for v in values) else float


def Rx(angle: complex) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]], dtype=_dtype(angle))


def Ry(angle: complex) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=_dtype(angle))


def Rz(angle: complex) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=_dtype(angle))


def Tx(distance: complex) -> np.ndarray:
    matrix = np.eye(4, dtype=_dtype(distance))
    matrix[0, 3] = distance
    return matrix


def Ty(distance: complex) -> np.ndarray:
    matrix = np.eye(4, dtype=_dtype(distance))
    matrix[1, 3] = distance
    return matrix


def Tz(distance: complex) -> np.ndarray:
    matrix = np.eye(4, dtype=_dtype(distance))
    matrix[2, 3] = distance
    return matrix


def standard_dh(theta: complex, d: complex, a: complex, alpha: complex) -> np.ndarray:
    """``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` as a product of elementary transforms."""
    return Rz(theta) @ Tz(d) @ Tx(a) @ Rx(alpha)


def modified_dh(theta: complex, d: complex, a: complex, alpha: complex) -> np.ndarray:
    """``Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)`` (the row holds alpha, a before it)."""
    return Rx(alpha) @ Tx(a) @ Rz(theta) @ Tz(d)


def frame(xyz: Sequence[float], rpy: Sequence[float]) -> np.ndarray:
    """A fixed transform from a translation and fixed-axis roll, pitch, yaw (radians).

    Roll about X, then pitch about Y, then yaw about Z (fixed axes):
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``.
    """
    roll, pitch, yaw = rpy
    return Tx(xyz[0]) @ Ty(xyz[1]) @ Tz(xyz[2]) @ Rz(yaw) @ Ry(pitch) @ Rx(roll)


def euler_zyx(R: np.ndarray) -> np.ndarray:
    """``(psi, theta, phi)`` with ``R = Rz(psi) Ry(theta) Rx(phi)`` (away from theta = +-90 deg)."""
    psi = np.arctan2(R[1, 0], R[0, 0])
    theta = np.arctan2(-R[2, 0], np.hypot(R[0, 0], R[1, 0]))
    phi = np.arctan2(R[2, 1], R[2, 2])
    return np.array([psi, theta, phi])


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles mapped to [-pi, pi)."""
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi


def vee(skew: np.ndarray) -> np.ndarray:
    """The vector of a 3x3 skew-symmetric matrix (its symmetric part, rounding, dropped)."""
    s = 0.5 * (skew - skew.T)
    return np.array([s[2, 1], s[0, 2], s[1, 0]])


# ---------------------------------------------------------------------------------------------
# A robot as numbers
# ---------------------------------------------------------------------------------------------


def _number(expr: sp.Expr, values: Mapping[sp.Symbol, float]) -> float:
    return float(sp.sympify(expr).xreplace(values))


@dataclass(frozen=True)
class NumericRobot:
    """DH table as floats: ``rows[i] = (type, theta, d, a, alpha)`` (radians, SI)."""

    rows: tuple[tuple[str, float, float, float, float], ...]
    convention: str
    base: np.ndarray
    tool: np.ndarray

    @classmethod
    def from_robot(
        cls,
        robot: object,
        overrides: Mapping[str, float] | None = None,
        *,
        base: np.ndarray | None = None,
        tool: np.ndarray | None = None,
    ) -> NumericRobot:
        """Numbers of a loaded ``symkin.robot.Robot`` (parameter values substituted)."""
        values = {
            sp.Symbol(name, real=True): value
            for name, value in robot.parameter_values(overrides).items()
        }
        rows = tuple(
            (
                joint.type,
                _number(joint.theta, values),
                _number(joint.d, values),
                _number(joint.a, values),
                _number(joint.alpha, values),
            )
            for joint in robot.joints
        )

        def matrix(given: np.ndarray | None, symbolic: sp.MatrixBase) -> np.ndarray:
            if given is not None:
                return np.asarray(given, dtype=float)
            return np.array(sp.Matrix(symbolic).xreplace(values).evalf(), dtype=float)

        return cls(rows, robot.convention, matrix(base, robot.base), matrix(tool, robot.tool))

    @property
    def dof(self) -> int:
        return len(self.rows)

    def link_transforms(self, q: Sequence[complex]) -> list[np.ndarray]:
        product = standard_dh if self.convention == "standard" else modified_dh
        links = []
        for (kind, theta, d, a, alpha), qi in zip(self.rows, q, strict=True):
            if kind == "revolute":
                links.append(product(qi + theta, d, a, alpha))
            else:
                links.append(product(theta, qi + d, a, alpha))
        return links

    def frames(self, q: Sequence[complex]) -> list[np.ndarray]:
        """``T_0_0 = base, T_0_1, ..., T_0_n``."""
        result = [self.base.astype(np.asarray(q).dtype)]
        for link in self.link_transforms(q):
            result.append(result[-1] @ link)
        return result

    def fk(self, q: Sequence[complex]) -> np.ndarray:
        """``T = base A_1 ... A_n tool``."""
        return self.frames(q)[-1] @ self.tool

    # -- Jacobians by numerical differentiation -------------------------------------------------

    def pose_derivatives(
        self,
        q: Sequence[float],
        method: str = "central",
        h: float | None = None,
        pose: Callable[[np.ndarray], np.ndarray] | None = None,
    ) -> list[np.ndarray]:
        """``dT/dq_k`` for every k (4x4 each) of ``pose`` (default: the tool pose ``fk``)."""
        pose = pose or self.fk
        q = np.asarray(q, dtype=float)
        derivatives = []
        for k in range(len(q)):
            step = np.zeros(len(q))
            step[k] = 1.0
            if method == "central":
                hk = 1e-6 if h is None else h
                derivatives.append((pose(q + hk * step) - pose(q - hk * step)) / (2 * hk))
            elif method == "complex":
                hk = 1e-30 if h is None else h
                derivatives.append(np.imag(pose(q + 1j * hk * step)) / hk)
            else:
                raise ValueError(method)
        return derivatives

    def jacobian(
        self, q: Sequence[float], method: str = "central", h: float | None = None
    ) -> np.ndarray:
        """6 x n geometric Jacobian in the base frame: ``[dp/dq_k; vee(dR/dq_k R^T)]``."""
        R = self.fk(np.asarray(q, dtype=float))[:3, :3]
        columns = []
        for dT in self.pose_derivatives(q, method, h):
            columns.append(np.concatenate([dT[:3, 3], vee(dT[:3, :3] @ R.T)]))
        return np.array(columns).T

    def point(self, q: Sequence[float], link: int, r: Sequence[float]) -> np.ndarray:
        """Base-frame position of a point with coordinates ``r`` in frame ``link``."""
        return (self.frames(q)[link] @ np.array([*r, 1.0]))[:3]


ROW_NAMES = ("x", "y", "z", "wx", "wy", "wz")


def task_rows(jacobian: np.ndarray, rows: Sequence[str]) -> np.ndarray:
    """The named rows of a 6 x n Jacobian."""
    return jacobian[[ROW_NAMES.index(r) for r in rows], :]


# ---------------------------------------------------------------------------------------------
# Evaluating symkin's expressions (the thing under test) with parameter values substituted
# ---------------------------------------------------------------------------------------------


def numeric_function(
    expr: sp.Basic,
    robot: object,
    args: Sequence[Sequence[sp.Symbol]],
    overrides: Mapping[str, float] | None = None,
) -> Callable[..., np.ndarray]:
    """``f(*arrays)`` evaluating ``expr`` (matrix or scalar) as float64 NumPy values.

    ``args`` are groups of symbols (e.g. ``(model.q, model.dq)``); each group is passed as one
    sequence.  Parameters are replaced by their values before lambdifying.
    """
    values = {
        sp.Symbol(name, real=True): sp.Float(value)
        for name, value in robot.parameter_values(overrides).items()
    }
    substituted = expr.xreplace(values) if isinstance(expr, sp.Basic) else expr
    if isinstance(substituted, sp.MatrixBase):
        substituted = sp.ImmutableMatrix(substituted)
    leftover = substituted.free_symbols - {s for group in args for s in group}
    if leftover:
        raise AssertionError(f"unexpected free symbols {leftover} in {expr}")
    function = sp.lambdify([list(group) for group in args], substituted, modules="numpy")

    def evaluate(*arrays: Sequence[float]) -> np.ndarray:
        result = function(*[list(np.asarray(a, dtype=float)) for a in arrays])
        return np.array(result, dtype=float)

    return evaluate


# ---------------------------------------------------------------------------------------------
# The robots under test: the catalogue plus hand-written files, each with its reference model
# ---------------------------------------------------------------------------------------------

CATALOGUE = (
    "cylindrical_rtt_wrist",
    "panda",
    "planar_2r",
    "planar_3r",
    "puma560",
    "rpr",
    "scara",
    "stanford",
    "ur5",
)
DEG = math.pi / 180
SAMPLES = 5

# Standard DH: revolute and prismatic joints with constant theta (prismatic), negative a and d,
# angle expressions, base and tool, and a parameter ("h") that has no value in the file.
# Base and tool angles are multiples of 30/45/90 deg on purpose: with generic degrees
# (e.g. rpy = [10, 20, 30]) symkin's expanded expressions grow so large that the tool-frame
# Jacobian of this 4-DOF arm takes ~10 minutes and cannot be lambdified (see the report).
HAND_STANDARD = """
name = "hand_standard"
convention = "standard"
angles = "deg"

[parameters]
a1 = -0.3
d2 = -0.2
h = "symbol"

[[joints]]
type = "revolute"
theta = 30
d = "h"
a = "a1"
alpha = 90

[[joints]]
type = "prismatic"
theta = 60
d = "d2"
a = -0.15
alpha = -90

[[joints]]
type = "revolute"
d = -0.1
a = 0.25
alpha = 90

[[joints]]
type = "revolute"
theta = "pi/7"
a = "2*a1"
alpha = "-pi/3"

[base]
xyz = [0.1, -0.2, 0.3]
rpy = [90, 0, 30]

[tool]
xyz = [0.05, -0.02, 0.12]
rpy = [0, -90, 45]
"""
HAND_STANDARD_OVERRIDES = {"h": 0.42}
HAND_STANDARD_BASE = frame([0.1, -0.2, 0.3], [90 * DEG, 0.0, 30 * DEG])
HAND_STANDARD_TOOL = frame([0.05, -0.02, 0.12], [0.0, -90 * DEG, 45 * DEG])

# Modified DH (Craig) with a prismatic joint, negative a and d, radians, base and tool.
HAND_MODIFIED = """
name = "hand_modified"
convention = "modified"
angles = "rad"

[parameters]
l = 0.4

[[joints]]
type = "revolute"
d = 0.25

[[joints]]
type = "revolute"
a = 0.05
d = -0.07
alpha = "-pi/2"

[[joints]]
type = "prismatic"
theta = 0.3
a = "l"
d = 0.1
alpha = "pi/2"

[[joints]]
type = "revolute"
theta = -0.4
a = -0.12
alpha = 0.7

[base]
xyz = [0, 0, 0.5]
rpy = [0, 0, 1.2]

[tool]
xyz = [0, 0.03, 0.09]
rpy = [0.3, 0.2, 0.1]
"""
HAND_MODIFIED_BASE = frame([0, 0, 0.5], [0, 0, 1.2])
HAND_MODIFIED_TOOL = frame([0, 0.03, 0.09], [0.3, 0.2, 0.1])

HAND = ("hand_standard", "hand_modified")
ALL_ROBOTS = CATALOGUE + HAND


@cache
def robot(name: str) -> Robot:
    if name == "hand_standard":
        return robot_from_toml(HAND_STANDARD, "hand_standard.toml")
    if name == "hand_modified":
        return robot_from_toml(HAND_MODIFIED, "hand_modified.toml")
    return load_robot(name)


def overrides(name: str) -> dict[str, float] | None:
    return HAND_STANDARD_OVERRIDES if name == "hand_standard" else None


@cache
def model(name: str) -> Model:
    return derive(robot(name))


@cache
def reference(name: str) -> NumericRobot:
    """The independent model; hand robots get base and tool computed here from xyz/rpy."""
    if name == "hand_standard":
        return NumericRobot.from_robot(
            robot(name), overrides(name), base=HAND_STANDARD_BASE, tool=HAND_STANDARD_TOOL
        )
    if name == "hand_modified":
        return NumericRobot.from_robot(
            robot(name), base=HAND_MODIFIED_BASE, tool=HAND_MODIFIED_TOOL
        )
    return NumericRobot.from_robot(robot(name))


def function(name: str, expr: sp.Basic, *extra: Sequence[sp.Symbol]) -> Callable[..., np.ndarray]:
    """``expr`` of robot ``name`` as a NumPy function of ``q`` (and of ``extra`` groups)."""
    m = model(name)
    return numeric_function(expr, robot(name), (m.q, *extra), overrides(name))


def random_q(name: str, rng: np.random.Generator) -> np.ndarray:
    """Revolute joints in (-pi, pi), prismatic joints in (-1, 1)."""
    return np.array(
        [
            rng.uniform(-np.pi, np.pi) if j.type == "revolute" else rng.uniform(-1.0, 1.0)
            for j in robot(name).joints
        ]
    )


def samples(name: str, seed: int, count: int = SAMPLES) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [random_q(name, rng) for _ in range(count)]


def without_inertials(name: str) -> str:
    """The catalogue file of ``name`` without its ``[joints.link]`` tables: the same robot with
    symbolic inertial parameters (m1, cx1, ...), for tests of the ``pi`` input.  Since issue 21
    every catalogue robot carries inertial data."""
    import re
    from pathlib import Path

    import symkin

    text = (Path(symkin.__file__).parent / "robots" / f"{name}.toml").read_text(encoding="utf-8")
    return re.sub(r"(?m)^(?:#.*\n)?\[joints\.link\]\n(?:[^\[\n].*\n)*", "", text)
