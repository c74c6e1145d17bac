"""Rotations, orientation representations and homogeneous transforms.

Conventions (see ``docs/conventions.md``):

* Rotations are **active**, right-handed, acting on **column vectors**: ``p' = R p``.
* Z-Y-X Euler ``R = Rz(psi) Ry(theta) Rx(phi)`` (moving axes z, y', x'') is the same matrix as
  roll-pitch-yaw about **fixed** axes X, Y, Z (``rpy_xyz_fixed``): roll about X first, then
  pitch about Y, then yaw about Z.
* Z-Y-Z Euler ``R = Rz(alpha) Ry(beta) Rz(gamma)``.
* All twelve Euler/Tait-Bryan orders: intrinsic ``"abc"`` is ``R = Ra(t1) Rb(t2) Rc(t3)``;
  extrinsic ``"abc"`` (fixed axes, a first) is the intrinsic order ``"cba"`` with the angles
  reversed.  The rotation vector is ``w = axis * angle``.
* Quaternions are ``(w, x, y, z)``, scalar first; conversions from rotations return ``w >= 0``.
* Twists are ``(v, w)`` (linear first), wrenches ``(f, tau)`` (force first).
* Homogeneous transforms are 4x4 ``[R p; 0 1]``; ``T_a_b`` is the pose of frame b in frame a.

Every function works on SymPy and NumPy values alike.  If any input is a SymPy object the
computation is symbolic and returns :class:`sympy.ImmutableMatrix` / SymPy expressions; otherwise
it returns ``numpy.ndarray`` (float64) / ``float``.  There is one implementation per function:
the handful of primitives that differ (sin, cos, atan2, sqrt, matrix constructor, "is this
zero?") are dispatched through :class:`symkin.spatial.backend.Backend`.

The functions live in :mod:`~symkin.spatial.rotations` (elementary rotations, axis-angle),
:mod:`~symkin.spatial.quaternions` (quaternion algebra, slerp, conversions),
:mod:`~symkin.spatial.euler` (the twelve Euler/Tait-Bryan orders; Z-Y-X / roll-pitch-yaw and
Z-Y-Z by name), :mod:`~symkin.spatial.orientation` (an Euler order or the rotation vector by
name),
:mod:`~symkin.spatial.transforms` (homogeneous transforms, :class:`TransformGraph`),
:mod:`~symkin.spatial.inertia` (inertia tensors: rotation, Steiner, composite bodies,
simple solids), :mod:`~symkin.spatial.lie` (exp/log of SO(3) and SE(3)) and
:mod:`~symkin.spatial.screws`
(screw axes, twists ``(v, w)``, wrenches ``(f, tau)``, the adjoint); all are importable from
here.
"""

from symkin.spatial.backend import (
    ORTHONORMAL_TOL,
    SINGULAR_TOL,
    ZERO_NORM_TOL,
    Matrix,
    MatrixLike,
    Scalar,
)
from symkin.spatial.euler import (
    EULER_ORDERS,
    PROPER_EULER_ORDERS,
    RPY,
    TAIT_BRYAN_ORDERS,
    EulerAngles,
    EulerZYX,
    EulerZYZ,
    euler_from_rotation,
    euler_zyx_from_rotation,
    euler_zyz_from_rotation,
    rotation_from_euler,
    rotation_from_euler_zyx,
    rotation_from_euler_zyz,
    rotation_from_rpy,
    rpy_from_rotation,
)
from symkin.spatial.inertia import (
    RigidBody,
    box_inertia,
    box_volume,
    composite_body,
    cylinder_inertia,
    cylinder_volume,
    hollow_cylinder_inertia,
    inertia_about_com,
    inertia_about_point,
    rotated_inertia,
    sphere_inertia,
    sphere_volume,
)
from symkin.spatial.lie import (
    RotationLog,
    TransformLog,
    rotation_from_rotation_vector,
    rotation_vector_from_rotation,
    skew,
    transform_from_twist,
    twist_from_transform,
)
from symkin.spatial.orientation import (
    ORIENTATIONS,
    Orientation,
    orientation_from_rotation,
    rotation_from_orientation,
)
from symkin.spatial.quaternions import (
    quaternion_canonical,
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_inverse,
    quaternion_product,
    quaternion_slerp,
    rotation_from_quaternion,
    unit_quaternion,
)
from symkin.spatial.rotations import (
    AxisAngle,
    axis_angle_from_rotation,
    rot_x,
    rot_y,
    rot_z,
    rotation_from_axis_angle,
)
from symkin.spatial.screws import (
    adjoint_from_transform,
    screw_axis_from_line,
    transform_twist,
    transform_wrench,
    twist_from_screw,
)
from symkin.spatial.transforms import (
    TransformGraph,
    transform_from_rotation_translation,
    transform_inverse,
    transform_point,
)

__all__ = [
    "EULER_ORDERS",
    "ORIENTATIONS",
    "ORTHONORMAL_TOL",
    "PROPER_EULER_ORDERS",
    "RPY",
    "SINGULAR_TOL",
    "TAIT_BRYAN_ORDERS",
    "ZERO_NORM_TOL",
    "AxisAngle",
    "EulerAngles",
    "EulerZYX",
    "EulerZYZ",
    "Matrix",
    "MatrixLike",
    "Orientation",
    "RigidBody",
    "RotationLog",
    "Scalar",
    "TransformGraph",
    "TransformLog",
    "adjoint_from_transform",
    "axis_angle_from_rotation",
    "box_inertia",
    "box_volume",
    "composite_body",
    "cylinder_inertia",
    "cylinder_volume",
    "euler_from_rotation",
    "euler_zyx_from_rotation",
    "euler_zyz_from_rotation",
    "hollow_cylinder_inertia",
    "inertia_about_com",
    "inertia_about_point",
    "orientation_from_rotation",
    "quaternion_canonical",
    "quaternion_conjugate",
    "quaternion_from_rotation",
    "quaternion_inverse",
    "quaternion_product",
    "quaternion_slerp",
    "rot_x",
    "rot_y",
    "rot_z",
    "rotated_inertia",
    "rotation_from_axis_angle",
    "rotation_from_euler",
    "rotation_from_euler_zyx",
    "rotation_from_euler_zyz",
    "rotation_from_orientation",
    "rotation_from_quaternion",
    "rotation_from_rotation_vector",
    "rotation_from_rpy",
    "rotation_vector_from_rotation",
    "rpy_from_rotation",
    "screw_axis_from_line",
    "skew",
    "sphere_inertia",
    "sphere_volume",
    "transform_from_rotation_translation",
    "transform_from_twist",
    "transform_inverse",
    "transform_point",
    "transform_twist",
    "transform_wrench",
    "twist_from_screw",
    "twist_from_transform",
    "unit_quaternion",
]
