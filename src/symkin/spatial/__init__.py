"""Rotations, orientation representations and homogeneous transforms.

Conventions (see ``docs/conventions.md``):

* Rotations are **active**, right-handed, acting on **column vectors**: ``p' = R p``.
* Z-Y-X Euler ``R = Rz(psi) Ry(theta) Rx(phi)`` (moving axes z, y', x'') is the same matrix as
  roll-pitch-yaw about **fixed** axes X, Y, Z (``rpy_xyz_fixed``): roll about X first, then
  pitch about Y, then yaw about Z.
* Z-Y-Z Euler ``R = Rz(alpha) Ry(beta) Rz(gamma)``.
* Quaternions are ``(w, x, y, z)``, scalar first.
* Homogeneous transforms are 4x4 ``[R p; 0 1]``; ``T_a_b`` is the pose of frame b in frame a.

Every function works on SymPy and NumPy values alike.  If any input is a SymPy object the
computation is symbolic and returns :class:`sympy.ImmutableMatrix` / SymPy expressions; otherwise
it returns ``numpy.ndarray`` (float64) / ``float``.  There is one implementation per function:
the handful of primitives that differ (sin, cos, atan2, sqrt, matrix constructor, "is this
zero?") are dispatched through :class:`symkin.spatial.backend.Backend`.

The functions live in :mod:`~symkin.spatial.rotations` (elementary rotations, axis-angle,
quaternions), :mod:`~symkin.spatial.euler` (Z-Y-X / roll-pitch-yaw and Z-Y-Z angles) and
:mod:`~symkin.spatial.transforms` (homogeneous transforms, :class:`TransformGraph`); all are
importable from here.
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
    RPY,
    EulerZYX,
    EulerZYZ,
    euler_zyx_from_rotation,
    euler_zyz_from_rotation,
    rotation_from_euler_zyx,
    rotation_from_euler_zyz,
    rotation_from_rpy,
    rpy_from_rotation,
)
from symkin.spatial.rotations import (
    AxisAngle,
    axis_angle_from_rotation,
    quaternion_from_rotation,
    rot_x,
    rot_y,
    rot_z,
    rotation_from_axis_angle,
    rotation_from_quaternion,
)
from symkin.spatial.transforms import (
    TransformGraph,
    transform_from_rotation_translation,
    transform_inverse,
    transform_point,
)

__all__ = [
    "ORTHONORMAL_TOL",
    "RPY",
    "SINGULAR_TOL",
    "ZERO_NORM_TOL",
    "AxisAngle",
    "EulerZYX",
    "EulerZYZ",
    "Matrix",
    "MatrixLike",
    "Scalar",
    "TransformGraph",
    "axis_angle_from_rotation",
    "euler_zyx_from_rotation",
    "euler_zyz_from_rotation",
    "quaternion_from_rotation",
    "rot_x",
    "rot_y",
    "rot_z",
    "rotation_from_axis_angle",
    "rotation_from_euler_zyx",
    "rotation_from_euler_zyz",
    "rotation_from_quaternion",
    "rotation_from_rpy",
    "rpy_from_rotation",
    "transform_from_rotation_translation",
    "transform_inverse",
    "transform_point",
]
