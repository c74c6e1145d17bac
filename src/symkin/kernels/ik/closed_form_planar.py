"""Closed-form IK of planar arms: 2R and 3R, each optionally with one prismatic joint along z.

Recognised from the table: every twist ``alpha_1 .. alpha_{n-1}`` is 0, so all joint axes are
parallel to the base z axis (the last twist only turns the tool and joins it).  The motion then
splits into a rigid motion in the x-y plane (the revolute joints) and a translation along z
(the prismatic joint, if any).  Covers the catalogue's ``planar_2r``, ``scara`` and
``planar_3r``.

In the plane each revolute joint k rotates by ``q_k + o_k`` and is followed by a constant 2-D
transform ``C_k = Trans(v_k) Rot(gamma_k)`` up to the next revolute joint (its link ``a_k``,
any prismatic rows in between, and the tool offset after the last one).  With cumulative
angles ``Theta_k = Theta_{k-1} + gamma_{k-1} + q_k + o_k`` (``Theta_0 = 0``)::

    p = v_0 + sum_k Rot(Theta_k) v_k,        heading = Theta_r + gamma_r

The elbow is the textbook two-link solution (Spong, Hutchinson, Vidyasagar, *Robot Modeling
and Control*, Sec. 5.3; Craig, *Introduction to Robotics*, Sec. 4.4) without ``acos``:
``cos delta = (|p|^2 - l1^2 - l2^2) / (2 l1 l2)``, ``delta = atan2(+-sqrt(1 - cos^2), cos)``,
``beta_1 = atan2(y, x) - atan2(l2 sin delta, l1 + l2 cos delta)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    homogeneous,
    is_parallel,
    rigid_inverse,
    rot_x,
)

#: ``|cos delta|`` up to this much above 1 is rounding at full stretch, clamped to 1; the FK
#: check then decides whether the pose is reached.
REACH_TOL = 1e-9

#: A raw solution: joint values (not yet wrapped) and branch flags as (name, value) pairs.
Candidate = tuple[tuple[float, ...], tuple[tuple[str, str], ...]]


def clamped_sqrt(value: float, scale: float) -> float | None:
    """``sqrt(value)``; a negative ``value`` within rounding of 0 (relative to ``scale``) gives
    0, a clearly negative one ``None`` (no real solution)."""
    if value >= 0.0:
        return math.sqrt(value)
    return 0.0 if value >= -REACH_TOL * scale else None


def two_link(x: float, y: float, l1: float, l2: float) -> tuple[tuple[float, float, int], ...]:
    """Both solutions ``(beta_1, delta, sign of sin delta)`` of
    ``l1 (cos beta_1, sin beta_1) + l2 (cos(beta_1 + delta), sin(beta_1 + delta)) = (x, y)``.

    Empty when the point is out of reach.  ``l1, l2 > 0``.
    """
    cos_delta = (x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    if abs(cos_delta) > 1.0 + REACH_TOL:
        return ()
    cos_delta = min(1.0, max(-1.0, cos_delta))
    sin_delta = math.sqrt((1.0 - cos_delta) * (1.0 + cos_delta))
    direction = math.atan2(y, x)
    return tuple(
        (direction - math.atan2(l2 * s, l1 + l2 * cos_delta), math.atan2(s, cos_delta), sign)
        for s, sign in ((sin_delta, 1), (-sin_delta, -1))
    )


def polar(vector: tuple[float, float]) -> tuple[float, float]:
    """``(length, angle)`` of a 2-D vector."""
    return math.hypot(*vector), math.atan2(vector[1], vector[0])


def planar_links(
    chain: Any, tool: Any, zero: Any, cos: Callable, sin: Callable
) -> tuple[tuple[Any, Any], list[Any], list[tuple[Any, Any]], Any]:
    """Walk a planar chain: the first revolute axis ``start``, each revolute joint's angle
    offset, the in-plane link vectors between revolute axes (prismatic joints and the tool
    folded in) and the turn ``gamma`` after the last revolute joint.

    Numbers for the solver, or SymPy expressions (``zero = sp.S.Zero``, ``sp.cos``, ``sp.sin``)
    for the constants of the generated C: one walk serves both.
    """

    def turn(angle: Any, vector: tuple[Any, Any]) -> tuple[Any, Any]:
        c, s = cos(angle), sin(angle)
        return c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]

    offsets: list[Any] = []
    links: list[tuple[Any, Any]] = []
    start = (zero, zero)
    gamma, vector = zero, (zero, zero)
    for i, kind in enumerate(chain.kinds):
        if kind == "revolute":
            if offsets:
                links.append(vector)
            else:
                start = vector
            offsets.append(chain.theta[i] + gamma)
            gamma, vector = zero, (chain.a[i], zero)
        else:
            gamma += chain.theta[i]
            shift = turn(gamma, (chain.a[i], zero))
            vector = (vector[0] + shift[0], vector[1] + shift[1])
    shift = turn(gamma, (tool[0, 3], tool[1, 3]))
    links.append((vector[0] + shift[0], vector[1] + shift[1]))
    return start, offsets, links, gamma


@dataclass(frozen=True, eq=False)
class PlanarSolver:
    """Planar 2R/3R (+ one prismatic joint along z), constants precomputed per robot.

    ``revolute``/``prismatic``: joint indices (0-based); ``offsets[k] = o_k + gamma_{k-1}``;
    ``links[k] = v_{k+1}`` in polar form ``(length, angle)``; ``start = v_0``;
    ``end_angle = gamma_r``; ``z_offset``: the tool point's z when the prismatic variable is 0;
    ``tool_row``: first row of the tool rotation (to read the last frame's heading).
    """

    dof: int
    revolute: tuple[int, ...]
    prismatic: int | None
    offsets: tuple[float, ...]
    links: tuple[tuple[float, float], ...]
    start: tuple[float, float]
    end_angle: float
    z_offset: float
    head_inverse: np.ndarray
    tool_row: np.ndarray
    scale: float

    @property
    def family(self) -> str:
        name = f"planar {len(self.revolute)}R"
        return name if self.prismatic is None else f"{name} + prismatic z"

    @property
    def task(self) -> str:
        """Target components used: ``x``, ``y`` (``z`` with a prismatic joint, ``heading``
        with three revolute joints), in the frame after the base transform."""
        rows = "xy" if self.prismatic is None else "xyz"
        return rows + ("+heading" if len(self.revolute) == 3 else "")

    def candidates(self, target: np.ndarray) -> list[Candidate]:
        local = self.head_inverse @ target
        x, y = local[0, 3] - self.start[0], local[1, 3] - self.start[1]
        angles: tuple[float, ...] = ()
        if len(self.revolute) == 3:
            column = local[:3, :3] @ self.tool_row
            last = math.atan2(column[1], column[0]) - self.end_angle
            length, angle = self.links[2]
            x -= length * math.cos(last + angle)
            y -= length * math.sin(last + angle)
            angles = (last,)
        (l1, phi1), (l2, phi2) = self.links[:2]
        result = []
        for beta1, delta, sign in two_link(x, y, l1, l2):
            cumulative = (beta1 - phi1, beta1 + delta - phi2, *angles)
            q = [0.0] * self.dof
            previous = 0.0
            for index, theta, offset in zip(self.revolute, cumulative, self.offsets, strict=True):
                q[index] = theta - previous - offset
                previous = theta
            if self.prismatic is not None:
                q[self.prismatic] = local[2, 3] - self.z_offset
            # Elbow "up": the elbow lies on the counterclockwise side of the line from the
            # first joint to the wrist point (cross(wrist, elbow) = -l1 l2 sin delta > 0).
            result.append((tuple(q), (("elbow", "up" if sign < 0 else "down"),)))
        return result


def planar_solver(chain: NumericChain) -> PlanarSolver | None:
    """The planar solver if ``chain`` is a planar 2R/3R (+ one prismatic) arm, else None."""
    revolute = tuple(i for i, kind in enumerate(chain.kinds) if kind == "revolute")
    prismatic = tuple(i for i, kind in enumerate(chain.kinds) if kind == "prismatic")
    if len(revolute) not in (2, 3) or len(prismatic) > 1:
        return None
    if not all(is_parallel(alpha) for alpha in chain.alpha[:-1]):
        return None
    # The last twist turns only the last frame: it joins the tool.
    tool = homogeneous(rot_x(chain.alpha[-1])) @ chain.tool
    start, offsets, links, gamma = planar_links(chain, tool, 0.0, math.cos, math.sin)
    if any(chain.is_zero_length(math.hypot(*v)) for v in links[:2]):
        return None
    return PlanarSolver(
        dof=chain.dof,
        revolute=revolute,
        prismatic=prismatic[0] if prismatic else None,
        offsets=tuple(offsets),
        links=tuple(polar(v) for v in links),
        start=start,
        end_angle=gamma,
        z_offset=sum(chain.d) + tool[2, 3],
        head_inverse=rigid_inverse(chain.base),
        tool_row=tool[0, :3].copy(),
        scale=chain.size,
    )
