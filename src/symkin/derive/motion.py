"""Position, velocity and acceleration of a point fixed in a link: closed forms by the
U-matrix method, and the link-by-link recursion that code generation uses.

With ``W_i = base A_1 ... A_i`` and a point ``r`` given in frame i (homogeneous
coordinates)::

    p = W_i r
    v = sum_j U_ij r dq_j
    a = (sum_j sum_k U_ijk dq_j dq_k + sum_j U_ij ddq_j) r

``U_ij = dW_i/dq_j`` and ``U_ijk = d^2 W_i / dq_j dq_k`` (zero for j > i).  The derivative
of a joint transform is ``Q A`` with ``Q_R = [[0,-1,0,0],[1,0,0,0],0,0]`` for a revolute
and ``Q_P`` with a single 1 at (3,4) for a prismatic joint, taken in the joint's own frame
``Z_j`` (frame j-1 in standard DH, frame j in modified DH).  Carried to the base frame this is
the twist matrix ``D_j = Z_j Q_j Z_j^-1``, and (Paul, "Robot Manipulators", ch. 6)::

    U_ij  = D_j W_i
    U_ijk = D_min(j,k) D_max(j,k) W_i

These single expressions suit reading and evaluation, but their double sum makes code grow
with the square of the link index (the PUMA's tool point cost about 2,800 operations after
CSE).  :attr:`PointMotion.assignments` and :attr:`PointMotion.outputs` are the same three
vectors from the outward Newton–Euler pass instead (:func:`~symkin.derive.recursion.
point_motion_recursion`): ``v = R_0_i (v_i + w_i x r)``, ``a = R_0_i (dv_i + U_i r)`` with
``w_i``, ``U_i``, ``v_i``, ``dv_i`` in frame i, every step named, so the code grows linearly.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from symkin.derive.kinematics import Kinematics
from symkin.derive.recursion import Recorder, point_motion_recursion, robot_recorder
from symkin.errors import SymkinError
from symkin.robot import Robot
from symkin.spatial import transform_inverse

Q_REVOLUTE = sp.ImmutableMatrix([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]])
Q_PRISMATIC = sp.ImmutableMatrix([[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, 0, 0]])


def twist_matrices(robot: Robot, kinematics: Kinematics) -> tuple[sp.ImmutableMatrix, ...]:
    """``D_j = Z_j Q_j Z_j^-1`` for every joint (4x4, base frame)."""
    twists = []
    for joint, frame in zip(robot.joints, kinematics.joint_frames, strict=True):
        q_matrix = Q_REVOLUTE if joint.type == "revolute" else Q_PRISMATIC
        twists.append(kinematics.contract(frame * q_matrix * transform_inverse(frame)))
    return tuple(twists)


@dataclass(frozen=True)
class PointMotion:
    """Base-frame position, velocity and acceleration (3x1 each) of a point on a link.

    Each is derived on first use: a velocity costs more than a position and an acceleration
    more than both, and callers often want only the first.  ``assignments`` and ``outputs``
    are the recursive form of all three (named intermediates; the input of code generation).
    """

    robot: Robot
    kinematics: Kinematics
    link: int
    point: tuple[sp.Expr, sp.Expr, sp.Expr]
    dq: tuple[sp.Symbol, ...]
    ddq: tuple[sp.Symbol, ...]

    def __post_init__(self) -> None:
        if not 0 <= self.link <= self.robot.dof:
            raise SymkinError(f"link must be between 0 and {self.robot.dof}, got {self.link}")
        if len(self.point) != 3:
            raise SymkinError(f"a point needs 3 coordinates, got {len(self.point)}")

    @cached_property
    def _recursion(self) -> tuple[Recorder, tuple[sp.Matrix, sp.Matrix, sp.Matrix]]:
        recorder = robot_recorder(self.robot, "m")
        outputs = point_motion_recursion(
            self.robot, self.kinematics, self.link, self.point, recorder, self.dq, self.ddq
        )
        return recorder, outputs

    @property
    def assignments(self) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The recursion's named intermediates, in evaluation order."""
        return tuple(self._recursion[0].assignments)

    @property
    def outputs(self) -> tuple[sp.ImmutableMatrix, ...]:
        """Position, velocity and acceleration (3x1 each) in the named intermediates."""
        return tuple(sp.ImmutableMatrix(m) for m in self._recursion[1])

    @cached_property
    def _world(self) -> sp.Matrix:
        return self.kinematics.frame_transforms[self.link] * sp.Matrix([*self.point, 1])

    @cached_property
    def _twists(self) -> tuple[sp.ImmutableMatrix, ...]:
        return twist_matrices(self.robot, self.kinematics)[: self.link]

    @cached_property
    def position(self) -> sp.ImmutableMatrix:
        """``p = W_i r``."""
        return self.kinematics.contract(self._world[:3, 0])

    @cached_property
    def velocity(self) -> sp.ImmutableMatrix:
        """``v = sum_j U_ij r dq_j`` with ``U_ij = D_j W_i``."""
        velocity = sp.zeros(4, 1)
        for j, twist in enumerate(self._twists):
            velocity += twist * self._world * self.dq[j]
        return self.kinematics.contract(velocity[:3, 0])

    @cached_property
    def acceleration(self) -> sp.ImmutableMatrix:
        """``a = (sum_jk U_ijk dq_j dq_k + sum_j U_ij ddq_j) r``, ``U_ijk = D_min D_max W_i``."""
        acceleration = sp.zeros(4, 1)
        for j, twist_j in enumerate(self._twists):
            acceleration += twist_j * self._world * self.ddq[j]
            for k, twist_k in enumerate(self._twists):
                first, second = (twist_k, twist_j) if k <= j else (twist_j, twist_k)
                acceleration += first * second * self._world * self.dq[j] * self.dq[k]
        return self.kinematics.contract(acceleration[:3, 0])
