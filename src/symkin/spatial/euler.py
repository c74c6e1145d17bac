"""Euler and Tait-Bryan angles in all twelve orders, both directions, symbolic and numeric.

An order is three axis letters, e.g. ``"zyx"``.  **Intrinsic** (the default, moving axes):
``R = R_a(θ1) R_b(θ2) R_c(θ3)`` for order ``"abc"`` — rotate about a, then about the new b',
then about the new c''.  **Extrinsic** (fixed axes) order ``"abc"`` rotates about the fixed a
first, then the fixed b, then the fixed c: ``R = R_c(θ3) R_b(θ2) R_a(θ1)``, which is the
intrinsic order reversed (``"cba"``) with the angles reversed.  Orders with three different
axes are Tait-Bryan (``xyz xzy yxz yzx zxy zyx``), those whose first and last axes agree are
proper Euler (``xyx xzx yxy yzy zxz zyz``).

Z-Y-X (``R = Rz(psi) Ry(theta) Rx(phi)``) is the same matrix as roll ``phi``, pitch ``theta``,
yaw ``psi`` about the fixed axes X, Y, Z (extrinsic ``"xyz"``); Z-Y-Z is
``R = Rz(alpha) Ry(beta) Rz(gamma)``.  The inverse maps return the angles with a ``singular``
flag (gimbal lock); the choice made there is documented on :func:`euler_from_rotation`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from symkin.errors import SymkinError
from symkin.spatial.backend import (
    Backend,
    Matrix,
    MatrixLike,
    Scalar,
    backend_of,
    rotation_input,
    singular_flag,
)
from symkin.spatial.rotations import rot_x, rot_y, rot_z

TAIT_BRYAN_ORDERS = ("xyz", "xzy", "yxz", "yzx", "zxy", "zyx")
PROPER_EULER_ORDERS = ("xyx", "xzx", "yxy", "yzy", "zxz", "zyz")
#: The twelve orders, Tait-Bryan first.
EULER_ORDERS = TAIT_BRYAN_ORDERS + PROPER_EULER_ORDERS

_AXIS = {"x": 0, "y": 1, "z": 2}
_ELEMENTARY = (rot_x, rot_y, rot_z)


class EulerAngles(NamedTuple):
    """Angles ``(θ1, θ2, θ3)`` of ``order`` (applied in that order; see the module docstring).

    ``singular`` is True at gimbal lock (the middle angle at ``±pi/2`` for Tait-Bryan, at ``0``
    or ``pi`` for proper Euler), False otherwise, None for SymPy input where it cannot be
    decided.
    """

    angles: tuple[Scalar, Scalar, Scalar]
    order: str
    extrinsic: bool
    singular: bool | None


def _axes(order: str) -> tuple[int, int, int]:
    """Axis indices of an order, checked."""
    if not isinstance(order, str) or order.lower() not in EULER_ORDERS:
        raise SymkinError(f"Euler order must be one of {', '.join(EULER_ORDERS)}, got {order!r}")
    i, j, k = (_AXIS[letter] for letter in order.lower())
    return i, j, k


def _parity(i: int, j: int) -> int:
    """+1 if ``(i, j, third axis)`` is a cyclic permutation of ``(x, y, z)``, else -1.

    ``e_i x e_j = parity * e_k``; it fixes the signs of the inverse formulas below.
    """
    return 1 if (j - i) % 3 == 1 else -1


def rotation_from_euler(order: str, angles: Sequence[Scalar], extrinsic: bool = False) -> Matrix:
    """Rotation matrix of three angles in ``order`` (intrinsic unless ``extrinsic``).

    Intrinsic ``"abc"``: ``R = R_a(θ1) R_b(θ2) R_c(θ3)``; extrinsic ``"abc"``:
    ``R = R_c(θ3) R_b(θ2) R_a(θ1)``.  SymPy angles give the exact product (SymPy's canonical
    form, the textbook entries); numbers give a float64 array.
    """
    axes = _axes(order)
    if len(angles) != 3:
        raise SymkinError(f"Euler angles are three values, got {len(angles)}")
    be = backend_of(*angles)
    # One backend for all three: a literal 0 beside a SymPy angle must stay exact.
    angles = [be.scalar(angle, "Euler angle") for angle in angles]
    factors = [_ELEMENTARY[axis](angle) for axis, angle in zip(axes, angles, strict=True)]
    if extrinsic:
        factors.reverse()
    first, second, third = factors
    return first @ second @ third


def euler_from_rotation(R: MatrixLike, order: str, extrinsic: bool = False) -> EulerAngles:
    """The angles of ``order`` with ``rotation_from_euler(order, angles, extrinsic) == R``.

    Intrinsic order ``(i, j, k)``, ``ε = +1`` when ``i j`` is cyclic (``xy, yz, zx``), else -1.
    Tait-Bryan (``k ≠ i``), middle angle in ``[-pi/2, pi/2]``::

        θ1 = atan2(-ε r_jk, r_kk)
        θ2 = atan2(ε r_ik, sqrt(r_jk² + r_kk²))
        θ3 = atan2(-ε r_ij, r_ii)

    Proper Euler (``k = i``; ``m`` the third axis), middle angle in ``[0, pi]``::

        θ1 = atan2(r_ji, -ε r_mi)
        θ2 = atan2(sqrt(r_ji² + r_mi²), r_ii)
        θ3 = atan2(r_ij, ε r_im)

    Gimbal lock (the ``sqrt`` term below ``SINGULAR_TOL``): only the sum or the difference of
    the outer angles is defined.  The documented choice: the last angle applied (intrinsic
    ``θ3``; for an extrinsic order its first angle, the one applied first about the fixed
    axes) is 0, and the first one comes from column ``j`` (``R e_j = R_i(θ1) e_j`` there):
    ``θ1 = atan2(ε r_mj, r_jj)``; ``singular=True``.  For Z-Y-X and Z-Y-Z these are exactly
    the formulas of :func:`euler_zyx_from_rotation` and :func:`euler_zyz_from_rotation`.
    SymPy input returns the regular formulas with ``singular=None`` unless the ``sqrt`` term
    is decidably zero (then the locked branch, exactly) or decidably non-zero.
    """
    axes = _axes(order)
    be, M = rotation_input(R)
    if extrinsic:
        axes = axes[::-1]
    first, middle, last, singular = _intrinsic_angles(be, M, axes)
    angles = (last, middle, first) if extrinsic else (first, middle, last)
    return EulerAngles(angles, order.lower(), extrinsic, singular)


def _intrinsic_angles(
    be: Backend, M: Matrix, axes: tuple[int, int, int]
) -> tuple[Scalar, Scalar, Scalar, bool | None]:
    i, j, k = axes
    eps = _parity(i, j)
    proper = k == i
    m = 3 - i - j  # the axis not in the sequence (= k for Tait-Bryan)
    if proper:
        off_axis = be.sqrt(M[j, i] ** 2 + M[m, i] ** 2)  # = |sin θ2|
        middle = be.atan2(off_axis, M[i, i])
    else:
        off_axis = be.sqrt(M[j, k] ** 2 + M[k, k] ** 2)  # = |cos θ2|
        middle = be.atan2(eps * M[i, k], off_axis)
    locked = be.is_zero(off_axis)
    if locked:
        return be.atan2(eps * M[m, j], M[j, j]), middle, be.scalar(0), True
    if proper:
        first = be.atan2(M[j, i], -eps * M[m, i])
        last = be.atan2(M[i, j], eps * M[i, m])
    else:
        first = be.atan2(-eps * M[j, k], M[k, k])
        last = be.atan2(-eps * M[i, j], M[i, i])
    return first, middle, last, singular_flag(locked)


# --------------------------------------------------------------------------------------------
# Z-Y-X Euler angles = roll-pitch-yaw about fixed X, Y, Z; Z-Y-Z: the named textbook cases
# --------------------------------------------------------------------------------------------


def rotation_from_euler_zyx(psi: Scalar, theta: Scalar, phi: Scalar) -> Matrix:
    """Z-Y-X Euler angles (moving axes z, y', x'') to a rotation matrix.

    ``R = Rz(psi) Ry(theta) Rx(phi)``::

        [ cψ cθ   cψ sθ sφ - sψ cφ   cψ sθ cφ + sψ sφ ]
        [ sψ cθ   sψ sθ sφ + cψ cφ   sψ sθ cφ - cψ sφ ]
        [ -sθ     cθ sφ              cθ cφ            ]

    The same matrix is roll ``phi`` / pitch ``theta`` / yaw ``psi`` about fixed axes X, Y, Z,
    see :func:`rotation_from_rpy`.
    """
    return rotation_from_euler("zyx", (psi, theta, phi))


def rotation_from_rpy(roll: Scalar, pitch: Scalar, yaw: Scalar) -> Matrix:
    """Roll-pitch-yaw about **fixed** axes (``rpy_xyz_fixed``) to a rotation matrix.

    Roll about X first, then pitch about Y, then yaw about Z, all about the fixed (world) axes:
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``, extrinsic ``"xyz"`` = the Z-Y-X Euler matrix with
    ``psi = yaw, theta = pitch, phi = roll`` (:func:`rotation_from_euler_zyx`).
    """
    return rotation_from_euler("xyz", (roll, pitch, yaw), extrinsic=True)


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
    These are the formulas of :func:`euler_from_rotation` for order ``"zyx"``.
    """
    if method not in _ZYX_METHODS:
        raise SymkinError(f"method must be one of {', '.join(_ZYX_METHODS)}, got {method!r}")
    (psi, theta, phi), _, _, singular = euler_from_rotation(R, "zyx")
    if method == "lecture" and not singular:
        be, M = rotation_input(R)
        theta = be.atan2(-M[2, 0], M[0, 0] * be.cos(psi) + M[1, 0] * be.sin(psi))
    return EulerZYX(psi, theta, phi, singular)


def rpy_from_rotation(R: MatrixLike, method: str = "atan2") -> RPY:
    """Roll-pitch-yaw about fixed X, Y, Z with ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    The same matrix as Z-Y-X Euler, so this is :func:`euler_zyx_from_rotation` with
    ``roll = phi, pitch = theta, yaw = psi`` (same formulas, same gimbal-lock handling:
    ``roll = 0`` at ``pitch = +-pi/2``).
    """
    psi, theta, phi, singular = euler_zyx_from_rotation(R, method)
    return RPY(roll=phi, pitch=theta, yaw=psi, singular=singular)


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

    ``R = Rz(alpha) Ry(beta) Rz(gamma)``::

        [ cα cβ cγ - sα sγ   -cα cβ sγ - sα cγ   cα sβ ]
        [ sα cβ cγ + cα sγ   -sα cβ sγ + cα cγ   sα sβ ]
        [ -sβ cγ              sβ sγ              cβ    ]
    """
    return rotation_from_euler("zyz", (alpha, beta, gamma))


def euler_zyz_from_rotation(R: MatrixLike) -> EulerZYZ:
    """Z-Y-Z Euler angles ``(alpha, beta, gamma)`` with ``R = Rz(alpha) Ry(beta) Rz(gamma)``.

    Regular case (``sin beta > 0`` branch, ``beta`` in ``(0, pi)``)::

        beta  = atan2(sqrt(r13² + r23²), r33)
        alpha = atan2(r23, r13)
        gamma = atan2(r32, -r31)

    Singular case ``sin beta = sqrt(r13² + r23²) < SINGULAR_TOL`` (``beta = 0``: only
    ``alpha + gamma`` is defined; ``beta = pi``: only ``alpha - gamma``): ``gamma = 0`` and
    ``alpha = atan2(-r12, r22)``, which is right in both cases (``r12 = -sin(alpha +- gamma)``,
    ``r22 = cos(alpha +- gamma)``); ``singular=True``.  These are the formulas of
    :func:`euler_from_rotation` for order ``"zyz"``.
    """
    (alpha, beta, gamma), _, _, singular = euler_from_rotation(R, "zyz")
    return EulerZYZ(alpha, beta, gamma, singular)
