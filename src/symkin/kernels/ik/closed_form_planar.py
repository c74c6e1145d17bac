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

The elbow is the two-link solution (``closed_form_steps.two_link``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from symkin.kernels.ik.closed_form_spec import (
    ClosedFormPlan,
    Constant,
    Shape,
    Values,
    frame_constants,
    polar,
)
from symkin.kernels.ik.closed_form_steps import Candidate, transform, two_link
from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    SymbolicChain,
    is_parallel,
    translation_rotation,
)
from symkin.spatial import rot_x

#: A 2-D vector of SymPy expressions.
Vector = tuple[sp.Expr, sp.Expr]


def planar_links(
    chain: SymbolicChain, tool: sp.Matrix
) -> tuple[Vector, list[sp.Expr], list[Vector], sp.Expr]:
    """Walk a planar chain: the first revolute axis ``start``, each revolute joint's angle
    offset, the in-plane link vectors between revolute axes (prismatic joints and the tool
    folded in) and the turn ``gamma`` after the last revolute joint."""

    def turn(angle: sp.Expr, vector: Vector) -> Vector:
        c, s = sp.cos(angle), sp.sin(angle)
        return c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]

    zero = sp.S.Zero
    offsets: list[sp.Expr] = []
    links: list[Vector] = []
    start: Vector = (zero, zero)
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


def planar_shape(chain: NumericChain) -> Shape | None:
    """The planar shape if ``chain`` is a planar 2R/3R (+ one prismatic) arm, else None."""
    revolute = tuple(i for i, kind in enumerate(chain.kinds) if kind == "revolute")
    prismatic = tuple(i for i, kind in enumerate(chain.kinds) if kind == "prismatic")
    if len(revolute) not in (2, 3) or len(prismatic) > 1:
        return None
    if not all(is_parallel(alpha) for alpha in chain.alpha[:-1]):
        return None
    name = f"planar {len(revolute)}R" + (" + prismatic z" if prismatic else "")
    task = ("xyz" if prismatic else "xy") + ("+heading" if len(revolute) == 3 else "")
    return Shape(
        family="planar",
        arm="planar",
        name=name,
        task=task,
        structure=(("revolute", revolute), ("prismatic", prismatic[0] if prismatic else None)),
        nonzero=(("link_length", 0), ("link_length", 1)),
    )


def planar_constants(chain: SymbolicChain, shape: Shape) -> list[Constant]:
    """``offsets[k] = o_k + gamma_{k-1}``; the links ``v_{k+1}`` in polar form; ``start =
    v_0``; with three revolute joints ``end_angle = gamma_r`` and the tool rotation's first
    row (to read the last frame's heading); with a prismatic joint the tool point's z when its
    variable is 0."""
    # The last twist turns only the last frame: it joins the tool.
    tool = translation_rotation(rot_x(chain.alpha[-1])) @ chain.tool
    start, offsets, links, gamma = planar_links(chain, tool)
    polars = [polar(*link) for link in links]
    constants = [
        Constant(
            "offsets", tuple(offsets), "o_k + gamma_{k-1}: angle offset of each revolute joint"
        ),
        Constant(
            "link_length",
            tuple(p[0] for p in polars),
            "|v_k|: planar links after each revolute joint",
        ),
        Constant("link_angle", tuple(p[1] for p in polars), "atan2 of v_k"),
        Constant("start", start, "v_0: first revolute axis in the plane"),
    ]
    if "heading" in shape.task:
        constants += [
            Constant("end_angle", (gamma,), "gamma_r: turn after the last revolute joint"),
            Constant("tool_row", tuple(tool[0, :3]), "first row of the tool rotation (heading)"),
        ]
    if shape["prismatic"] is not None:
        z_offset = sum(chain.d, sp.S.Zero) + tool[2, 3]
        constants.append(Constant("z_offset", (z_offset,), "tool z at q_prismatic = 0"))
    return constants + frame_constants(chain, None)


@dataclass(frozen=True, eq=False)
class PlanarSolver:
    """Planar 2R/3R (+ one prismatic joint along z), the plan's constants evaluated.

    ``revolute``/``prismatic``: joint indices (0-based); ``links[k]``: ``(length, angle)``;
    ``tool_row`` and ``end_angle`` are used with three revolute joints only, ``z_offset`` with
    a prismatic joint only (constants of :func:`planar_constants`).
    """

    family: str
    task: str
    dof: int
    revolute: tuple[int, ...]
    prismatic: int | None
    offsets: tuple[float, ...]
    links: tuple[tuple[float, float], ...]
    start: tuple[float, ...]
    end_angle: float
    z_offset: float
    head_inverse: np.ndarray
    tool_row: np.ndarray
    scale: float

    @classmethod
    def from_plan(cls, plan: ClosedFormPlan, values: Values, dof: int) -> PlanarSolver:
        shape = plan.shape
        return cls(
            family=shape.name,
            task=shape.task,
            dof=dof,
            revolute=shape["revolute"],
            prismatic=shape["prismatic"],
            offsets=values["offsets"],
            links=tuple(zip(values["link_length"], values["link_angle"], strict=True)),
            start=values["start"],
            end_angle=values.get("end_angle", (0.0,))[0],
            z_offset=values.get("z_offset", (0.0,))[0],
            head_inverse=transform(values.get("head_inverse")),
            tool_row=np.array(values.get("tool_row", (1.0, 0.0, 0.0))),
            scale=values["scale"][0],
        )

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
