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
zero?") are dispatched through :class:`_Backend`.
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from collections.abc import Hashable, Sequence
from typing import Any, NamedTuple

import numpy as np
import sympy as sp

from symkin.errors import SymkinError

__all__ = [
    "RPY",
    "AxisAngle",
    "EulerZYX",
    "EulerZYZ",
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

#: Numeric inputs to the inverse maps must satisfy ``|R^T R - I| <= ORTHONORMAL_TOL`` and
#: ``det R > 0``; anything further off is a user mistake, not rounding.
ORTHONORMAL_TOL = 1e-6
#: Numeric singularity threshold.  Near a singularity the angles are ill-conditioned
#: (error ~ 1e-16 / distance), while the fallback branch is off by ~ distance, so the
#: best switch point is about sqrt(machine epsilon).
SINGULAR_TOL = 1e-8
#: A numeric axis or quaternion shorter than this is "zero" (no direction to normalise).
ZERO_NORM_TOL = 1e-12

#: A scalar: a Python/NumPy number or a SymPy expression.
Scalar = float | sp.Expr
#: A matrix result: a float64 array or an immutable SymPy matrix.
Matrix = np.ndarray | sp.ImmutableMatrix
#: Anything convertible to a matrix or vector (nested sequences, arrays, SymPy matrices).
MatrixLike = Any


# --------------------------------------------------------------------------------------------
# Backend dispatch
# --------------------------------------------------------------------------------------------


def _is_symbolic(x: object) -> bool:
    """True if ``x`` is (or contains) a SymPy object."""
    if isinstance(x, sp.Basic | sp.MatrixBase):
        return True
    if isinstance(x, np.ndarray):
        # Only object arrays can hold SymPy values; float arrays are numeric by construction.
        return x.dtype == object and any(_is_symbolic(e) for e in x.flat)
    if isinstance(x, list | tuple):
        return any(_is_symbolic(e) for e in x)
    return False


class _Backend:
    """The few primitives that differ between the SymPy and the NumPy computation."""

    def __init__(self, symbolic: bool) -> None:
        self.symbolic = symbolic

    # Scalars ---------------------------------------------------------------------------------
    def scalar(self, x: Any, name: str = "value") -> Scalar:
        if self.symbolic:
            return sp.sympify(x)
        try:
            return float(x)
        except (TypeError, ValueError) as exc:
            raise SymkinError(f"{name} must be a real number, got {x!r}") from exc

    def sin(self, x: Scalar) -> Scalar:
        return sp.sin(x) if self.symbolic else math.sin(x)

    def cos(self, x: Scalar) -> Scalar:
        return sp.cos(x) if self.symbolic else math.cos(x)

    def atan2(self, y: Scalar, x: Scalar) -> Scalar:
        return sp.atan2(y, x) if self.symbolic else math.atan2(y, x)

    def sqrt(self, x: Scalar) -> Scalar:
        # max(0, .) guards a radicand that is -1e-17 by rounding; SymPy radicands are exact.
        return sp.sqrt(x) if self.symbolic else math.sqrt(max(x, 0.0))

    def is_zero(self, x: Scalar, tol: float = SINGULAR_TOL) -> bool | None:
        """Numeric: ``|x| < tol``.  SymPy: True/False when decidable, else None."""
        if not self.symbolic:
            return abs(x) < tol
        x = sp.sympify(x)
        zero = x.is_zero
        if zero is None and not x.free_symbols:
            # A constant the assumption system cannot decide (nested radicals, ...).
            zero = x.equals(0)
        return zero

    def argmax(self, values: Sequence[Scalar]) -> int | None:
        """Index of the largest value; None for SymPy values with free symbols (undecidable)."""
        if self.symbolic:
            if any(sp.sympify(v).free_symbols for v in values):
                return None
            values = [float(sp.N(v)) for v in values]
        return max(range(len(values)), key=lambda i: values[i])

    def is_negative(self, x: Scalar) -> bool:
        """``x < 0``; SymPy values with free symbols count as not negative."""
        if self.symbolic:
            x = sp.sympify(x)
            return not x.free_symbols and float(sp.N(x)) < 0
        return x < 0

    # Matrices --------------------------------------------------------------------------------
    def matrix(self, rows: Sequence[Sequence[Any]]) -> Matrix:
        return sp.ImmutableMatrix(rows) if self.symbolic else np.array(rows, dtype=np.float64)

    def vector(self, items: Sequence[Any]) -> Matrix:
        """A column vector: SymPy n x 1, NumPy shape ``(n,)``."""
        if self.symbolic:
            return sp.ImmutableMatrix(len(items), 1, list(items))
        return np.array(items, dtype=np.float64)


_NUMERIC = _Backend(symbolic=False)
_SYMBOLIC = _Backend(symbolic=True)


def _backend(*args: object) -> _Backend:
    """SymPy if any argument is symbolic, else NumPy."""
    return _SYMBOLIC if any(_is_symbolic(a) for a in args) else _NUMERIC


def _as_matrix(be: _Backend, x: MatrixLike, shape: tuple[int, int], name: str) -> Matrix:
    """Convert ``x`` to a ``shape`` matrix of the backend's kind, or raise SymkinError."""
    try:
        m = sp.ImmutableMatrix(x) if be.symbolic else np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError, sp.SympifyError) as exc:
        raise SymkinError(f"{name} must be a {shape[0]}x{shape[1]} matrix, got {x!r}") from exc
    if tuple(m.shape) != shape:
        raise SymkinError(
            f"{name} must be a {shape[0]}x{shape[1]} matrix, got shape {tuple(m.shape)}"
        )
    return m


def _as_vector(be: _Backend, x: MatrixLike, n: int, name: str) -> list[Scalar]:
    """Convert ``x`` (length-n sequence, row or column) to a list of n backend scalars."""
    try:
        m = sp.ImmutableMatrix(x) if be.symbolic else np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError, sp.SympifyError) as exc:
        raise SymkinError(f"{name} must be a {n}-vector, got {x!r}") from exc
    # Accept shape (n,), (n, 1) and (1, n); SymPy matrices are always 2-D.
    shape = tuple(m.shape)
    if not (shape == (n,) or (len(shape) == 2 and sorted(shape) == [1, n])):
        raise SymkinError(f"{name} must be a {n}-vector, got shape {shape}")
    return list(m) if be.symbolic else [float(v) for v in m.reshape(-1)]


def _rotation_input(R: MatrixLike, name: str = "R") -> tuple[_Backend, Matrix]:
    """Backend and 3x3 matrix for an inverse map; numeric input must be a rotation."""
    be = _backend(R)
    M = _as_matrix(be, R, (3, 3), name)
    if not be.symbolic:
        _check_rotation(M, name)
    return be, M


def _check_rotation(M: np.ndarray, name: str) -> None:
    if not np.all(np.isfinite(M)):
        raise SymkinError(f"{name} must be finite, got {M.tolist()}")
    err = float(np.max(np.abs(M.T @ M - np.eye(3))))
    if err > ORTHONORMAL_TOL or np.linalg.det(M) <= 0:
        raise SymkinError(
            f"{name} must be a rotation matrix (R^T R = I within {ORTHONORMAL_TOL:g}, det R = +1), "
            f"got {M.tolist()}"
        )


def _unit(be: _Backend, items: Sequence[Scalar], name: str) -> list[Scalar]:
    """``items / |items|``; raise SymkinError for a zero vector."""
    n2 = sum(v * v for v in items)
    if be.symbolic:
        # simplify() turns e.g. cos(t)**2 + sin(t)**2 into 1, so unit inputs stay untouched.
        n2 = sp.simplify(n2)
        zero = be.is_zero(n2)
    else:
        zero = not math.isfinite(n2) or math.sqrt(n2) < ZERO_NORM_TOL
    if zero:
        raise SymkinError(f"{name} must be a non-zero vector, got {list(items)}")
    n = be.sqrt(n2)
    return [v / n for v in items]


def _singular_flag(*flags: bool | None) -> bool | None:
    """Combine "is at this singularity" flags: True if any is True, None if any undecided."""
    if any(f is True for f in flags):
        return True
    if any(f is None for f in flags):
        return None
    return False


# --------------------------------------------------------------------------------------------
# Elementary rotations
# --------------------------------------------------------------------------------------------


def rot_x(angle: Scalar) -> Matrix:
    """Active rotation about the x axis by ``angle`` (right-handed, column vectors).

    ``Rx(a) = [[1, 0, 0], [0, cos a, -sin a], [0, sin a, cos a]]``.
    """
    be = _backend(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(angle: Scalar) -> Matrix:
    """Active rotation about the y axis by ``angle`` (right-handed, column vectors).

    ``Ry(a) = [[cos a, 0, sin a], [0, 1, 0], [-sin a, 0, cos a]]``.
    """
    be = _backend(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(angle: Scalar) -> Matrix:
    """Active rotation about the z axis by ``angle`` (right-handed, column vectors).

    ``Rz(a) = [[cos a, -sin a, 0], [sin a, cos a, 0], [0, 0, 1]]``.
    """
    be = _backend(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


# --------------------------------------------------------------------------------------------
# Z-Y-X Euler angles = roll-pitch-yaw about fixed X, Y, Z
# --------------------------------------------------------------------------------------------


def rotation_from_euler_zyx(psi: Scalar, theta: Scalar, phi: Scalar) -> Matrix:
    """Z-Y-X Euler angles (moving axes z, y', x'') to a rotation matrix.

    ``R = Rz(psi) Ry(theta) Rx(phi)``, written out in closed form::

        [ cψ cθ   cψ sθ sφ - sψ cφ   cψ sθ cφ + sψ sφ ]
        [ sψ cθ   sψ sθ sφ + cψ cφ   sψ sθ cφ - cψ sφ ]
        [ -sθ     cθ sφ              cθ cφ            ]

    The same matrix is roll ``phi`` / pitch ``theta`` / yaw ``psi`` about fixed axes X, Y, Z,
    see :func:`rotation_from_rpy`.
    """
    be = _backend(psi, theta, phi)
    psi, theta, phi = (be.scalar(v, n) for v, n in ((psi, "psi"), (theta, "theta"), (phi, "phi")))
    cps, sps = be.cos(psi), be.sin(psi)
    cth, sth = be.cos(theta), be.sin(theta)
    cph, sph = be.cos(phi), be.sin(phi)
    # Closed form rather than three products: SymPy then prints exactly the textbook entries.
    return be.matrix(
        [
            [cps * cth, cps * sth * sph - sps * cph, cps * sth * cph + sps * sph],
            [sps * cth, sps * sth * sph + cps * cph, sps * sth * cph - cps * sph],
            [-sth, cth * sph, cth * cph],
        ]
    )


def rotation_from_rpy(roll: Scalar, pitch: Scalar, yaw: Scalar) -> Matrix:
    """Roll-pitch-yaw about **fixed** axes (``rpy_xyz_fixed``) to a rotation matrix.

    Roll about X first, then pitch about Y, then yaw about Z, all about the fixed (world) axes:
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``.  This is exactly the Z-Y-X Euler matrix with
    ``psi = yaw, theta = pitch, phi = roll`` (:func:`rotation_from_euler_zyx`).
    """
    return rotation_from_euler_zyx(yaw, pitch, roll)


class EulerZYX(NamedTuple):
    """Z-Y-X Euler angles of ``R = Rz(psi) Ry(theta) Rx(phi)``.

    ``singular`` is True at gimbal lock (``cos theta = 0``), False otherwise, and None for
    SymPy input where it cannot be decided.
    """

    psi: Scalar
    theta: Scalar
    phi: Scalar
    singular: bool | None


class RPY(NamedTuple):
    """Roll-pitch-yaw about fixed axes X, Y, Z of ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    ``singular`` as in :class:`EulerZYX` (gimbal lock at ``pitch = +-pi/2``).
    """

    roll: Scalar
    pitch: Scalar
    yaw: Scalar
    singular: bool | None


_ZYX_METHODS = ("atan2", "lecture")


def euler_zyx_from_rotation(R: MatrixLike, method: str = "atan2") -> EulerZYX:
    """Z-Y-X Euler angles ``(psi, theta, phi)`` with ``R = Rz(psi) Ry(theta) Rx(phi)``.

    Regular case (``cos theta > 0`` branch, ``theta`` in ``[-pi/2, pi/2]``)::

        phi   = atan2(r32, r33)
        psi   = atan2(r21, r11)
        theta = atan2(-r31, sqrt(r11² + r21²))                   method="atan2"
        theta = atan2(-r31, r11 cos psi + r21 sin psi)           method="lecture", eq. (14.7)

    The two ``theta`` forms agree: with ``psi = atan2(r21, r11)``,
    ``r11 cos psi + r21 sin psi = sqrt(r11² + r21²)``.

    Gimbal lock (``cos theta = sqrt(r11² + r21²) < SINGULAR_TOL``): only ``psi - phi`` (at
    ``theta = +pi/2``) or ``psi + phi`` (at ``-pi/2``) is defined.  We return ``phi = 0`` and,
    from the second column of ``R Rx(phi)^T = Rz(psi) Ry(theta)``, ``psi = atan2(-r12, r22)``, so
    that ``rotation_from_euler_zyx(psi, theta, phi)`` reproduces ``R``; ``singular=True``.

    SymPy input returns the regular formulas with ``singular=None`` unless ``cos theta`` is
    decidably zero (then the gimbal-lock branch, exactly) or decidably non-zero.
    """
    psi, theta, phi, singular = _euler_zyx_inverse(R, method)
    return EulerZYX(psi, theta, phi, singular)


def rpy_from_rotation(R: MatrixLike, method: str = "atan2") -> RPY:
    """Roll-pitch-yaw about fixed X, Y, Z with ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    The same matrix as Z-Y-X Euler, so this is :func:`euler_zyx_from_rotation` with
    ``roll = phi, pitch = theta, yaw = psi`` (same formulas, same gimbal-lock handling:
    ``roll = 0`` at ``pitch = +-pi/2``).
    """
    psi, theta, phi, singular = _euler_zyx_inverse(R, method)
    return RPY(roll=phi, pitch=theta, yaw=psi, singular=singular)


def _euler_zyx_inverse(R: MatrixLike, method: str) -> tuple[Scalar, Scalar, Scalar, bool | None]:
    if method not in _ZYX_METHODS:
        raise SymkinError(f"method must be one of {', '.join(_ZYX_METHODS)}, got {method!r}")
    be, M = _rotation_input(R)
    r11, r12 = M[0, 0], M[0, 1]
    r21, r22 = M[1, 0], M[1, 1]
    r31, r32, r33 = M[2, 0], M[2, 1], M[2, 2]
    cos_theta = be.sqrt(r11**2 + r21**2)  # = |cos theta| = sqrt(r32² + r33²)
    locked = be.is_zero(cos_theta)
    if locked:
        theta = be.atan2(-r31, cos_theta)  # +-pi/2
        return be.atan2(-r12, r22), theta, be.scalar(0), True
    phi = be.atan2(r32, r33)
    psi = be.atan2(r21, r11)
    if method == "lecture":
        theta = be.atan2(-r31, r11 * be.cos(psi) + r21 * be.sin(psi))
    else:
        theta = be.atan2(-r31, cos_theta)
    return psi, theta, phi, _singular_flag(locked)


# --------------------------------------------------------------------------------------------
# Z-Y-Z Euler angles
# --------------------------------------------------------------------------------------------


class EulerZYZ(NamedTuple):
    """Z-Y-Z Euler angles of ``R = Rz(alpha) Ry(beta) Rz(gamma)``.

    ``singular`` is True at ``beta = 0`` or ``pi`` (``sin beta = 0``), False otherwise, None for
    undecidable SymPy input.
    """

    alpha: Scalar
    beta: Scalar
    gamma: Scalar
    singular: bool | None


def rotation_from_euler_zyz(alpha: Scalar, beta: Scalar, gamma: Scalar) -> Matrix:
    """Z-Y-Z Euler angles to a rotation matrix.

    ``R = Rz(alpha) Ry(beta) Rz(gamma)``, in closed form::

        [ cα cβ cγ - sα sγ   -cα cβ sγ - sα cγ   cα sβ ]
        [ sα cβ cγ + cα sγ   -sα cβ sγ + cα cγ   sα sβ ]
        [ -sβ cγ              sβ sγ              cβ    ]
    """
    be = _backend(alpha, beta, gamma)
    alpha, beta, gamma = (
        be.scalar(v, n) for v, n in ((alpha, "alpha"), (beta, "beta"), (gamma, "gamma"))
    )
    ca, sa = be.cos(alpha), be.sin(alpha)
    cb, sb = be.cos(beta), be.sin(beta)
    cg, sg = be.cos(gamma), be.sin(gamma)
    return be.matrix(
        [
            [ca * cb * cg - sa * sg, -ca * cb * sg - sa * cg, ca * sb],
            [sa * cb * cg + ca * sg, -sa * cb * sg + ca * cg, sa * sb],
            [-sb * cg, sb * sg, cb],
        ]
    )


def euler_zyz_from_rotation(R: MatrixLike) -> EulerZYZ:
    """Z-Y-Z Euler angles ``(alpha, beta, gamma)`` with ``R = Rz(alpha) Ry(beta) Rz(gamma)``.

    Regular case (``sin beta > 0`` branch, ``beta`` in ``(0, pi)``)::

        beta  = atan2(sqrt(r13² + r23²), r33)
        alpha = atan2(r23, r13)
        gamma = atan2(r32, -r31)

    Singular case ``sin beta = sqrt(r13² + r23²) < SINGULAR_TOL`` (``beta = 0``: only
    ``alpha + gamma`` is defined; ``beta = pi``: only ``alpha - gamma``): ``gamma = 0`` and
    ``alpha = atan2(-r12, r22)``, which is right in both cases (``r12 = -sin(alpha +- gamma)``,
    ``r22 = cos(alpha +- gamma)``); ``singular=True``.  SymPy input as in
    :func:`euler_zyx_from_rotation`.
    """
    be, M = _rotation_input(R)
    sin_beta = be.sqrt(M[0, 2] ** 2 + M[1, 2] ** 2)
    beta = be.atan2(sin_beta, M[2, 2])
    at_pole = be.is_zero(sin_beta)
    if at_pole:
        return EulerZYZ(be.atan2(-M[0, 1], M[1, 1]), beta, be.scalar(0), True)
    alpha = be.atan2(M[1, 2], M[0, 2])
    gamma = be.atan2(M[2, 1], -M[2, 0])
    return EulerZYZ(alpha, beta, gamma, _singular_flag(at_pole))


# --------------------------------------------------------------------------------------------
# Axis-angle (Euler parameters)
# --------------------------------------------------------------------------------------------


class AxisAngle(NamedTuple):
    """Unit ``axis`` (NumPy shape ``(3,)`` or SymPy 3x1) and ``angle`` in ``[0, pi]``.

    ``singular`` is True when the axis is not determined by ``R``: at ``angle = 0`` (any axis;
    ``(0, 0, 1)`` is returned) and at ``angle = pi`` (the axis sign is a choice).
    """

    axis: Matrix
    angle: Scalar
    singular: bool | None


def rotation_from_axis_angle(axis: MatrixLike, angle: Scalar) -> Matrix:
    """Rotation by ``angle`` about ``axis`` (right-hand rule), Rodrigues' formula.

    The axis ``k`` is normalised first (a zero axis raises :class:`SymkinError`). With
    ``c = cos angle``, ``s = sin angle``, ``v = 1 - c``::

        R = c I + s [k]x + v k k^T

          [ kx² v + c        kx ky v - kz s   kx kz v + ky s ]
        = [ kx ky v + kz s   ky² v + c        ky kz v - kx s ]
          [ kx kz v - ky s   ky kz v + kx s   kz² v + c      ]
    """
    be = _backend(axis, angle)
    kx, ky, kz = _unit(be, _as_vector(be, axis, 3, "axis"), "axis")
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    v = 1 - c
    return be.matrix(
        [
            [kx * kx * v + c, kx * ky * v - kz * s, kx * kz * v + ky * s],
            [kx * ky * v + kz * s, ky * ky * v + c, ky * kz * v - kx * s],
            [kx * kz * v - ky * s, ky * kz * v + kx * s, kz * kz * v + c],
        ]
    )


def axis_angle_from_rotation(R: MatrixLike) -> AxisAngle:
    """Axis and angle of a rotation matrix (inverse of :func:`rotation_from_axis_angle`).

    Regular case::

        angle = acos((tr R - 1) / 2)                                in [0, pi]
        axis  = (r32 - r23, r13 - r31, r21 - r12) / (2 sin angle)

    Numerically the angle is evaluated as ``atan2(|w| / 2, (tr R - 1) / 2)`` with
    ``w = (r32 - r23, r13 - r31, r21 - r12)``, ``|w| = 2 sin angle``: the same value as the
    clipped ``acos`` for a rotation matrix, but ``acos`` loses half the digits near 0 and pi.

    Special cases (never NaN):

    * ``angle = 0`` (numerically ``< SINGULAR_TOL``): ``R = I``, any axis works; returns axis
      ``(0, 0, 1)``, angle 0, ``singular=True``.
    * ``angle`` near ``pi``: ``w`` vanishes, so the axis comes from the symmetric part,
      ``(R + R^T)/2 = c I + (1 - c) k k^T``; at ``angle = pi`` this is the diagonal of
      ``(R + I)/2 = k k^T``.  The largest ``|k_i| = sqrt((r_ii - c)/(1 - c))`` is taken
      positive, the others follow with their signs from ``k_i k_j = (r_ij + r_ji)/(2(1 - c))``,
      and the overall sign from ``w`` (which is ``2 sin(angle) k``) when it is not zero.
      NumPy uses this branch whenever ``cos angle < 0`` (better conditioned than dividing by a
      small ``sin``); ``singular=True`` only within ``SINGULAR_TOL`` of ``pi``.

    SymPy input uses the ``acos`` formula; the special cases apply when decidable, otherwise
    ``singular=None``.
    """
    be, M = _rotation_input(R)
    w = [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]
    c = (M[0, 0] + M[1, 1] + M[2, 2] - 1) / 2
    if be.symbolic:
        angle = sp.acos(c)
        at_zero, at_pi = be.is_zero(c - 1), be.is_zero(c + 1)
        near_pi = at_pi
    else:
        w_norm = math.sqrt(sum(x * x for x in w))
        angle = math.atan2(w_norm / 2, c)
        at_zero, at_pi = angle < SINGULAR_TOL, math.pi - angle < SINGULAR_TOL
        near_pi = c < 0
    if at_zero:
        return AxisAngle(be.vector([0, 0, 1]), be.scalar(0), True)
    if near_pi:
        axis = _axis_from_symmetric_part(be, M, c, w)
        return AxisAngle(be.vector(axis), sp.pi if be.symbolic else angle, _singular_flag(at_pi))
    if be.symbolic:
        two_sin = 2 * sp.sin(angle)  # SymPy writes sin(acos(c)) as sqrt(1 - c²)
        axis = [x / two_sin for x in w]
    else:
        axis = [x / w_norm for x in w]  # w_norm = 2 sin angle; normalising keeps |axis| = 1
    return AxisAngle(be.vector(axis), angle, _singular_flag(at_zero, at_pi))


def _axis_from_symmetric_part(
    be: _Backend, M: Matrix, c: Scalar, w: Sequence[Scalar]
) -> list[Scalar]:
    """Unit axis from ``(R + R^T)/2 = c I + (1 - c) k k^T`` (well conditioned near pi)."""
    one_minus_c = 1 - c
    i = be.argmax([M[0, 0], M[1, 1], M[2, 2]])  # largest r_ii <=> largest k_i²
    assert i is not None  # symbolic callers only get here for constant (decided) matrices
    k = [be.scalar(0)] * 3
    k[i] = be.sqrt((M[i, i] - c) / one_minus_c)
    for j in range(3):
        if j != i:
            k[j] = (M[i, j] + M[j, i]) / (2 * one_minus_c * k[i])
    # w = 2 sin(angle) k with sin >= 0, so w fixes the sign; at exactly pi w = 0 and either
    # sign is a valid answer (the largest component stays positive).
    if be.is_negative(sum(a * b for a, b in zip(k, w, strict=True))):
        k = [-x for x in k]
    if not be.symbolic:
        n = math.sqrt(sum(x * x for x in k))  # exact for a rotation; absorbs rounding
        k = [x / n for x in k]
    return k


# --------------------------------------------------------------------------------------------
# Unit quaternions (w, x, y, z), scalar first
# --------------------------------------------------------------------------------------------


def rotation_from_quaternion(q: MatrixLike) -> Matrix:
    """Rotation matrix of the quaternion ``q = (w, x, y, z)`` (scalar first).

    ``q`` is normalised first (a zero quaternion raises :class:`SymkinError`)::

        [ 1 - 2(y² + z²)   2(xy - wz)       2(xz + wy)     ]
        [ 2(xy + wz)       1 - 2(x² + z²)   2(yz - wx)     ]
        [ 2(xz - wy)       2(yz + wx)       1 - 2(x² + y²) ]

    ``q`` and ``-q`` give the same matrix.
    """
    be = _backend(q)
    w, x, y, z = _unit(be, _as_vector(be, q, 4, "q"), "q")
    return be.matrix(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_from_rotation(R: MatrixLike) -> Matrix:
    """Unit quaternion ``(w, x, y, z)`` of a rotation matrix, with ``w >= 0``.

    Shepperd's method: of ``4w² = 1 + tr R`` and ``4x² = 1 + r11 - r22 - r33`` (and cyclic), take
    the largest, so the square root and the division below are well conditioned::

        w = sqrt(1 + tr R)/2:  x = (r32 - r23)/4w,  y = (r13 - r31)/4w,  z = (r21 - r12)/4w
        x = sqrt(1 + r11 - r22 - r33)/2:
              w = (r32 - r23)/4x,  y = (r12 + r21)/4x,  z = (r13 + r31)/4x   (y, z cyclic)

    then flip the sign so that ``w >= 0`` (at ``w = 0``, a rotation by pi, ``q`` and ``-q`` are
    both valid; the sign is the one the chosen branch yields).  Returns NumPy shape ``(4,)`` or
    SymPy 4x1.  SymPy input with free symbols uses the ``w`` branch (the choice is not decidable
    there).
    """
    be, M = _rotation_input(R)
    trace = M[0, 0] + M[1, 1] + M[2, 2]
    # Candidate index 0 is the w branch, 1 + a the branch for vector component a.
    best = be.argmax([trace, M[0, 0], M[1, 1], M[2, 2]])
    if not best:  # 0, or None (undecidable symbolic: use the w branch)
        w = be.sqrt(1 + trace) / 2
        vec = [
            (M[2, 1] - M[1, 2]) / (4 * w),
            (M[0, 2] - M[2, 0]) / (4 * w),
            (M[1, 0] - M[0, 1]) / (4 * w),
        ]
    else:
        i = best - 1
        j, k = (i + 1) % 3, (i + 2) % 3
        vec = [be.scalar(0)] * 3
        vec[i] = be.sqrt(1 + M[i, i] - M[j, j] - M[k, k]) / 2
        w = (M[k, j] - M[j, k]) / (4 * vec[i])
        vec[j] = (M[i, j] + M[j, i]) / (4 * vec[i])
        vec[k] = (M[i, k] + M[k, i]) / (4 * vec[i])
    q = [w, *vec]
    if be.is_negative(w):
        q = [-x for x in q]
    if not be.symbolic:
        n = math.sqrt(sum(x * x for x in q))  # 1 up to rounding for a rotation matrix
        q = [x / n for x in q]
    return be.vector(q)


# --------------------------------------------------------------------------------------------
# Homogeneous transforms
# --------------------------------------------------------------------------------------------


def transform_from_rotation_translation(R: MatrixLike, p: MatrixLike) -> Matrix:
    """The 4x4 homogeneous transform ``[[R, p], [0 0 0 1]]``.

    ``R`` is a 3x3 rotation and ``p`` a 3-vector (the origin of the child frame expressed in the
    parent frame), so ``T @ [x; 1] = [R x + p; 1]``.
    """
    be = _backend(R, p)
    Rm = _as_matrix(be, R, (3, 3), "R")
    pv = _as_vector(be, p, 3, "p")
    rows = [[Rm[i, 0], Rm[i, 1], Rm[i, 2], pv[i]] for i in range(3)]
    return be.matrix([*rows, [0, 0, 0, 1]])


def transform_inverse(T: MatrixLike) -> Matrix:
    """Inverse of a rigid transform in closed form.

    ``[[R, p], [0, 1]]^-1 = [[R^T, -R^T p], [0, 1]]``.

    Never a general matrix inverse: exact for SymPy (no ``1/det``) and cheaper for NumPy.
    Numeric ``T`` must be rigid (rotation block, bottom row ``0 0 0 1``).
    """
    be, M = _transform_input(T)
    Rt = M[:3, :3].T
    p = [M[i, 3] for i in range(3)]
    minus_rt_p = [-sum(Rt[i, j] * p[j] for j in range(3)) for i in range(3)]
    return transform_from_rotation_translation(Rt, be.vector(minus_rt_p))


def transform_point(T: MatrixLike, p: MatrixLike) -> Matrix:
    """Apply a homogeneous transform to a 3-vector point: ``R p + t``.

    Returns NumPy shape ``(3,)`` or a SymPy 3x1 matrix.
    """
    be = _backend(T, p)
    M = _as_matrix(be, T, (4, 4), "T")
    pv = _as_vector(be, p, 3, "p")
    return be.vector([sum(M[i, j] * pv[j] for j in range(3)) + M[i, 3] for i in range(3)])


def _transform_input(T: MatrixLike, name: str = "T") -> tuple[_Backend, Matrix]:
    """Backend and 4x4 matrix; numeric input must be a rigid transform."""
    be = _backend(T)
    M = _as_matrix(be, T, (4, 4), name)
    if not be.symbolic:
        _check_rotation(M[:3, :3], f"the rotation block of {name}")
        if not np.all(np.isfinite(M)) or np.max(np.abs(M[3] - [0, 0, 0, 1])) > ORTHONORMAL_TOL:
            raise SymkinError(f"{name} must have the bottom row [0, 0, 0, 1], got {M.tolist()}")
    return be, M


# --------------------------------------------------------------------------------------------
# Transform graph
# --------------------------------------------------------------------------------------------


class TransformGraph:
    """Frames as nodes, known transforms as directed edges.

    ``add(parent, child, T_parent_child)`` records the pose of ``child`` in ``parent``.
    ``transform(frm, to)`` returns ``T_frm_to``, the pose of ``to`` in ``frm``: the product of
    the edge transforms along a shortest path (breadth-first search, neighbours visited in the
    order edges were added, so the result is deterministic).  An edge traversed against its
    direction contributes its closed-form :func:`transform_inverse`.

    All state lives in the instance; stored NumPy matrices are read-only copies, so later
    changes to the caller's array do not leak in.  If the path contains a SymPy edge the result
    is SymPy (NumPy edges are converted), otherwise NumPy.
    """

    def __init__(self) -> None:
        # (parent, child) -> T_parent_child
        self._edges: dict[tuple[Hashable, Hashable], Matrix] = {}
        # frame -> neighbours in insertion order (both directions), for deterministic BFS
        self._neighbours: dict[Hashable, list[Hashable]] = {}

    @property
    def frames(self) -> tuple[Hashable, ...]:
        """The known frames, in the order they were first added."""
        return tuple(self._neighbours)

    def __contains__(self, frame: object) -> bool:
        return frame in self._neighbours

    def add(self, parent: Hashable, child: Hashable, T_parent_child: MatrixLike) -> None:
        """Record ``T_parent_child``, the pose of frame ``child`` in frame ``parent``.

        Raises :class:`SymkinError` if ``parent == child``, if the two frames are already
        connected by an edge (either direction; replacing silently would hide a conflict), or if
        ``T_parent_child`` is not a (numerically rigid) 4x4 transform.
        """
        if parent == child:
            raise SymkinError(f"a transform needs two different frames, got {parent!r} twice")
        if (parent, child) in self._edges or (child, parent) in self._edges:
            raise SymkinError(f"frames {parent!r} and {child!r} are already connected")
        _, M = _transform_input(T_parent_child, f"T_{parent}_{child}")
        if isinstance(M, np.ndarray):
            M = M.copy()
            M.setflags(write=False)
        self._edges[(parent, child)] = M
        self._neighbours.setdefault(parent, []).append(child)
        self._neighbours.setdefault(child, []).append(parent)

    def transform(self, frm: Hashable, to: Hashable) -> Matrix:
        """``T_frm_to``: the pose of frame ``to`` expressed in frame ``frm``.

        Raises :class:`SymkinError` naming the frames if one is unknown or no chain of
        transforms connects them.  ``transform(a, a)`` is the 4x4 identity (SymPy if the graph
        holds any SymPy edge, else NumPy).
        """
        for frame in (frm, to):
            if frame not in self._neighbours:
                known = ", ".join(repr(f) for f in self._neighbours) or "none"
                raise SymkinError(f"unknown frame {frame!r} (known frames: {known})")
        path = self._path(frm, to)
        if path is None:
            raise SymkinError(f"no chain of transforms connects frame {frm!r} to frame {to!r}")
        factors = []
        for a, b in itertools.pairwise(path):
            if (a, b) in self._edges:
                factors.append(self._edges[(a, b)])
            else:  # the edge is stored as b -> a: walk it backwards
                factors.append(transform_inverse(self._edges[(b, a)]))
        symbolic = any(_is_symbolic(f) for f in factors) or (
            not factors and any(_is_symbolic(f) for f in self._edges.values())
        )
        if symbolic:
            result = sp.ImmutableMatrix(sp.eye(4))
            for f in factors:
                result = result @ sp.ImmutableMatrix(f)
            return sp.ImmutableMatrix(result)
        result = np.eye(4)
        for f in factors:
            result = result @ f
        return result

    def _path(self, frm: Hashable, to: Hashable) -> list[Hashable] | None:
        """Frames on a shortest path from ``frm`` to ``to`` (inclusive), or None."""
        previous: dict[Hashable, Hashable] = {frm: frm}
        queue = deque([frm])
        while queue:
            node = queue.popleft()
            if node == to:
                path = [node]
                while node != frm:
                    node = previous[node]
                    path.append(node)
                return path[::-1]
            for nxt in self._neighbours[node]:
                if nxt not in previous:
                    previous[nxt] = node
                    queue.append(nxt)
        return None
