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

The arm classes' fields are the constants of :func:`wrist_constants`, evaluated.
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
    clamped_sqrt,
    elbow_flag,
    extension_flag,
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

#: One solution of the first three joints: joint values, DH angles theta_1..3, branch flags.
ArmSolution = tuple[tuple[float, float, float], tuple[float, float, float], tuple]


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

    @classmethod
    def from_values(cls, shape: Shape, values: Values) -> ArticulatedArm:
        return cls(
            twist1=shape["twist1"],
            d1=values["d1"][0],
            a1=values["a1"][0],
            offset=values["offset"][0],
            link2=values["link2"],
            link3=values["link3"],
            theta=values["theta"][:3],
            scale=values["scale"][0],
        )

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

    @classmethod
    def from_values(cls, shape: Shape, values: Values) -> SphericalArm:
        return cls(
            twist1=shape["twist1"],
            twist2=shape["twist2"],
            d1=values["d1"][0],
            a1=values["a1"][0],
            offset=values["offset"][0],
            k=values["k"][0],
            reach_offset=values["reach_offset"][0],
            theta=values["theta"][:3],
            scale=values["scale"][0],
        )

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

    @classmethod
    def from_values(cls, shape: Shape, values: Values) -> CylindricalArm:
        del shape  # no signs: they are in g and e
        return cls(
            height=values["height"][0],
            g=values["g"],
            e=values["e"],
            reach_offset=values["reach_offset"][0],
            theta=values["theta"][:3],
            scale=values["scale"][0],
        )

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
#: The arm classes by the ``arm`` of a wrist :class:`Shape`.
ARMS: dict[str, type[ArticulatedArm] | type[SphericalArm] | type[CylindricalArm]] = {
    "articulated": ArticulatedArm,
    "spherical": SphericalArm,
    "cylindrical": CylindricalArm,
}


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

    family: str
    arm: Arm
    wrist: Wrist
    twists: tuple[np.ndarray, ...]  # Rx(alpha_1), Rx(alpha_2), Rx(alpha_3)
    d6: float
    head_inverse: np.ndarray
    tail_inverse: np.ndarray
    scale: float
    task = "pose"

    @classmethod
    def from_plan(cls, plan: ClosedFormPlan, values: Values, dof: int) -> SphericalWristSolver:
        del dof  # six
        shape = plan.shape
        rotations = twist_rotations(values["twist_cos"], values["twist_sin"])
        wrist = Wrist(
            twist4=shape["twist4"],
            twist5=shape["twist5"],
            undo4=rotations[3].T,
            undo5=rotations[4].T,
            theta=values["theta"][3:],
        )
        return cls(
            family=shape.name,
            arm=ARMS[shape.arm].from_values(shape, values),
            wrist=wrist,
            twists=tuple(rotations[:3]),
            d6=values["d6"][0],
            head_inverse=transform(values.get("head_inverse")),
            tail_inverse=transform(values.get("tail_inverse")),
            scale=values["scale"][0],
        )

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


#: The arm's kind by its joint types, and which lengths its formulas divide by.
ARM_KINDS = {
    ("revolute", "revolute", "revolute"): ("articulated", (("link2", 0), ("link3", 0))),
    ("revolute", "revolute", "prismatic"): ("spherical", ()),
    ("revolute", "prismatic", "prismatic"): ("cylindrical", ()),
}
#: Twists the arm needs: (index, +-90 deg) or (index, 0).
ARM_TWISTS = {
    "articulated": ((0, True), (1, False)),
    "spherical": ((0, True), (1, True)),
    "cylindrical": ((0, False), (1, True)),
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


def spherical_wrist_shape(chain: NumericChain) -> Shape | None:
    """The Pieper shape if ``chain`` has a spherical wrist and a recognised arm, else None."""
    if not has_spherical_wrist(chain) or chain.kinds[:3] not in ARM_KINDS:
        return None
    arm, nonzero = ARM_KINDS[chain.kinds[:3]]
    for index, right_angle in ARM_TWISTS[arm]:
        alpha = chain.alpha[index]
        if not (twist_sign(alpha) if right_angle else is_parallel(alpha)):
            return None
    twists = {f"twist{i + 1}": twist_sign(chain.alpha[i]) for i in (0, 1, 3, 4)}
    return Shape(
        family="wrist",
        arm=arm,
        name=f"spherical wrist, {arm} {''.join(k[0].upper() for k in chain.kinds[:3])} arm",
        task="pose",
        structure=tuple(twists.items()),
        nonzero=nonzero,
    )


def wrist_centre_in_frame2(chain: SymbolicChain) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``(c_x, c_y, c_z)``: the wrist centre ``(0, 0, d_4)`` of frame 3 in frame 2, without
    the joint-3 motion: ``Rot(theta_3) (a_3, -sin(al3) d_4)`` and ``d_3 + cos(al3) d_4``."""
    a3, alpha3, d4 = chain.a[2], chain.alpha[2], chain.d[3]
    cx, cy = a3, -sp.sin(alpha3) * d4
    if chain.kinds[2] == "prismatic":
        c, s = sp.cos(chain.theta[2]), sp.sin(chain.theta[2])
        cx, cy = c * cx - s * cy, s * cx + c * cy
    return cx, cy, chain.d[2] + sp.cos(alpha3) * d4


def arm_constants(chain: SymbolicChain, shape: Shape) -> list[Constant]:
    """The constants of the arm's formulas (the fields of its class)."""
    a, d = chain.a, chain.d
    twist1, twist2 = shape["twist1"], shape["twist2"]
    if shape.arm == "articulated":
        height = d[1] + d[2] + sp.cos(chain.alpha[2]) * d[3]
        return [
            Constant("d1", (d[0],), "d_1"),
            Constant("a1", (a[0],), "a_1"),
            Constant("offset", (-twist1 * height,), "wrist centre's distance from the arm's plane"),
            Constant("link2", polar(a[1], sp.S.Zero), "(a_2, 0) in polar form (length, angle)"),
            Constant(
                "link3",
                polar(a[2], -sp.sin(chain.alpha[2]) * d[3]),
                "(a_3, -sin(alpha_3) d_4) in polar form",
            ),
        ]
    cx, cy, cz = wrist_centre_in_frame2(chain)
    if shape.arm == "spherical":
        return [
            Constant("d1", (d[0],), "d_1"),
            Constant("a1", (a[0],), "a_1"),
            Constant("offset", (-twist1 * (d[1] + twist2 * cy),), "shoulder offset"),
            Constant("k", (a[1] + cx,), "the reach's distance from the shoulder axis"),
            Constant("reach_offset", (cz,), "lambda - q_3"),
        ]
    c, s = sp.cos(chain.theta[1]), sp.sin(chain.theta[1])
    k = a[1] + cx
    return [
        Constant("height", (d[0] + d[1] + twist2 * cy,), "z of the wrist centre minus q_2"),
        Constant("g", (a[0] + c * k, s * k), "horizontal wrist centre at zero radial reach"),
        Constant("e", (s * twist2, -c * twist2), "unit direction of the radial reach"),
        Constant("reach_offset", (cz,), "lambda - q_3"),
    ]


def wrist_constants(chain: SymbolicChain, shape: Shape) -> list[Constant]:
    """The arm's constants, the twists, the DH angles, ``d_6`` and the frames."""
    return [
        *arm_constants(chain, shape),
        *twist_constants(chain),
        Constant("theta", chain.theta, "theta_i - q_i (revolute) or theta_i (prismatic)"),
        Constant("d6", (chain.d[5],), "d_6: wrist centre to flange along z_6"),
        *frame_constants(chain, tail(chain)),
    ]
