"""Elementary rotations and axis-angle.

Rotations are active, right-handed, acting on column vectors: ``p' = R p``.  Unit quaternions
are in :mod:`symkin.spatial.quaternions`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import sympy as sp

from symkin.spatial.backend import (
    SINGULAR_TOL,
    Backend,
    Matrix,
    MatrixLike,
    Scalar,
    as_vector,
    backend_of,
    rotation_input,
    singular_flag,
    unit,
)

# --------------------------------------------------------------------------------------------
# Elementary rotations
# --------------------------------------------------------------------------------------------


def rot_x(angle: Scalar) -> Matrix:
    """Active rotation about the x axis by ``angle`` (right-handed, column vectors).

    ``Rx(a) = [[1, 0, 0], [0, cos a, -sin a], [0, sin a, cos a]]``.
    """
    be = backend_of(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(angle: Scalar) -> Matrix:
    """Active rotation about the y axis by ``angle`` (right-handed, column vectors).

    ``Ry(a) = [[cos a, 0, sin a], [0, 1, 0], [-sin a, 0, cos a]]``.
    """
    be = backend_of(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(angle: Scalar) -> Matrix:
    """Active rotation about the z axis by ``angle`` (right-handed, column vectors).

    ``Rz(a) = [[cos a, -sin a, 0], [sin a, cos a, 0], [0, 0, 1]]``.
    """
    be = backend_of(angle)
    a = be.scalar(angle, "angle")
    c, s = be.cos(a), be.sin(a)
    return be.matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


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
    be = backend_of(axis, angle)
    kx, ky, kz = unit(be, as_vector(be, axis, 3, "axis"), "axis")
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
    be, M = rotation_input(R)
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
        return AxisAngle(be.vector(axis), sp.pi if be.symbolic else angle, singular_flag(at_pi))
    if be.symbolic:
        two_sin = 2 * sp.sin(angle)  # SymPy writes sin(acos(c)) as sqrt(1 - c²)
        axis = [x / two_sin for x in w]
    else:
        axis = [x / w_norm for x in w]  # w_norm = 2 sin angle; normalising keeps |axis| = 1
    return AxisAngle(be.vector(axis), angle, singular_flag(at_zero, at_pi))


def _axis_from_symmetric_part(
    be: Backend, M: Matrix, c: Scalar, w: Sequence[Scalar]
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
