"""Base inertial parameters: the fewest link parameters that give the same joint torques.

``tau`` is linear in each link's ten *barycentric* parameters (Khalil's standard
parameters): the inertia tensor about the link frame's origin, the first moment ``m c`` and
the mass (Khalil & Dombre, *Modeling, Identification and Control of Robots*, Ch. 9)::

    tau(q, dq, ddq) = Y(q, dq, ddq) delta

Some columns of ``Y`` are combinations of others (a link's mass along its joint axis acts like
inertia of the link before it, and so on), so ``Y delta = Y_b beta`` with ``beta = delta_b +
K delta_d``: the dependent parameters are folded into the independent ones and set to zero.
For a fully numeric robot this is computed numerically from ``Y`` at random states (Gautier,
"Numerical calculation of the base inertial parameters of robots", J. Robotic Systems 8(4),
1991); the recursion then runs with ``beta`` and has many zero parameters to skip.  The
torques are unchanged (checked at fresh random states before the result is used).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache, lru_cache

import numpy as np
import sympy as sp

from symkin.derive.dynamics import link_inertial_data
from symkin.derive.kinematics import Kinematics
from symkin.derive.recursion import (
    BarycentricParameters,
    barycentric_definitions,
    joint_torques,
    robot_recorder,
)
from symkin.robot import Robot

# Order in which columns are offered to the basis: a parameter is dropped (folded into the
# ones before it) when its column depends on earlier ones.  Inner links come first, and within
# a link the inertia, then the mass, then the first moments, so outer links' first moments are
# the ones folded in.  Of the orders tried this gives the PUMA 560 the shortest code (inverse
# dynamics 382 operations; 400 with the first moments before the mass).
PARAMETER_NAMES = ("zz", "yy", "xx", "yz", "xz", "xy", "m", "mz", "my", "mx")
SAMPLES = 15
RANK_TOLERANCE = 1e-8
# Base parameters keep this relative precision (13 significant digits at most); one whose
# size is below NEGLIGIBLE times the sizes folded into it is cancellation noise and zero.
SNAP = 1e-13
NEGLIGIBLE = 1e-12
# The folded model must give each torque to this tolerance relative to its own terms.
TORQUE_TOLERANCE = 1e-10


def has_numeric_geometry(robot: Robot, kinematics: Kinematics) -> bool:
    """The link transforms hold numbers and joint variables only (no parameters ``p``)."""
    if robot.parameters:
        return False
    geometry = set().union(*(t.free_symbols for t in kinematics.link_transforms))
    return geometry <= set(kinematics.q)


def is_numeric(robot: Robot, kinematics: Kinematics) -> bool:
    """Geometry and every link's inertial data are numbers (no parameters, no symbols)."""
    if not has_numeric_geometry(robot, kinematics) or any(j.link is None for j in robot.joints):
        return False
    links = [j.link for j in robot.joints]
    values = [sp.sympify(x) for link in links for x in (link.mass, *link.com, *link.inertia)]
    return all(v.is_number for v in values)


@dataclass(frozen=True)
class Folding:
    """How a geometry's barycentric parameters fold into its base parameters.

    Over the link-major list ``delta`` (``PARAMETER_NAMES`` for link 1, then link 2, ...):
    ``beta[kept] = delta[kept] + K delta[dropped]`` and ``beta[dropped] = 0`` give the same
    torques as ``delta`` for every state (Gautier 1991, eq. 13).
    """

    kept: tuple[int, ...]
    dropped: tuple[int, ...]
    matrix: tuple[tuple[float, ...], ...]  # K: a row per kept, a column per dropped parameter

    def beta(self, delta: np.ndarray) -> np.ndarray:
        """The base parameters of numeric barycentric parameters (zero where dropped)."""
        kept, dropped = list(self.kept), list(self.dropped)
        beta = np.zeros_like(delta, dtype=float)
        beta[kept] = delta[kept] + self._matrix() @ delta[dropped]
        return beta

    def magnitude(self, delta: np.ndarray) -> np.ndarray:
        """Per base parameter, the sum of the sizes of what is added into it
        (``|delta_k| + sum_d |K_kd delta_d|``): the scale its rounding error is relative to."""
        kept, dropped = list(self.kept), list(self.dropped)
        size = np.zeros_like(delta, dtype=float)
        size[kept] = np.abs(delta[kept]) + np.abs(self._matrix()) @ np.abs(delta[dropped])
        return size

    def _matrix(self) -> np.ndarray:
        return np.array(self.matrix).reshape(len(self.kept), len(self.dropped))


@lru_cache(maxsize=16)
def _regressor(robot: Robot, kinematics: Kinematics):
    """``seed -> Y``: the regressor's columns (one per barycentric parameter) stacked over
    ``SAMPLES`` random states drawn from ``seed``."""

    n = robot.dof
    flat = barycentric_symbols(n)
    dq = sp.symbols(f"dq1:{n + 1}", real=True)
    ddq = sp.symbols(f"ddq1:{n + 1}", real=True)
    recorder = robot_recorder(robot, "b")
    links = barycentric_links(flat)
    torque = joint_torques(robot, kinematics, recorder, dq, ddq, robot.gravity, links)
    # All columns of Y in one call: the parameters are passed as the rows of the identity.
    regressor_of = sp.lambdify(
        [kinematics.q, dq, ddq, flat],
        torque,
        modules="numpy",
        cse=lambda e: (recorder.assignments, e),
    )
    identity = list(np.eye(len(flat)))

    # Cached: the folding and the numeric base parameters both check at the same fresh states.
    @cache
    def regressor(seed: int) -> np.ndarray:
        rng = np.random.default_rng(seed)
        rows = []
        for _ in range(SAMPLES):
            state = rng.uniform(-2.0, 2.0, (3, n))
            columns = regressor_of(*state, identity)
            rows.append(np.array([np.broadcast_to(c, len(flat)) for c in columns], dtype=float))
        return np.vstack(rows)

    return regressor


@lru_cache(maxsize=16)
def base_parameter_folding(robot: Robot, kinematics: Kinematics) -> Folding | None:
    """The folding of a robot with numeric geometry (its inertial data play no part), or
    ``None`` when the geometry has parameters or the folding fails its check at fresh states."""
    if not has_numeric_geometry(robot, kinematics):
        return None
    regressor = _regressor(robot, kinematics)
    return folding_from_samples(regressor(seed=1), regressor(seed=2))


def folding_from_samples(Y: np.ndarray, check: np.ndarray) -> Folding | None:
    """The folding of the columns of ``Y`` (the regressor stacked over random states): each
    column is kept when it is independent of the kept ones before it (Gautier 1991), the
    others are their least-squares combination.  ``None`` unless the folded parameters give
    the same torques as random ones at the other states ``check``."""
    tolerance = RANK_TOLERANCE * np.linalg.norm(Y)
    kept: list[int] = []
    for k in range(Y.shape[1]):
        if np.linalg.matrix_rank(Y[:, [*kept, k]], tol=tolerance) == len(kept) + 1:
            kept.append(k)
    dropped = [k for k in range(Y.shape[1]) if k not in kept]
    matrix, *_ = np.linalg.lstsq(Y[:, kept], Y[:, dropped], rcond=None)
    # Least squares leaves noise where a dropped parameter does not fold into a kept one.
    matrix[np.abs(matrix) <= NEGLIGIBLE * np.max(np.abs(matrix), initial=0.0)] = 0.0
    folding = Folding(tuple(kept), tuple(dropped), tuple(map(tuple, matrix.tolist())))
    delta = np.random.default_rng(3).uniform(-1.0, 1.0, Y.shape[1])
    error = np.max(np.abs(check @ folding.beta(delta) - check @ delta))
    return folding if error <= 1e-9 * max(1.0, np.max(np.abs(check @ delta))) else None


@lru_cache(maxsize=16)
def base_parameters(
    robot: Robot, kinematics: Kinematics
) -> tuple[BarycentricParameters, ...] | None:
    """Per-link parameters with the dependent ones folded in and zeroed, or ``None`` when the
    robot is not fully numeric (then the recursion keeps the file's parameters)."""
    if not is_numeric(robot, kinematics):
        return None
    folding = base_parameter_folding(robot, kinematics)
    if folding is None:
        return None
    links = [barycentric_definitions(link_inertial_data(robot, i)) for i in range(robot.dof)]
    delta = np.array([float(link[name]) for link in links for name in PARAMETER_NAMES])
    beta = folding.beta(delta)
    # Each value is rounded relative to itself (the shortest decimal within SNAP of its own
    # size), never relative to the largest parameter: one large first moment must not coarsen
    # the others.  A value that is only cancellation noise of what was added into it is zero.
    size = folding.magnitude(delta)
    beta = np.array(
        [0.0 if abs(b) <= NEGLIGIBLE * m else _shortest_decimal(b, SNAP * abs(b))
         for b, m in zip(beta, size, strict=True)]
    )  # fmt: skip
    if not _same_torques(_regressor(robot, kinematics)(seed=2), beta, delta):
        return None
    return barycentric_links([sp.Float(x) if x else sp.Integer(0) for x in beta])


def _same_torques(Y: np.ndarray, beta: np.ndarray, delta: np.ndarray) -> bool:
    """``Y beta = Y delta`` in every torque, each to a tolerance relative to its own size (the
    sum of the sizes of its terms ``|Y| |delta|``), not to the largest torque."""
    size = np.abs(Y) @ np.abs(delta)
    return bool(np.all(np.abs(Y @ beta - Y @ delta) <= TORQUE_TOLERANCE * size))


def barycentric_symbols(dof: int) -> tuple[sp.Symbol, ...]:
    """``xx1, yy1, ..., mx1, my1, mz1, m1, xx2, ...``: barycentric parameters in the order of
    :class:`Folding` (``PARAMETER_NAMES`` per link), inertia about the frame origin."""
    return tuple(
        sp.Symbol(f"{name}{i + 1}", real=True) for i in range(dof) for name in PARAMETER_NAMES
    )


def barycentric_links(values: Sequence[sp.Expr]) -> tuple[BarycentricParameters, ...]:
    """Per-link parameters from a link-major list in the order of :func:`barycentric_symbols`."""
    count = len(PARAMETER_NAMES)
    return tuple(
        BarycentricParameters.from_values(
            dict(zip(PARAMETER_NAMES, values[start : start + count], strict=True))
        )
        for start in range(0, len(values), count)
    )


def symbolic_base_parameters(
    robot: Robot, kinematics: Kinematics
) -> tuple[tuple[BarycentricParameters, ...], tuple[tuple[sp.Symbol, sp.Expr], ...]] | None:
    """Base parameters as symbols, for a robot with numeric geometry and any inertial data.

    Returns the links' parameters (a symbol where a parameter is kept, 0 where it is folded
    away) and each symbol's definition in :func:`barycentric_symbols`.  Kept parameters are
    named in capitals (``XY2``), with an ``R`` when others fold into them (``ZZ2R``, Khalil's
    notation).  ``None`` when the geometry has parameters.
    """
    folding = base_parameter_folding(robot, kinematics)
    if folding is None:
        return None
    delta = barycentric_symbols(robot.dof)
    count = len(PARAMETER_NAMES)
    # Least squares leaves noise in the last digits (0.18644623999999 for 0.4318**2): each
    # coefficient is rounded relative to itself; one below 1e-12 of the largest is noise.
    noise = 1e-12 * max((abs(c) for row in folding.matrix for c in row), default=1.0)
    values: list[sp.Expr] = [sp.Integer(0)] * len(delta)
    definitions = []
    for row, k in zip(folding.matrix, folding.kept, strict=True):
        folded = [
            _coefficient(_shortest_decimal(c, 10 * NEGLIGIBLE * abs(c))) * delta[d]
            for c, d in zip(row, folding.dropped, strict=True)
            if abs(c) > noise
        ]
        link, name = divmod(k, count)
        suffix = "R" if folded else ""
        symbol = sp.Symbol(f"{PARAMETER_NAMES[name].upper()}{link + 1}{suffix}", real=True)
        values[k] = symbol
        definitions.append((symbol, delta[k] + sp.Add(*folded)))
    return barycentric_links(values), tuple(definitions)


def _coefficient(value: float) -> sp.Number:
    return sp.Integer(int(value)) if abs(value) == 1.0 else sp.Float(value)


def _shortest_decimal(value: float, tolerance: float) -> float:
    for digits in range(1, 18):
        rounded = float(f"{value:.{digits}g}")
        if abs(rounded - value) <= tolerance:
            return rounded
    return value
