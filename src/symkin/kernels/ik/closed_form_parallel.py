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

from symkin.kernels.ik.closed_form_planar import Candidate, polar, two_link
from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    is_parallel,
    rigid_inverse,
    rot_x,
    rot_z,
    twist_sign,
)
from symkin.kernels.ik.closed_form_wrist import (
    WRIST_SINGULAR,
    elbow_flag,
    shoulder,
    shoulder_flag,
    tail_inverse,
)


@dataclass(frozen=True, eq=False)
class ParallelAxesSolver:
    """UR-type arm, constants precomputed per robot (module docstring for the steps)."""

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


def parallel_axes_solver(chain: NumericChain) -> ParallelAxesSolver | None:
    """The UR-type solver if ``chain`` has that shape (module docstring), else None."""
    if chain.dof != 6 or chain.kinds != ("revolute",) * 6:
        return None
    t1, t4, t5 = (twist_sign(chain.alpha[i]) for i in (0, 3, 4))
    if not (t1 and t4 and t5 and is_parallel(chain.alpha[1]) and is_parallel(chain.alpha[2])):
        return None
    if not all(chain.is_zero_length(x) for x in (chain.a[3], chain.a[4])):
        return None
    if any(chain.is_zero_length(x) for x in (chain.a[1], chain.a[2])):
        return None
    return ParallelAxesSolver(
        twists=(t1, t4, t5),
        d1=chain.d[0],
        a1=chain.a[0],
        offset=-t1 * (chain.d[1] + chain.d[2] + chain.d[3]),
        d5=chain.d[4],
        d6=chain.d[5],
        link2=polar((chain.a[1], 0.0)),
        link3=polar((chain.a[2], 0.0)),
        twist1=rot_x(chain.alpha[0]),
        undo4=rot_x(chain.alpha[3]).T,
        undo5=rot_x(chain.alpha[4]).T,
        theta=chain.theta,
        head_inverse=rigid_inverse(chain.base),
        tail_inverse=tail_inverse(chain),
        scale=chain.size,
    )
