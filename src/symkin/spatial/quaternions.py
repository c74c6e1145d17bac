"""Unit quaternions ``q = (w, x, y, z)``, scalar first (Hamilton product, ``i j = k``).

A unit quaternion and its negative are the same rotation (the double cover).  symkin's one
convention: conversions from a rotation return the **canonical** sign ``w >= 0``
(:func:`quaternion_canonical`); products, inverses and interpolations keep the sign their
formula gives (``-q`` is as valid as ``q``); :func:`quaternion_slerp` takes the **short way**
(it flips the end quaternion when ``q0 . q1 < 0``).  ``rotation_from_quaternion(q1 * q2)`` is
``R(q1) R(q2)``.
"""

from __future__ import annotations

import math

import sympy as sp

from symkin.spatial.backend import (
    SINGULAR_TOL,
    Matrix,
    MatrixLike,
    Scalar,
    as_vector,
    backend_of,
    rotation_input,
    unit,
)

# --------------------------------------------------------------------------------------------
# Quaternion algebra
# --------------------------------------------------------------------------------------------


def quaternion_product(p: MatrixLike, q: MatrixLike) -> Matrix:
    """Hamilton product ``p q`` of ``p = (pw, pv)`` and ``q = (qw, qv)`` (not normalised)::

        p q = (pw qw - pv . qv,  pw qv + qw pv + pv x qv)

    For unit quaternions ``R(p q) = R(p) R(q)``: rotate by ``q`` first, then by ``p``.
    """
    be = backend_of(p, q)
    pw, px, py, pz = as_vector(be, p, 4, "p")
    qw, qx, qy, qz = as_vector(be, q, 4, "q")
    return be.vector(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ]
    )


def quaternion_conjugate(q: MatrixLike) -> Matrix:
    """``q* = (w, -x, -y, -z)``; for a unit quaternion the inverse rotation."""
    be = backend_of(q)
    w, x, y, z = as_vector(be, q, 4, "q")
    return be.vector([w, -x, -y, -z])


def quaternion_inverse(q: MatrixLike) -> Matrix:
    """``q^-1 = q* / |q|²``, so ``q q^-1 = (1, 0, 0, 0)``; a zero ``q`` raises SymkinError."""
    be = backend_of(q)
    items = as_vector(be, q, 4, "q")
    w, x, y, z = unit(be, items, "q")  # q / |q|; raises for a zero quaternion
    n = be.sqrt(sum(v * v for v in items))
    if be.symbolic:
        n = sp.simplify(n)
    return be.vector([w / n, -x / n, -y / n, -z / n])  # q* / |q|²


def unit_quaternion(q: MatrixLike) -> Matrix:
    """``q / |q|`` (sign kept); a zero ``q`` raises SymkinError."""
    be = backend_of(q)
    return be.vector(unit(be, as_vector(be, q, 4, "q"), "q"))


def quaternion_canonical(q: MatrixLike) -> Matrix:
    """``q / |q|`` with the canonical sign ``w >= 0`` (``-q`` when ``w < 0``).

    At ``w = 0`` (a rotation by pi) both signs are the same rotation and ``q`` is returned as
    given.  SymPy values whose sign is undecidable are returned unflipped.
    """
    be = backend_of(q)
    items = unit(be, as_vector(be, q, 4, "q"), "q")
    if be.is_negative(items[0]):
        items = [-v for v in items]
    return be.vector(items)


def quaternion_slerp(q0: MatrixLike, q1: MatrixLike, t: Scalar) -> Matrix:
    """Spherical linear interpolation from ``q0`` (``t = 0``) to ``q1`` (``t = 1``), short way.

    Both ends are normalised; if ``q0 . q1 < 0``, ``q1`` is replaced by ``-q1`` (the same
    rotation), so the path turns by the rotation angle between the two (at most pi) about a
    fixed axis at constant angular speed.  With ``Omega`` the angle between ``q0`` and ``q1``
    on the unit sphere (half the rotation angle)::

        slerp = (sin((1 - t) Omega) q0 + sin(t Omega) q1) / sin Omega

    Numerically ``Omega = 2 atan2(|q1 - q0|, |q1 + q0|)`` (accurate near 0, unlike ``acos``);
    below ``SINGULAR_TOL`` the normalised linear blend is used (the two differ by
    ``O(Omega³)``).  ``q0 . q1 = 0`` means rotations pi apart: both ways are equally short and
    ``q1`` is used as given.  SymPy: ``Omega = acos(q0 . q1)``; the flip happens only when the
    sign of ``q0 . q1`` is decidable.
    """
    be = backend_of(q0, q1, t)
    a = unit(be, as_vector(be, q0, 4, "q0"), "q0")
    b = unit(be, as_vector(be, q1, 4, "q1"), "q1")
    s = be.scalar(t, "t")
    if be.is_negative(sum(x * y for x, y in zip(a, b, strict=True))):
        b = [-v for v in b]
    if be.symbolic:
        omega = sp.acos(sum(x * y for x, y in zip(a, b, strict=True)))
        if be.is_zero(omega):
            return be.vector(a)
    else:
        diff = math.sqrt(sum((y - x) ** 2 for x, y in zip(a, b, strict=True)))
        add = math.sqrt(sum((y + x) ** 2 for x, y in zip(a, b, strict=True)))
        omega = 2 * math.atan2(diff, add)
        if omega < SINGULAR_TOL:
            blend = [(1 - s) * x + s * y for x, y in zip(a, b, strict=True)]
            return be.vector(unit(be, blend, "q"))
    c0, c1, d = be.sin((1 - s) * omega), be.sin(s * omega), be.sin(omega)
    return be.vector([(c0 * x + c1 * y) / d for x, y in zip(a, b, strict=True)])


# --------------------------------------------------------------------------------------------
# Rotation matrices
# --------------------------------------------------------------------------------------------


def rotation_from_quaternion(q: MatrixLike) -> Matrix:
    """Rotation matrix of the quaternion ``q = (w, x, y, z)`` (scalar first).

    ``q`` is normalised first (a zero quaternion raises :class:`SymkinError`)::

        [ 1 - 2(y² + z²)   2(xy - wz)       2(xz + wy)     ]
        [ 2(xy + wz)       1 - 2(x² + z²)   2(yz - wx)     ]
        [ 2(xz - wy)       2(yz + wx)       1 - 2(x² + y²) ]

    ``q`` and ``-q`` give the same matrix.
    """
    be = backend_of(q)
    w, x, y, z = unit(be, as_vector(be, q, 4, "q"), "q")
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
    be, M = rotation_input(R)
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
