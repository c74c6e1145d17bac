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

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from symkin.derive.dynamics import link_inertial_data
from symkin.derive.kinematics import Kinematics
from symkin.robot import Link, Robot

# Order in which columns are offered to the basis: a parameter is dropped (folded into the
# ones before it) when its column depends on earlier ones.  Inner links come first, and within
# a link the inertia, then the mass, then the first moments, so outer links' first moments are
# the ones folded in.  Of the orders tried this gives the PUMA 560 the shortest code (inverse
# dynamics 382 operations; 400 with the first moments before the mass).
PARAMETER_NAMES = ("zz", "yy", "xx", "yz", "xz", "xy", "m", "mz", "my", "mx")
SAMPLES = 15
RANK_TOLERANCE = 1e-8


@dataclass(frozen=True)
class BarycentricParameters:
    """One link's inertia about its frame origin, first moment ``m c`` and mass (frame-i axes)."""

    inertia: sp.ImmutableMatrix
    first_moment: sp.ImmutableMatrix
    mass: sp.Expr

    @classmethod
    def from_values(cls, values: dict[str, sp.Expr]) -> BarycentricParameters:
        v = values
        return cls(
            inertia=sp.ImmutableMatrix(
                [
                    [v["xx"], v["xy"], v["xz"]],
                    [v["xy"], v["yy"], v["yz"]],
                    [v["xz"], v["yz"], v["zz"]],
                ]
            ),
            first_moment=sp.ImmutableMatrix([v["mx"], v["my"], v["mz"]]),
            mass=v["m"],
        )


def barycentric_from_link(link: Link) -> dict[str, float]:
    """Parallel-axis theorem: ``I_o = I_c + m (c.c E - c c^T)``, ``m c``, ``m`` (floats)."""
    mass = float(link.mass)
    com = np.array([float(c) for c in link.com])
    inertia = np.array(link.inertia_matrix, dtype=float)
    inertia = inertia + mass * (com @ com * np.eye(3) - np.outer(com, com))
    first = mass * com
    return {
        "xx": inertia[0, 0], "yy": inertia[1, 1], "zz": inertia[2, 2],
        "xy": inertia[0, 1], "xz": inertia[0, 2], "yz": inertia[1, 2],
        "mx": first[0], "my": first[1], "mz": first[2], "m": mass,
    }  # fmt: skip


def is_numeric(robot: Robot, kinematics: Kinematics) -> bool:
    """Geometry and every link's inertial data are numbers (no parameters, no symbols)."""
    if robot.parameters or any(j.link is None for j in robot.joints):
        return False
    geometry = set().union(*(t.free_symbols for t in kinematics.link_transforms))
    if not geometry <= set(kinematics.q):
        return False
    links = [j.link for j in robot.joints]
    values = [sp.sympify(x) for link in links for x in (link.mass, *link.com, *link.inertia)]
    return all(v.is_number for v in values)


@lru_cache(maxsize=16)
def base_parameters(
    robot: Robot, kinematics: Kinematics
) -> tuple[BarycentricParameters, ...] | None:
    """Per-link parameters with the dependent ones folded in and zeroed, or ``None`` when the
    robot is not fully numeric (then the recursion keeps the file's parameters)."""
    from symkin.derive.newton_euler import Recorder, joint_torques

    if not is_numeric(robot, kinematics):
        return None
    n = robot.dof
    symbols = [
        [sp.Symbol(f"{name}{i + 1}", real=True) for name in PARAMETER_NAMES] for i in range(n)
    ]
    links = tuple(
        BarycentricParameters.from_values(dict(zip(PARAMETER_NAMES, row, strict=True)))
        for row in symbols
    )
    dq = sp.symbols(f"dq1:{n + 1}", real=True)
    ddq = sp.symbols(f"ddq1:{n + 1}", real=True)
    recorder = Recorder("b")
    torque = joint_torques(robot, kinematics, recorder, dq, ddq, robot.gravity, links)
    flat = [s for row in symbols for s in row]
    # All columns of Y in one call: the parameters are passed as the rows of the identity.
    regressor_of = sp.lambdify(
        [kinematics.q, dq, ddq, flat],
        torque,
        modules="numpy",
        cse=lambda e: (recorder.assignments, e),
    )
    identity = list(np.eye(len(flat)))

    def regressor(seed: int) -> np.ndarray:
        rng = np.random.default_rng(seed)
        rows = []
        for _ in range(SAMPLES):
            state = rng.uniform(-2.0, 2.0, (3, n))
            columns = regressor_of(*state, identity)
            rows.append(np.array([np.broadcast_to(c, len(flat)) for c in columns], dtype=float))
        return np.vstack(rows)

    Y = regressor(seed=1)
    tolerance = RANK_TOLERANCE * np.linalg.norm(Y)
    kept: list[int] = []
    for k in range(Y.shape[1]):
        if np.linalg.matrix_rank(Y[:, [*kept, k]], tol=tolerance) == len(kept) + 1:
            kept.append(k)
    dropped = [k for k in range(Y.shape[1]) if k not in kept]
    folding, *_ = np.linalg.lstsq(Y[:, kept], Y[:, dropped], rcond=None)
    delta = np.array(
        [
            barycentric_from_link(link_inertial_data(robot, i))[name]
            for i in range(n)
            for name in PARAMETER_NAMES
        ]
    )
    beta = np.zeros_like(delta)
    beta[kept] = delta[kept] + folding @ delta[dropped]
    # The least-squares fold leaves noise in the last digits (0.000884319999994): each value
    # becomes the shortest decimal within 1e-13 of the largest parameter.
    snap = 1e-13 * np.max(np.abs(beta))
    beta = np.array([_shortest_decimal(b, snap) for b in beta])
    check = regressor(seed=2)
    error = np.max(np.abs(check @ beta - check @ delta))
    if error > 1e-10 * max(1.0, np.max(np.abs(check @ delta))):
        return None
    negligible = 1e-12 * np.max(np.abs(beta))
    rows = [
        {
            name: sp.Float(x) if abs(x) > negligible else sp.Integer(0)
            for name, x in zip(PARAMETER_NAMES, row, strict=True)
        }
        for row in beta.reshape(n, len(PARAMETER_NAMES))
    ]
    return tuple(BarycentricParameters.from_values(row) for row in rows)


def _shortest_decimal(value: float, tolerance: float) -> float:
    for digits in range(1, 18):
        rounded = float(f"{value:.{digits}g}")
        if abs(rounded - value) <= tolerance:
            return rounded
    return value
