"""Link transforms and forward kinematics (pure SymPy).

Standard DH (Spong; docs/conventions.md)::

    A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)

Modified DH (Craig, eq. 3.6)::

    A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)

Placement form (URDF-like; ``P_i`` the joint's constant ``placement``)::

    A_i = P_i Rz(theta_i) Tz(d_i)

with ``theta_i = q_i + theta`` (revolute) or ``d_i = q_i + d`` (prismatic), ``-q_i`` for a
flipped joint, and ``T = base * A_1 * ... * A_n * tool``.  Each product is contracted with
:func:`~symkin.derive.simplify.contract_trig` as it is formed, so ``T_0_i`` stays readable
(``sin(q2 + q3)`` rather than four products).
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import sympy as sp
from sympy.core.parameters import distribute

from symkin.derive.pythagorean import fold_pythagorean
from symkin.derive.simplify import contract_matrix, contract_product
from symkin.robot import Joint, Robot
from symkin.spatial import euler_zyx_from_rotation, rot_x, rot_z, rpy_from_rotation
from symkin.symbols import joint_symbols


def joint_dh_values(joint: Joint, q: sp.Symbol) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """``(theta, d, a, alpha)`` of one joint with its variable ``q`` inserted (``-q`` when
    the joint is flipped)."""
    variable = -q if joint.flip else q
    if joint.type == "revolute":
        return variable + joint.theta, joint.d, joint.a, joint.alpha
    return joint.theta, variable + joint.d, joint.a, joint.alpha


def joint_axis_sign(joint: Joint) -> int:
    """``-1`` for a flipped joint (it moves about or along ``-z`` as ``q`` grows), else 1."""
    return -1 if joint.flip else 1


def trig_pair(angle: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """``(cos, sin)`` of an angle; a constant without a closed form becomes a Float.

    ``cos(pi/3)`` stays ``1/2``, but ``cos(pi/18)`` would stay a symbol-like constant that
    multiplies the size of every expanded product; its 17-digit value reads and computes better.
    """
    pair = (sp.cos(angle), sp.sin(angle))
    if angle.is_number:
        return tuple(v.evalf(17) if v.has(sp.cos, sp.sin) else v for v in pair)
    return pair


def numeric_trig_constants(matrix: sp.MatrixBase) -> sp.ImmutableMatrix:
    """A constant transform with ``cos(pi/18)``-like entries evaluated (see :func:`trig_pair`)."""
    return sp.ImmutableMatrix(
        matrix.applyfunc(lambda e: e.evalf(17) if e.is_number and e.has(sp.cos, sp.sin) else e)
    )


def standard_dh_matrix(theta: sp.Expr, d: sp.Expr, a: sp.Expr, alpha: sp.Expr) -> sp.Matrix:
    """``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` in closed form."""
    (ct, st), (ca, sa) = trig_pair(theta), trig_pair(alpha)
    return sp.Matrix(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0, sa, ca, d],
            [0, 0, 0, 1],
        ]
    )


def modified_dh_matrix(theta: sp.Expr, d: sp.Expr, a: sp.Expr, alpha: sp.Expr) -> sp.Matrix:
    """``Rx(alpha) Tx(a) Rz(theta) Tz(d)`` in closed form (Craig's eq. 3.6)."""
    (ct, st), (ca, sa) = trig_pair(theta), trig_pair(alpha)
    return sp.Matrix(
        [
            [ct, -st, 0, a],
            [st * ca, ct * ca, -sa, -sa * d],
            [st * sa, ct * sa, ca, ca * d],
            [0, 0, 0, 1],
        ]
    )


def joint_placement(joint: Joint, convention: str) -> sp.ImmutableMatrix:
    """The constant part ``C_i`` of ``A_i = C_i Rz(theta_i) Tz(d_i)`` in the modified and
    placement forms: ``Rx(alpha_{i-1}) Tx(a_{i-1})`` (Craig's eq. 3.6) or the joint's
    ``placement``.  Its z axis is the joint axis and its origin a point of it, in frame i-1."""
    if convention == "placement":
        return numeric_trig_constants(joint.placement)
    return sp.ImmutableMatrix(modified_dh_matrix(sp.S.Zero, sp.S.Zero, joint.a, joint.alpha))


def placement_xyz_rpy(placement: sp.MatrixBase) -> tuple[tuple[sp.Expr, ...], tuple[sp.Expr, ...]]:
    """``(xyz, rpy)`` of a placement, URDF's ``origin`` form: translation and fixed-axis
    roll-pitch-yaw, ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    angles = rpy_from_rotation(sp.Matrix(placement[:3, :3]))
    xyz = tuple(placement[:3, 3])
    return xyz, tuple(sp.sympify(a) for a in (angles.roll, angles.pitch, angles.yaw))


def link_transform(joint: Joint, q: sp.Symbol, convention: str) -> sp.ImmutableMatrix:
    """``A_i``: pose of frame i in frame i-1 for one joint."""
    theta, d, a, alpha = joint_dh_values(joint, q)
    if convention == "standard":
        return sp.ImmutableMatrix(standard_dh_matrix(theta, d, a, alpha))
    if convention == "modified":
        return sp.ImmutableMatrix(modified_dh_matrix(theta, d, a, alpha))
    # Placement: the variable part is modified DH's with a = alpha = 0 (Rz(theta) Tz(d)).
    return sp.ImmutableMatrix(
        joint_placement(joint, convention) * modified_dh_matrix(theta, d, sp.S.Zero, sp.S.Zero)
    )


@dataclass(frozen=True)
class Kinematics:
    """Forward kinematics of a robot, all in the base frame of ``base``'s parent.

    ``frame_transforms[i]`` is ``T_0_i = base * A_1 ... A_i`` (index 0 is ``base``), and
    ``forward_kinematics`` is ``T = T_0_n * tool``.  ``joint_frames[i]`` is the frame whose
    z axis is joint i+1's axis, pointing where ``q_{i+1}`` grows: frame i in standard DH,
    frame i+1 in modified DH, turned half a turn about its x axis for a flipped joint (same
    origin, ``y`` and ``z`` negated), so the Jacobians, the twists of point motion and the
    Lagrange angular velocities need no case for the flip.
    """

    q: tuple[sp.Symbol, ...]
    link_transforms: tuple[sp.ImmutableMatrix, ...]
    frame_transforms: tuple[sp.ImmutableMatrix, ...]
    joint_frames: tuple[sp.ImmutableMatrix, ...]
    forward_kinematics: sp.ImmutableMatrix
    angle_sums: bool
    simplified: bool = True

    def contract(self, matrix: sp.MatrixBase) -> sp.ImmutableMatrix:
        """The simplification policy for this chain (see :func:`contract_matrix`).

        Unsimplified kinematics keep the raw product form: it reads worse but, after common
        subexpression elimination, gives the shortest code (a recursive product, in effect).
        """
        if not self.simplified:
            return sp.ImmutableMatrix(matrix)
        return contract_matrix(matrix, self.angle_sums)

    def contract_product(self, left: sp.MatrixBase, right: sp.MatrixBase) -> sp.ImmutableMatrix:
        """``contract(left * right)``, the product formed in SymEngine when simplified."""
        if not self.simplified:
            # SymPy would distribute each numeric factor over the sum it multiplies, rebuilding
            # the whole tree of T_0_{k-1} at every link (a generic 12R: 4.9 s, 0.7 s without).
            with distribute(False):
                return sp.ImmutableMatrix(left * right)
        return contract_product(left, right, self.angle_sums)

    @property
    def tool_position(self) -> sp.ImmutableMatrix:
        """Tool position ``p`` (3x1), the translation of ``T``."""
        return self.forward_kinematics[:3, 3]

    @property
    def tool_rotation(self) -> sp.ImmutableMatrix:
        """Tool orientation ``R`` (3x3), the rotation of ``T``."""
        return self.forward_kinematics[:3, :3]


def _rotation_between_revolute_axes(robot: Robot, j: int, k: int) -> sp.Matrix:
    """Constant part of the rotation from joint j's axis frame to joint k's (0-based, j < k).

    The variable rotation about joint j's own axis is left out: it cannot tilt that axis.
    """
    rotation = sp.eye(3)
    joints = robot.joints
    if robot.convention == "standard":
        rotation *= rot_x(joints[j].alpha)
        for m in range(j + 1, k):
            rotation *= rot_z(joints[m].theta) * rot_x(joints[m].alpha)
    else:
        for m in range(j + 1, k):
            rotation *= _constant_rotation(joints[m], robot.convention) * rot_z(joints[m].theta)
        rotation *= _constant_rotation(joints[k], robot.convention)
    return rotation


def _constant_rotation(joint: Joint, convention: str) -> sp.Matrix:
    """The rotation of :func:`joint_placement` (``Rx(alpha)`` in modified DH)."""
    return sp.Matrix(joint_placement(joint, convention)[:3, :3])


def has_parallel_revolute_axes(robot: Robot) -> bool:
    """Whether two successive revolute joints have parallel axes in every configuration.

    Only then can sums of joint angles (``sin(q2 + q3)``) arise in the kinematics; a chain
    like the Panda's, with every axis at 90 degrees to the next, has none.
    """
    revolute = [i for i, joint in enumerate(robot.joints) if joint.type == "revolute"]
    for j, k in itertools.pairwise(revolute):
        z_component = sp.nsimplify(_rotation_between_revolute_axes(robot, j, k)[2, 2])
        if not z_component.is_number or abs(z_component) == 1:
            return True
    return False


def _half_turn_about_x(frame: sp.ImmutableMatrix) -> sp.ImmutableMatrix:
    """``frame * Rx(pi)``: the same origin and x axis, ``y`` and ``z`` negated."""
    return sp.ImmutableMatrix(frame * sp.diag(1, -1, -1, 1))


def joint_axis_frames(robot: Robot, frames: list[sp.ImmutableMatrix]) -> list[sp.ImmutableMatrix]:
    """Joint i's axis frame (z where ``q_i`` grows) from the frames ``T_0_0 .. T_0_n``:
    frame i-1 in standard DH, frame i otherwise, half a turn about x for a flipped joint."""
    axis_frames = frames[:-1] if robot.convention == "standard" else frames[1:]
    return [
        _half_turn_about_x(frame) if joint.flip else frame
        for joint, frame in zip(robot.joints, axis_frames, strict=True)
    ]


def kinematics_from_robot(robot: Robot, simplified: bool = True) -> Kinematics:
    """Per-joint and cumulative transforms and ``T`` of ``robot`` (symbolic).

    ``simplified=False`` keeps every product unexpanded (the form code generation uses).
    """
    q = joint_symbols(robot.dof)
    links = tuple(
        link_transform(joint, qi, robot.convention)
        for joint, qi in zip(robot.joints, q, strict=True)
    )
    policy = Kinematics(q, links, (), (), robot.tool, has_parallel_revolute_axes(robot), simplified)
    frames = [numeric_trig_constants(robot.base)]
    for link in links:
        frames.append(policy.contract_product(frames[-1], link))
    joint_frames = joint_axis_frames(robot, frames)
    tool = policy.contract_product(frames[-1], numeric_trig_constants(robot.tool))
    return dataclasses.replace(
        policy,
        frame_transforms=tuple(frames),
        joint_frames=tuple(joint_frames),
        forward_kinematics=tool,
    )


def euler_zyx_of_tool(kinematics: Kinematics, method: str = "atan2") -> tuple[sp.Expr, ...]:
    """``(psi, theta, phi)`` with ``R = Rz(psi) Ry(theta) Rx(phi)``, symbolic.

    ``method="atan2"`` uses ``theta = atan2(-r31, sqrt(r11^2 + r21^2))``;
    ``method="lecture"`` the lecture's eq. (14.7)
    ``theta = atan2(-r31, r11 cos psi + r21 sin psi)``.  ``sin^2 + cos^2`` is folded to 1
    (a planar arm's ``sqrt(r11^2 + r21^2)``; :mod:`symkin.derive.pythagorean`).
    """
    angles = euler_zyx_from_rotation(kinematics.tool_rotation, method=method)
    return tuple(fold_pythagorean(sp.sympify(a)) for a in (angles.psi, angles.theta, angles.phi))
