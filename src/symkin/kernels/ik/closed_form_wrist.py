"""Closed-form IK of six-joint arms with a spherical wrist (Pieper's decomposition).

Recognised from the standard-DH table: joints 4, 5, 6 are revolute, ``a_4 = a_5 = d_5 = 0``
and ``alpha_4, alpha_5 = +-90 deg``, so the axes of joints 4, 5 and 6 meet in one point, the
wrist centre ``o_3 + d_4 z_3`` (Pieper 1968).  With the tool, ``Tx(a_6) Rx(alpha_6)`` and the
base taken off the target, ``W = base^-1 T (Tx(a_6) Rx(alpha_6) tool)^-1``::

    wrist centre  p_c = p_W - d_6 z_W                (position: joints 1..3 only)
    orientation   R_3^T R_W = Rz(th4) Rx(al4) Rz(th5) Rx(al5) Rz(th6)   (joints 4..6)

The first three joints come in three recognised kinds (all angles ``th_i = q_i + offset``):

* **RRR, articulated** (PUMA 560): ``alpha_1 = +-90``, ``alpha_2 = 0``; any ``a_1, d_1, d_2,
  a_2, a_3, d_3, alpha_3, d_4``.  In frame 1 the wrist centre is a planar two-link point
  ``Rot(th2) [(a_2, 0) + Rot(th3) (a_3, -sin(al3) d_4)]`` at height ``h = d_2 + d_3 +
  cos(al3) d_4`` (the shoulder offset), so ``X = +-sqrt(px^2 + py^2 - h^2)`` (shoulder),
  ``th1 = atan2(py, px) - atan2(-sin(al1) h, X)``, then the two-link elbow (Craig, Sec. 4.7;
  Paul, *Robot Manipulators*, 1981, Ch. 3).
* **RRP, spherical** (Stanford arm): ``alpha_1, alpha_2 = +-90``; the same shoulder, then the
  reach ``lambda = +-sqrt(x1^2 + y1^2 - k^2)`` along the prismatic axis (Spong et al.,
  Sec. 5.3).
* **RPP, cylindrical** (Spong's cylindrical arm): ``alpha_1 = 0`` (joint 2 slides along
  joint 1's axis), ``alpha_2 = +-90``; height from ``z``, the radial reach from a quadratic
  (Spong et al., Sec. 5.3).

The wrist (Spong et al., Sec. 5.4; Craig, Sec. 4.7) with ``s4 = sin(al4), s5 = sin(al5)`` and
``u = R_3^T z_W``: ``cos th5 = -s4 s5 u_z``, ``sin th5 = +-sqrt(u_x^2 + u_y^2)``,
``th4 = atan2(s5 sin(th5) u_y, s5 sin(th5) u_x)``; ``th6`` from the remaining rotation
``(Rz(th4) Rx(al4) Rz(th5) Rx(al5))^T R_3^T R_W = Rz(th6)``, which stays exact near the
singularity.  At ``sin th5 = 0`` only ``th4 +- th6`` is defined: ``q4 = 0`` is chosen and the
branch is flagged ``"wrist": "singular"``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symkin.kernels.ik.closed_form_planar import Candidate, clamped_sqrt, polar, two_link
from symkin.kernels.ik.closed_form_table import (
    NumericChain,
    homogeneous,
    is_parallel,
    rigid_inverse,
    rot_x,
    rot_z,
    twist_sign,
)

#: ``sin th5`` below this is the wrist singularity (``q4`` set to 0, flag "singular").
WRIST_SINGULAR = 1e-12

#: One solution of the first three joints: joint values, DH angles theta_1..3, branch flags.
ArmSolution = tuple[tuple[float, float, float], tuple[float, float, float], tuple]


def shoulder(x: float, y: float, offset: float, scale: float) -> tuple[tuple[float, float], ...]:
    """Both ``(X, th1)`` with ``Rz(th1) (X, offset) = (x, y)``: the waist angle that puts a
    point at horizontal offset ``offset`` from the arm's plane (Paul and Zhang 1986, eq. 40).
    Empty when the point is closer to the waist axis than ``|offset|``."""
    reach = clamped_sqrt(x * x + y * y - offset * offset, scale * scale)
    if reach is None:
        return ()
    direction = math.atan2(y, x)
    return tuple((X, direction - math.atan2(offset, X)) for X in (reach, -reach))


def shoulder_flag(X: float, offset: float) -> tuple[str, str]:
    """Shoulder "right" when the shoulder offset lies to the right of the reach direction seen from
    above (``X * offset < 0``; with no offset: reaching forward, ``X >= 0``).  For the PUMA 560
    this is Robotics Toolbox's 'r' (righty)."""
    right = X * offset < 0 if offset != 0.0 else X >= 0
    return ("shoulder", "right" if right else "left")


def elbow_flag(sign: int, X: float, twist: int) -> tuple[str, str]:
    """Elbow "up" when the elbow lies above the line from the shoulder to the wrist, looking at the
    arm's plane with the reach pointing forward: ``-sign(sin delta) sign(X) sin(alpha_1) > 0``
    (for the PUMA 560 Robotics Toolbox's 'u')."""
    forward = 1 if X >= 0 else -1
    return ("elbow", "up" if -sign * forward * twist > 0 else "down")


def extension_flag(root: float) -> tuple[str, str]:
    """Extension "forward" for the positive square root of the reach equation (for the Stanford arm:
    the prismatic reach ``lambda`` is positive), "backward" for the negative one."""
    return ("extension", "forward" if root >= 0 else "backward")


@dataclass(frozen=True, eq=False)
class ArticulatedArm:
    """RRR: waist (``alpha_1 = +-90``) and two parallel joints (``alpha_2 = 0``)."""

    twist1: int
    d1: float
    a1: float
    offset: float  # -sin(alpha_1) h: the wrist centre's distance from the arm's plane
    link2: tuple[float, float]  # (a_2, 0) in polar form
    link3: tuple[float, float]  # (a_3, -sin(alpha_3) d_4) in polar form
    theta: tuple[float, float, float]
    scale: float

    family = "spherical wrist, articulated RRR arm"

    def solve(self, x: float, y: float, z: float) -> list[ArmSolution]:
        (l2, phi2), (l3, phi3) = self.link2, self.link3
        result = []
        for X, theta1 in shoulder(x, y, self.offset, self.scale):
            x1, y1 = X - self.a1, self.twist1 * (z - self.d1)
            for beta, delta, sign in two_link(x1, y1, l2, l3):
                theta2, theta3 = beta - phi2, delta + phi2 - phi3
                angles = (theta1, theta2, theta3)
                q = tuple(t - o for t, o in zip(angles, self.theta, strict=True))
                flags = (shoulder_flag(X, self.offset), elbow_flag(sign, X, self.twist1))
                result.append((q, angles, flags))
        return result


@dataclass(frozen=True, eq=False)
class SphericalArm:
    """RRP: waist and shoulder (``alpha_1, alpha_2 = +-90``), prismatic reach."""

    twist1: int
    twist2: int
    d1: float
    a1: float
    offset: float  # -sin(alpha_1) (d_2 + sin(alpha_2) c_y)
    k: float  # a_2 + c_x: the reach's distance from the shoulder axis
    reach_offset: float  # lambda - q_3 = d_3 offset + cos(alpha_3) d_4
    theta: tuple[float, float, float]
    scale: float

    family = "spherical wrist, spherical RRP arm"

    def solve(self, x: float, y: float, z: float) -> list[ArmSolution]:
        result = []
        for X, theta1 in shoulder(x, y, self.offset, self.scale):
            x1, y1 = X - self.a1, self.twist1 * (z - self.d1)
            root = clamped_sqrt(x1 * x1 + y1 * y1 - self.k * self.k, self.scale**2)
            if root is None:
                continue
            for reach in (root, -root):
                theta2 = math.atan2(y1, x1) - math.atan2(-self.twist2 * reach, self.k)
                q = (theta1 - self.theta[0], theta2 - self.theta[1], reach - self.reach_offset)
                angles = (theta1, theta2, self.theta[2])
                result.append((q, angles, (shoulder_flag(X, self.offset), extension_flag(reach))))
        return result


@dataclass(frozen=True, eq=False)
class CylindricalArm:
    """RPP: waist, vertical slide along the waist axis (``alpha_1 = 0``), radial slide."""

    height: float  # z of the wrist centre minus q_2
    g: tuple[float, float]  # horizontal wrist centre at zero radial reach, in frame 1 axes
    e: tuple[float, float]  # unit direction of the radial reach, in frame 1 axes
    reach_offset: float
    theta: tuple[float, float, float]
    scale: float

    family = "spherical wrist, cylindrical RPP arm"

    def solve(self, x: float, y: float, z: float) -> list[ArmSolution]:
        # |g + lambda e| = |(x, y)|: lambda^2 + 2 (g.e) lambda + |g|^2 - x^2 - y^2 = 0.
        (gx, gy), (ex, ey) = self.g, self.e
        half = gx * ex + gy * ey
        root = clamped_sqrt(half * half - gx * gx - gy * gy + x * x + y * y, self.scale**2)
        if root is None:
            return []
        result = []
        direction = math.atan2(y, x)
        for sign in (1, -1):
            reach = -half + sign * root
            theta1 = direction - math.atan2(gy + reach * ey, gx + reach * ex)
            q = (theta1 - self.theta[0], z - self.height, reach - self.reach_offset)
            angles = (theta1, self.theta[1], self.theta[2])
            result.append((q, angles, (extension_flag(reach + half),)))
        return result


Arm = ArticulatedArm | SphericalArm | CylindricalArm


@dataclass(frozen=True, eq=False)
class Wrist:
    """``Rz(th4) Rx(al4) Rz(th5) Rx(al5) Rz(th6)`` with ``al4, al5 = +-90 deg``."""

    twist4: int
    twist5: int
    undo4: np.ndarray  # Rx(alpha_4)^T
    undo5: np.ndarray  # Rx(alpha_5)^T
    theta: tuple[float, float, float]

    def angles(self, rotation: np.ndarray) -> list[tuple[float, float, float, str]]:
        """``(th4, th5, th6, flag)`` for each wrist branch of ``rotation = R_3^T R_W``.

        ``"no_flip"`` when ``sin(al4) sin(th5) < 0``, i.e. when the equivalent Z-Y-Z angle
        ``beta = -sin(al4) th5`` is positive (Robotics Toolbox's 'n' for the PUMA 560).
        """
        ux, uy, uz = rotation[0, 2], rotation[1, 2], rotation[2, 2]
        cos5 = -self.twist4 * self.twist5 * uz
        rho = math.hypot(ux, uy)
        if rho <= WRIST_SINGULAR:
            options = [(self.theta[0], math.atan2(0.0, cos5), "singular")]
        else:
            options = []
            for sin5 in (rho, -rho):
                sigma = self.twist5 if sin5 > 0 else -self.twist5
                flag = "no_flip" if self.twist4 * sin5 < 0 else "flip"
                options.append((math.atan2(sigma * uy, sigma * ux), math.atan2(sin5, cos5), flag))
        result = []
        for theta4, theta5, flag in options:
            rest = self.undo5 @ rot_z(-theta5) @ self.undo4 @ rot_z(-theta4) @ rotation
            result.append((theta4, theta5, math.atan2(rest[1, 0], rest[0, 0]), flag))
        return result


@dataclass(frozen=True, eq=False)
class SphericalWristSolver:
    """Six joints, spherical wrist: the arm's position solutions times the wrist's."""

    arm: Arm
    wrist: Wrist
    twists: tuple[np.ndarray, np.ndarray, np.ndarray]  # Rx(alpha_1), Rx(alpha_2), Rx(alpha_3)
    d6: float
    head_inverse: np.ndarray
    tail_inverse: np.ndarray
    scale: float
    task = "pose"

    @property
    def family(self) -> str:
        return self.arm.family

    def candidates(self, target: np.ndarray) -> list[Candidate]:
        local = self.head_inverse @ target @ self.tail_inverse
        rotation = local[:3, :3]
        centre = local[:3, 3] - self.d6 * rotation[:, 2]
        result = []
        for q_arm, angles, flags in self.arm.solve(*centre):
            r03 = np.eye(3)
            for theta, twist in zip(angles, self.twists, strict=True):
                r03 = r03 @ rot_z(theta) @ twist
            for theta4, theta5, theta6, flag in self.wrist.angles(r03.T @ rotation):
                q_wrist = tuple(
                    t - o for t, o in zip((theta4, theta5, theta6), self.wrist.theta, strict=True)
                )
                result.append(((*q_arm, *q_wrist), (*flags, ("wrist", flag))))
        return result


def wrist_centre_in_frame2(
    chain: Any, cos: Callable = math.cos, sin: Callable = math.sin
) -> tuple[Any, Any, Any]:
    """``(c_x, c_y, c_z)``: the wrist centre ``(0, 0, d_4)`` of frame 3 in frame 2, without
    the joint-3 motion: ``Rot(theta_3) (a_3, -sin(al3) d_4)`` and ``d_3 + cos(al3) d_4``.
    Numbers for the solver; with ``sp.cos``, ``sp.sin`` expressions for the generated C."""
    a3, alpha3, d4 = chain.a[2], chain.alpha[2], chain.d[3]
    cx, cy = a3, -sin(alpha3) * d4
    if chain.kinds[2] == "prismatic":
        c, s = cos(chain.theta[2]), sin(chain.theta[2])
        cx, cy = c * cx - s * cy, s * cx + c * cy
    return cx, cy, chain.d[2] + cos(alpha3) * d4


def _articulated(chain: NumericChain) -> ArticulatedArm | None:
    twist1 = twist_sign(chain.alpha[0])
    if not twist1 or not is_parallel(chain.alpha[1]):
        return None
    link3 = (chain.a[2], -math.sin(chain.alpha[2]) * chain.d[3])
    if chain.is_zero_length(chain.a[1]) or chain.is_zero_length(math.hypot(*link3)):
        return None
    height = chain.d[1] + chain.d[2] + math.cos(chain.alpha[2]) * chain.d[3]
    return ArticulatedArm(
        twist1=twist1,
        d1=chain.d[0],
        a1=chain.a[0],
        offset=-twist1 * height,
        link2=polar((chain.a[1], 0.0)),
        link3=polar(link3),
        theta=chain.theta[:3],
        scale=chain.size,
    )


def _spherical(chain: NumericChain) -> SphericalArm | None:
    twist1, twist2 = twist_sign(chain.alpha[0]), twist_sign(chain.alpha[1])
    if not twist1 or not twist2:
        return None
    cx, cy, cz = wrist_centre_in_frame2(chain)
    return SphericalArm(
        twist1=twist1,
        twist2=twist2,
        d1=chain.d[0],
        a1=chain.a[0],
        offset=-twist1 * (chain.d[1] + twist2 * cy),
        k=chain.a[1] + cx,
        reach_offset=cz,
        theta=chain.theta[:3],
        scale=chain.size,
    )


def _cylindrical(chain: NumericChain) -> CylindricalArm | None:
    twist2 = twist_sign(chain.alpha[1])
    if not is_parallel(chain.alpha[0]) or not twist2:
        return None
    cx, cy, cz = wrist_centre_in_frame2(chain)
    c, s = math.cos(chain.theta[1]), math.sin(chain.theta[1])
    k = chain.a[1] + cx
    return CylindricalArm(
        height=chain.d[0] + chain.d[1] + twist2 * cy,
        g=(chain.a[0] + c * k, s * k),
        e=(s * twist2, -c * twist2),
        reach_offset=cz,
        theta=chain.theta[:3],
        scale=chain.size,
    )


ARMS: dict[tuple[str, ...], Callable[[NumericChain], Arm | None]] = {
    ("revolute", "revolute", "revolute"): _articulated,
    ("revolute", "revolute", "prismatic"): _spherical,
    ("revolute", "prismatic", "prismatic"): _cylindrical,
}


def has_spherical_wrist(chain: NumericChain) -> bool:
    """Six joints whose last three revolute axes meet in one point, with 90 deg twists."""
    return (
        chain.dof == 6
        and chain.kinds[3:] == ("revolute",) * 3
        and bool(twist_sign(chain.alpha[3]))
        and bool(twist_sign(chain.alpha[4]))
        and all(chain.is_zero_length(x) for x in (chain.a[3], chain.a[4], chain.d[4]))
    )


def tail_inverse(chain: NumericChain) -> np.ndarray:
    """``(Tx(a_6) Rx(alpha_6) tool)^-1``: what follows ``Rz(th6) Tz(d6)`` taken off a target."""
    tail = homogeneous(rot_x(chain.alpha[5]), (chain.a[5], 0.0, 0.0)) @ chain.tool
    return rigid_inverse(tail)


def spherical_wrist_solver(chain: NumericChain) -> SphericalWristSolver | None:
    """The Pieper solver if ``chain`` has a spherical wrist and a recognised arm, else None."""
    if not has_spherical_wrist(chain) or chain.kinds[:3] not in ARMS:
        return None
    arm = ARMS[chain.kinds[:3]](chain)
    if arm is None:
        return None
    wrist = Wrist(
        twist4=twist_sign(chain.alpha[3]),
        twist5=twist_sign(chain.alpha[4]),
        undo4=rot_x(chain.alpha[3]).T,
        undo5=rot_x(chain.alpha[4]).T,
        theta=chain.theta[3:],
    )
    return SphericalWristSolver(
        arm=arm,
        wrist=wrist,
        twists=tuple(rot_x(alpha) for alpha in chain.alpha[:3]),
        d6=chain.d[5],
        head_inverse=rigid_inverse(chain.base),
        tail_inverse=tail_inverse(chain),
        scale=chain.size,
    )
