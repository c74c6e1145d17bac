"""Exponential and logarithm maps of SO(3) and SE(3).

Conventions (see ``docs/conventions.md``):

* A **rotation vector** ``w = angle * axis`` (unit axis, right-hand rule) is the exponential
  coordinate of ``R = exp([w]x)``.  The logarithm returns ``|w| = angle`` in ``[0, pi]``; at
  ``angle = pi`` both ``w`` and ``-w`` are logarithms and the result is flagged ``singular``.
* A **twist** (exponential coordinates of a transform) is ordered **``(v, w)``, linear part
  first**, like the geometric Jacobian ``[v; w]`` (Murray, Li & Sastry; spatialmath).  Lynch &
  Park and pytransform3d order it ``(w, v)``.  ``T = exp([twist])`` with
  ``[twist] = [[ [w]x, v ], [0, 0]]``.
* ``[w]x`` is the cross-product matrix: ``[w]x u = w x u``.

Near ``angle = 0`` the coefficients ``sin t / t`` and the like are evaluated by their Taylor
series (NumPy), so small and zero rotations are exact, never NaN.
"""

from __future__ import annotations

import math
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
    transform_input,
)
from symkin.spatial.rotations import axis_angle_from_rotation

#: Below this angle (NumPy) the coefficients use their Taylor series; the first omitted term
#: is below ``angle**8 / 40320``, under 1e-20 here.
SERIES_ANGLE = 1e-2


class RotationLog(NamedTuple):
    """``vector`` = rotation vector ``angle * axis``; ``angle`` in ``[0, pi]``.

    ``singular`` is True at ``angle = pi``, where ``-vector`` is an equally valid logarithm
    (numerically within ``SINGULAR_TOL`` of pi); None when SymPy cannot decide.
    """

    vector: Matrix
    angle: Scalar
    singular: bool | None


class TransformLog(NamedTuple):
    """``twist`` = exponential coordinates ``(v, w)`` of a transform; ``angle = |w|``.

    ``singular`` as in :class:`RotationLog` (the rotation by pi has two logarithms).
    """

    twist: Matrix
    angle: Scalar
    singular: bool | None


def skew(w: MatrixLike) -> Matrix:
    """The cross-product matrix ``[w]x = [[0, -wz, wy], [wz, 0, -wx], [-wy, wx, 0]]``."""
    be = backend_of(w)
    x, y, z = as_vector(be, w, 3, "w")
    return be.matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def _coefficients(be: Backend, angle: Scalar) -> tuple[Scalar, Scalar, Scalar, Scalar]:
    """``sin t/t, (1 - cos t)/t², (t - sin t)/t³, (1 - t sin t/(2(1 - cos t)))/t²`` at ``t``.

    NumPy below ``SERIES_ANGLE`` and SymPy at a decidably zero angle use the Taylor series.
    """
    t = angle
    if be.symbolic and not be.is_zero(t):
        s, c = sp.sin(t), sp.cos(t)
        return s / t, (1 - c) / t**2, (t - s) / t**3, (1 - t * s / (2 * (1 - c))) / t**2
    if not be.symbolic and t >= SERIES_ANGLE:
        s, c = math.sin(t), math.cos(t)
        half = 2 * math.sin(t / 2) ** 2  # 1 - cos t without cancellation
        return s / t, half / t**2, (t - s) / t**3, (1 - t * s / (2 * half)) / t**2
    t2 = be.scalar(t) ** 2 if not be.symbolic else sp.Integer(0)
    return (
        1 - t2 / 6 * (1 - t2 / 20 * (1 - t2 / 42)),
        (1 - t2 / 12 * (1 - t2 / 30 * (1 - t2 / 56))) / 2,
        (1 - t2 / 20 * (1 - t2 / 42 * (1 - t2 / 72))) / 6,
        (1 + t2 / 60 * (1 + t2 / 42 * (1 + t2 / 40))) / 12,
    )


def _so3_exp(be: Backend, w: list[Scalar]) -> tuple[Matrix, Scalar, Scalar]:
    """``R = I + a [w]x + b [w]x²`` and the coefficients ``b``, ``c`` needed by SE(3)."""
    angle = be.sqrt(sum(x * x for x in w))
    a, b, c, _ = _coefficients(be, angle)
    K = skew(be.vector(w))
    K2 = K @ K
    R = [[int(i == j) + a * K[i, j] + b * K2[i, j] for j in range(3)] for i in range(3)]
    return be.matrix(R), b, c


def rotation_from_rotation_vector(w: MatrixLike) -> Matrix:
    """``R = exp([w]x)``, the rotation by ``|w|`` about ``w / |w|`` (Rodrigues)::

        R = I + (sin t / t) [w]x + ((1 - cos t) / t²) [w]x²,    t = |w|

    ``w = 0`` gives ``I`` (series near 0, no division by zero).
    """
    be = backend_of(w)
    return _so3_exp(be, as_vector(be, w, 3, "w"))[0]


def rotation_vector_from_rotation(R: MatrixLike) -> RotationLog:
    """The logarithm of SO(3): ``w`` with ``exp([w]x) = R`` and ``|w|`` in ``[0, pi]``.

    NumPy, for ``angle <= pi/2``: ``w = (t / sin t) * vee(R - R^T) / 2`` with
    ``vee(R - R^T) = (r32 - r23, r13 - r31, r21 - r12)`` and
    ``t = atan2(|vee| / 2, (tr R - 1) / 2)``; ``t / sin t`` by series near 0, so a tiny rotation
    keeps all its digits.  Beyond ``pi/2`` (and for SymPy) it is ``angle * axis`` from
    :func:`~symkin.spatial.axis_angle_from_rotation` (axis from the symmetric part near pi).
    At ``angle = pi`` the sign is that of the axis there (largest component positive) and
    ``singular=True``.
    """
    be, M = rotation_input(R)
    c = (M[0, 0] + M[1, 1] + M[2, 2] - 1) / 2
    if not be.symbolic and c >= 0:
        half_vee = [(M[2, 1] - M[1, 2]) / 2, (M[0, 2] - M[2, 0]) / 2, (M[1, 0] - M[0, 1]) / 2]
        angle = math.atan2(math.sqrt(sum(x * x for x in half_vee)), c)
        sinc = _coefficients(be, angle)[0]
        return RotationLog(be.vector([x / sinc for x in half_vee]), angle, False)
    axis, angle, _ = axis_angle_from_rotation(M)
    at_pi = be.is_zero(c + 1) if be.symbolic else math.pi - angle < SINGULAR_TOL
    vector = be.vector([angle * k for k in axis])
    return RotationLog(vector, angle, singular_flag(at_pi))


def transform_from_twist(twist: MatrixLike) -> Matrix:
    """``T = exp([twist])`` for exponential coordinates ``twist = (v, w)`` (linear first)::

        R = exp([w]x),   p = (I + ((1 - cos t)/t²) [w]x + ((t - sin t)/t³) [w]x²) v,   t = |w|

    A pure translation ``w = 0`` gives ``T = [I, v; 0, 1]``.  For a unit screw axis ``S`` and
    a joint value ``q``, ``transform_from_twist(q * S)`` is the joint's motion.
    """
    be = backend_of(twist)
    items = as_vector(be, twist, 6, "twist")
    v, w = items[:3], items[3:]
    R, b, c = _so3_exp(be, w)
    K = skew(be.vector(w))
    K2 = K @ K
    p = [v[i] + sum((b * K[i, j] + c * K2[i, j]) * v[j] for j in range(3)) for i in range(3)]
    rows = [[R[i, 0], R[i, 1], R[i, 2], p[i]] for i in range(3)]
    return be.matrix([*rows, [0, 0, 0, 1]])


def twist_from_transform(T: MatrixLike) -> TransformLog:
    """The logarithm of SE(3): ``(v, w)`` with ``exp([(v, w)]) = T`` and ``|w|`` in ``[0, pi]``.

    ``w`` is :func:`rotation_vector_from_rotation` of the rotation block, and
    ``v = (I - [w]x / 2 + d [w]x²) p`` with ``d = (1 - t sin t / (2 (1 - cos t))) / t²``
    (``1/12`` at ``t = 0``, series nearby; ``1/pi²`` at ``t = pi``).  A pure translation gives
    ``(p, 0)``.  ``singular`` is that of the rotation (``t = pi``: ``-w`` and its ``v`` are an
    equally valid logarithm).
    """
    be, M = transform_input(T)
    w, angle, singular = rotation_vector_from_rotation(M[:3, :3])
    d = _coefficients(be, angle)[3]
    K = skew(w)
    K2 = K @ K
    p = [M[i, 3] for i in range(3)]
    v = [p[i] + sum((-K[i, j] / 2 + d * K2[i, j]) * p[j] for j in range(3)) for i in range(3)]
    return TransformLog(be.vector([*v, *w]), angle, singular)
