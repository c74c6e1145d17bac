"""Closed-form IK of six-revolute arms with three parallel middle axes (UR5/UR10 type).

No spherical wrist, yet eight solutions in closed form (Hawkins, "Analytic inverse kinematics
for the Universal Robots UR-5/UR-10 arms", 2013; Andersen, "Kinematics of a UR5", Aalborg
University, 2018), here derived for any table of this shape.  Recognised from the standard-DH
table: six revolute joints, ``alpha_1 = +-90``, ``alpha_2 = alpha_3 = 0`` (axes 2, 3, 4
parallel to ``z_1``), ``alpha_4, alpha_5 = +-90``, ``a_4 = a_5 = 0``; any ``d_1 .. d_6``,
``a_1``, ``a_2, a_3 != 0``.  With ``t_i = sin(alpha_i)`` and
``W = base^-1 T (Tx(a_6) Rx(alpha_6) tool)^-1``:

1. ``o_5 = p_W - d_6 z_W``.  Everything but ``d_5 z_4`` moves in the plane normal to ``z_1``,
   and ``z_4`` lies in it, so ``o_5 . z_1 = d_2 + d_3 + d_4 = h``: the waist angle is the
   articulated arm's shoulder with offset ``-t_1 h`` (two solutions, "shoulder").
2. ``z_W . z_1 = -t_4 t_5 cos th5`` and the in-plane part of ``z_W`` has length
   ``|sin th5|`` (two solutions, "wrist").
3. ``z_1`` in tool axes is ``(t_4 sin th5 cos th6, -t_4 sin th5 sin th6, .)``: ``th6`` from
   ``z_1 . x_W`` and ``z_1 . y_W``.  At ``sin th5 = 0`` (axis 6 parallel to 2, 3, 4) ``th6``
   is free: ``q6 = 0`` is chosen, flag ``"wrist": "singular"``.
4. ``Rz(th2 + th3 + th4) = (Rz(th1) Rx(al1))^T R_W Rz(th6)^T Rx(al5)^T Rz(th5)^T Rx(al4)^T``.
5. ``o_4 = o_5 - d_5 z_4`` in frame-1 plane coordinates is a two-link point
   ``Rot(th2) (a_2, 0) + Rot(th2 + th3) (a_3, 0)`` (two solutions, "elbow"); then
   ``th4 = (th2 + th3 + th4) - th2 - th3``.
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
    tail,
    twist_constants,
)
from symkin.kernels.ik.closed_form_steps import (
    WRIST_SINGULAR,
    Candidate,
    elbow_flag,
    rot_z,
    shoulder,
    shoulder_flag,
    transform,
    twist_rotations,
    two_link,
)
from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    SymbolicChain,
    is_parallel,
    twist_sign,
)


@dataclass(frozen=True, eq=False)
class ParallelAxesSolver:
    """UR-type arm, the constants of :func:`parallel_constants` evaluated (module docstring
    for the steps)."""

    twists: tuple[int, int, int]  # t_1, t_4, t_5
    d1: float
    a1: float
    offset: float  # -t_1 (d_2 + d_3 + d_4)
    d5: float
    d6: float
    link2: tuple[float, float]
    link3: tuple[float, float]
    twist1: np.ndarray  # Rx(alpha_1)
    undo4: np.ndarray  # Rx(alpha_4)^T
    undo5: np.ndarray  # Rx(alpha_5)^T
    theta: tuple[float, ...]
    head_inverse: np.ndarray
    tail_inverse: np.ndarray
    scale: float

    family = "three parallel axes (UR type)"
    task = "pose"

    @classmethod
    def from_plan(cls, plan: ClosedFormPlan, values: Values, dof: int) -> ParallelAxesSolver:
        del dof  # six
        shape = plan.shape
        rotations = twist_rotations(values["twist_cos"], values["twist_sin"])
        return cls(
            twists=(shape["twist1"], shape["twist4"], shape["twist5"]),
            d1=values["d1"][0],
            a1=values["a1"][0],
            offset=values["offset"][0],
            d5=values["d5"][0],
            d6=values["d6"][0],
            link2=values["link2"],
            link3=values["link3"],
            twist1=rotations[0],
            undo4=rotations[3].T,
            undo5=rotations[4].T,
            theta=values["theta"],
            head_inverse=transform(values.get("head_inverse")),
            tail_inverse=transform(values.get("tail_inverse")),
            scale=values["scale"][0],
        )

    def _wrist(self, rotation: np.ndarray, c1: float, s1: float) -> list[tuple[float, float, str]]:
        """``(th5, th6, flag)`` for both wrist branches at waist angle ``(c1, s1)``."""
        t1, t4, t5 = self.twists
        z = rotation[:, 2]
        cos5 = -t4 * t5 * t1 * (z[0] * s1 - z[1] * c1)
        rho = math.hypot(z[0] * c1 + z[1] * s1, t1 * z[2])
        if rho <= WRIST_SINGULAR:
            return [(math.atan2(0.0, cos5), self.theta[5], "singular")]
        along_x = t1 * (rotation[0, 0] * s1 - rotation[1, 0] * c1)  # z_1 . x_W
        along_y = t1 * (rotation[0, 1] * s1 - rotation[1, 1] * c1)  # z_1 . y_W
        result = []
        for sin5 in (rho, -rho):
            sigma = 1.0 if t4 * sin5 > 0 else -1.0
            flag = "no_flip" if t4 * sin5 < 0 else "flip"
            theta6 = math.atan2(-sigma * along_y, sigma * along_x)
            result.append((math.atan2(sin5, cos5), theta6, flag))
        return result

    def candidates(self, target: np.ndarray) -> list[Candidate]:
        local = self.head_inverse @ target @ self.tail_inverse
        rotation = local[:3, :3]
        x5, y5, z5 = local[:3, 3] - self.d6 * rotation[:, 2]
        t1, t4, _ = self.twists
        (l2, phi2), (l3, phi3) = self.link2, self.link3
        result = []
        for X, theta1 in shoulder(x5, y5, self.offset, self.scale):
            c1, s1 = math.cos(theta1), math.sin(theta1)
            r01 = rot_z(theta1) @ self.twist1
            for theta5, theta6, flag in self._wrist(rotation, c1, s1):
                rest = r01.T @ rotation @ rot_z(-theta6) @ self.undo5 @ rot_z(-theta5) @ self.undo4
                theta234 = math.atan2(rest[1, 0], rest[0, 0])
                x = (x5 - self.a1 * c1) * c1 + (y5 - self.a1 * s1) * s1
                y = t1 * (z5 - self.d1)
                x -= self.d5 * t4 * math.sin(theta234)
                y += self.d5 * t4 * math.cos(theta234)
                for beta, delta, sign in two_link(x, y, l2, l3):
                    theta2, theta3 = beta - phi2, delta + phi2 - phi3
                    angles = (theta1, theta2, theta3, theta234 - theta2 - theta3, theta5, theta6)
                    q = tuple(t - o for t, o in zip(angles, self.theta, strict=True))
                    flags = (
                        shoulder_flag(X, self.offset),
                        elbow_flag(sign, X, t1),
                        ("wrist", flag),
                    )
                    result.append((q, flags))
        return result


def parallel_axes_shape(chain: NumericChain) -> Shape | None:
    """The UR-type shape if ``chain`` has it (module docstring), else None."""
    if chain.dof != 6 or chain.kinds != ("revolute",) * 6:
        return None
    t1, t4, t5 = (twist_sign(chain.alpha[i]) for i in (0, 3, 4))
    if not (t1 and t4 and t5 and is_parallel(chain.alpha[1]) and is_parallel(chain.alpha[2])):
        return None
    if not all(chain.is_zero_length(x) for x in (chain.a[3], chain.a[4])):
        return None
    return Shape(
        family="parallel",
        arm="parallel",
        name=ParallelAxesSolver.family,
        task="pose",
        structure=(("twist1", t1), ("twist4", t4), ("twist5", t5)),
        nonzero=(("link2", 0), ("link3", 0)),
    )


def parallel_constants(chain: SymbolicChain, shape: Shape) -> list[Constant]:
    """The constants of the UR-type formulas (the fields of :class:`ParallelAxesSolver`)."""
    a, d = chain.a, chain.d
    return [
        Constant("d1", (d[0],), "d_1"),
        Constant("a1", (a[0],), "a_1"),
        Constant("offset", (-shape["twist1"] * (d[1] + d[2] + d[3]),), "-t_1 (d_2 + d_3 + d_4)"),
        Constant("d5", (d[4],), "d_5"),
        Constant("d6", (d[5],), "d_6"),
        Constant("link2", polar(a[1], sp.S.Zero), "(a_2, 0) in polar form (length, angle)"),
        Constant("link3", polar(a[2], sp.S.Zero), "(a_3, 0) in polar form"),
        *twist_constants(chain),
        Constant("theta", chain.theta, "theta_i - q_i"),
        *frame_constants(chain, tail(chain)),
    ]
