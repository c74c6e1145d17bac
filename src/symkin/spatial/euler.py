"""Euler angles: Z-Y-X (= roll-pitch-yaw about fixed X, Y, Z) and Z-Y-Z, both directions.

``R = Rz(psi) Ry(theta) Rx(phi)`` (moving axes z, y', x'') is the same matrix as roll ``phi``,
pitch ``theta``, yaw ``psi`` about fixed axes X, Y, Z; Z-Y-Z is ``R = Rz(alpha) Ry(beta)
Rz(gamma)``.  The inverse maps return the angles with a ``singular`` flag (gimbal lock).
"""

from __future__ import annotations

from typing import NamedTuple

from symkin.errors import SymkinError
from symkin.spatial.backend import (
    Matrix,
    MatrixLike,
    Scalar,
    backend_of,
    rotation_input,
    singular_flag,
)

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
    be = backend_of(psi, theta, phi)
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
    be, M = rotation_input(R)
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
    return psi, theta, phi, singular_flag(locked)


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
    be = backend_of(alpha, beta, gamma)
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
    be, M = rotation_input(R)
    sin_beta = be.sqrt(M[0, 2] ** 2 + M[1, 2] ** 2)
    beta = be.atan2(sin_beta, M[2, 2])
    at_pole = be.is_zero(sin_beta)
    if at_pole:
        return EulerZYZ(be.atan2(-M[0, 1], M[1, 1]), beta, be.scalar(0), True)
    alpha = be.atan2(M[1, 2], M[0, 2])
    gamma = be.atan2(M[2, 1], -M[2, 0])
    return EulerZYZ(alpha, beta, gamma, singular_flag(at_pole))
