"""Screw axes, twists and wrenches, and the adjoint map that moves them between frames.

Order (see ``docs/conventions.md``): a twist is ``(v, w)`` (linear velocity first, like the
geometric Jacobian ``[v; w]``), a wrench is ``(f, tau)`` (force first), so the power is the
plain dot product ``wrench . twist = f . v + tau . w``.  ``T_a_b`` is the pose of frame b in
frame a; a twist or wrench "in frame b" has its components in b's axes and its reference point
at b's origin.
"""

from __future__ import annotations

import math

import sympy as sp

from symkin.spatial.backend import (
    Backend,
    Matrix,
    MatrixLike,
    Scalar,
    as_vector,
    backend_of,
    transform_input,
    unit,
)
from symkin.spatial.lie import skew


def screw_axis_from_line(point: MatrixLike, direction: MatrixLike, pitch: Scalar) -> Matrix:
    """Unit screw axis ``S = (v, w)`` about the line through ``point`` along ``direction``.

    ``w = direction / |direction|`` and ``v = point x w + pitch w`` (``= -w x point + h w``):
    the twist of a body turning at unit speed about the line while advancing ``pitch`` per
    radian.  Pitch 0 is a revolute joint's axis.  ``pitch = inf`` (``math.inf`` or
    ``sympy.oo``) is a pure translation, ``S = (direction / |direction|, 0)``, and ``point``
    is ignored.  A zero direction raises SymkinError.
    """
    be = backend_of(point, direction, pitch)
    d = unit(be, as_vector(be, direction, 3, "direction"), "direction")
    if pitch == sp.oo or (not be.symbolic and math.isinf(float(pitch)) and pitch > 0):
        return be.vector([*d, 0, 0, 0])
    q = as_vector(be, point, 3, "point")
    h = be.scalar(pitch, "pitch")
    cross = [q[1] * d[2] - q[2] * d[1], q[2] * d[0] - q[0] * d[2], q[0] * d[1] - q[1] * d[0]]
    return be.vector([cross[i] + h * d[i] for i in range(3)] + d)


def twist_from_screw(screw: MatrixLike, speed: Scalar) -> Matrix:
    """The twist ``speed * S`` of motion along the screw axis ``S = (v, w)`` at ``speed``.

    ``speed`` is the joint rate (rad/s about a screw with ``|w| = 1``, m/s along a pure
    translation); with a joint value instead of a rate the result is the exponential
    coordinates for :func:`~symkin.spatial.transform_from_twist`.
    """
    be = backend_of(screw, speed)
    s = be.scalar(speed, "speed")
    return be.vector([s * x for x in as_vector(be, screw, 6, "screw")])


def adjoint_from_transform(T_a_b: MatrixLike) -> Matrix:
    """The 6x6 adjoint ``Ad_T`` of ``T_a_b = [R p; 0 1]``, twist order ``(v, w)``::

        Ad_T = [[R, [p]x R],
                [0, R     ]]

    so ``V_a = Ad_T V_b`` for a twist ``V_b`` in frame b, ``Ad_{T1 T2} = Ad_T1 Ad_T2`` and
    ``Ad_{T^-1} = Ad_T^-1``.  (pytransform3d and Lynch & Park, who order ``(w, v)``, write the
    same blocks swapped: ``[[R, 0], [[p]x R, R]]``.)
    """
    be, M = transform_input(T_a_b, "T_a_b")
    R = M[:3, :3]
    PR = skew([M[0, 3], M[1, 3], M[2, 3]]) @ R
    top = [[R[i, j] for j in range(3)] + [PR[i, j] for j in range(3)] for i in range(3)]
    bottom = [[0, 0, 0] + [R[i, j] for j in range(3)] for i in range(3)]
    return be.matrix(top + bottom)


def transform_twist(T_a_b: MatrixLike, twist_b: MatrixLike) -> Matrix:
    """The twist ``(v, w)`` given in frame b, expressed in frame a: ``Ad_{T_a_b} twist_b``.

    ``w_a = R w_b`` and ``v_a = R v_b + p x (R w_b)`` (the linear velocity moves to a's
    origin).
    """
    be = backend_of(T_a_b, twist_b)
    return _apply(adjoint_from_transform(T_a_b), as_vector(be, twist_b, 6, "twist_b"), be)


def transform_wrench(T_a_b: MatrixLike, wrench_b: MatrixLike) -> Matrix:
    """The wrench ``(f, tau)`` given in frame b, expressed in frame a: ``Ad_{T_a_b}^-T wrench_b``.

    ``f_a = R f_b`` and ``tau_a = R tau_b + p x (R f_b)`` (the moment moves to a's origin).
    The transpose-inverse of the twist map keeps the power invariant:
    ``wrench_a . twist_a = wrench_b . twist_b``.  Computed as ``Ad_{T_b_a}^T`` in closed form
    (``[[R, 0], [[p]x R, R]]``), never by a matrix inverse.
    """
    be = backend_of(T_a_b, wrench_b)
    Ad = adjoint_from_transform(T_a_b)
    # Ad^-T = [[R, 0], [[p]x R, R]]: Ad's off-diagonal block moved below the diagonal.
    rows = [[Ad[i, j] for j in range(3)] + [0, 0, 0] for i in range(3)] + [
        [Ad[i - 3, j + 3] for j in range(3)] + [Ad[i, j + 3] for j in range(3)] for i in range(3, 6)
    ]
    return _apply(be.matrix(rows), as_vector(be, wrench_b, 6, "wrench_b"), be)


def _apply(A: Matrix, x: list[Scalar], be: Backend) -> Matrix:
    """``A x`` as a backend vector."""
    return be.vector([sum(A[i, j] * x[j] for j in range(6)) for i in range(6)])
