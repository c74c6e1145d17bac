"""Inertia tensors: rotation into another frame, Steiner's theorem, composite bodies and the
tensors of simple solids.

Conventions (docs/conventions.md, Inertia):

* A tensor is the 3x3 matrix ``I = integral (|r|^2 E - r r^T) dm`` (positive moments on the
  diagonal, *minus* the products of inertia off it: URDF's ``ixy`` is ``I[0, 1]``).
* ``I`` given in frame b is ``R I R^T`` in frame a, with ``R = R_a_b`` (frame b's axes in a).
* Steiner (parallel axis): about a point ``o`` with the centre of mass at ``r`` from ``o``,
  ``I_o = I_c + m (|r|^2 E - r r^T)``, and back ``I_c = I_o - m (|r|^2 E - r r^T)``.

Like the rest of :mod:`symkin.spatial`, every function is symbolic when any input is a SymPy
object (returns :class:`sympy.ImmutableMatrix`) and numeric otherwise (``numpy.ndarray``).
Textbook formulas: Gross, Hauger, Schröder, Wall, *Technische Mechanik 3*, table 3.2;
Spong, Hutchinson, Vidyasagar, *Robot Modeling and Control*, section 7.2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symkin.errors import SymkinError
from symkin.spatial.backend import (
    Backend,
    Matrix,
    MatrixLike,
    Scalar,
    as_matrix,
    as_vector,
    backend_of,
)

AXES = ("x", "y", "z")


@dataclass(frozen=True)
class RigidBody:
    """Mass, centre of mass and inertia tensor about the centre of mass, all in one frame."""

    mass: Scalar
    com: Matrix
    inertia: Matrix


def _steiner_term(be: Backend, mass: Scalar, offset: Sequence[Scalar]) -> Matrix:
    """``m (|r|^2 E - r r^T)``: the inertia of a point mass ``m`` at ``r``."""
    square = sum(r * r for r in offset)
    return be.matrix(
        [
            [mass * ((square if i == j else 0) - offset[i] * offset[j]) for j in range(3)]
            for i in range(3)
        ]
    )


def rotated_inertia(inertia: MatrixLike, rotation: MatrixLike) -> Matrix:
    """``R I R^T``: the tensor ``I`` given in frame b, expressed in frame a (``R = R_a_b``)."""
    be = backend_of(inertia, rotation)
    tensor = as_matrix(be, inertia, (3, 3), "inertia")
    rotation_ab = as_matrix(be, rotation, (3, 3), "rotation")
    return be.matrix((rotation_ab @ tensor @ rotation_ab.T).tolist())


def inertia_about_point(inertia_com: MatrixLike, mass: Scalar, offset: MatrixLike) -> Matrix:
    """Steiner: ``I_o = I_c + m (|r|^2 E - r r^T)``, ``r`` = centre of mass seen from ``o``."""
    be = backend_of(inertia_com, mass, offset)
    tensor = as_matrix(be, inertia_com, (3, 3), "inertia_com")
    return be.matrix(
        (
            tensor + _steiner_term(be, be.scalar(mass, "mass"), as_vector(be, offset, 3, "offset"))
        ).tolist()
    )


def inertia_about_com(inertia_point: MatrixLike, mass: Scalar, offset: MatrixLike) -> Matrix:
    """Steiner backwards: ``I_c = I_o - m (|r|^2 E - r r^T)``, ``r`` = centre of mass from ``o``."""
    be = backend_of(inertia_point, mass, offset)
    tensor = as_matrix(be, inertia_point, (3, 3), "inertia_point")
    return be.matrix(
        (
            tensor - _steiner_term(be, be.scalar(mass, "mass"), as_vector(be, offset, 3, "offset"))
        ).tolist()
    )


def composite_body(bodies: Sequence[RigidBody]) -> RigidBody:
    """One rigid body from several in the same frame: ``m = sum m_k``,
    ``c = sum m_k c_k / m`` and ``I_c = sum (I_k + m_k (|d_k|^2 E - d_k d_k^T))`` with
    ``d_k = c_k - c`` (each body's tensor carried to the common centre by Steiner)."""
    if not bodies:
        raise SymkinError("composite_body needs at least one body")
    be = backend_of(
        *([b.mass for b in bodies] + [b.com for b in bodies] + [b.inertia for b in bodies])
    )
    masses = [be.scalar(b.mass, "mass") for b in bodies]
    coms = [as_vector(be, b.com, 3, "com") for b in bodies]
    total = sum(masses)
    if be.is_zero(total) is True:
        raise SymkinError("composite_body: the total mass is zero; the centre is undefined")
    centre = [sum(m * c[i] for m, c in zip(masses, coms, strict=True)) / total for i in range(3)]
    inertia = be.matrix([[0] * 3] * 3)
    for body, m, c in zip(bodies, masses, coms, strict=True):
        offset = [c[i] - centre[i] for i in range(3)]
        inertia = inertia + inertia_about_point(
            as_matrix(be, body.inertia, (3, 3), "inertia"), m, be.vector(offset)
        )
    if be.symbolic:
        centre = [sp.simplify(c) for c in centre]
        inertia = inertia.applyfunc(sp.simplify)
    return RigidBody(total, be.vector(centre), be.matrix(inertia.tolist()))


def _axis_index(axis: str) -> int:
    if axis not in AXES:
        raise SymkinError(f"axis must be one of x, y, z, got {axis!r}")
    return AXES.index(axis)


def _diagonal(be: Backend, moments: Sequence[Scalar]) -> Matrix:
    return be.matrix([[moments[i] if i == j else 0 for j in range(3)] for i in range(3)])


def hollow_cylinder_inertia(
    mass: Scalar, inner_radius: Scalar, outer_radius: Scalar, length: Scalar, axis: str = "z"
) -> Matrix:
    """Thick-walled tube about its centre, its axis along ``axis``:
    ``m (ri^2 + ro^2) / 2`` about the axis, ``m (3 (ri^2 + ro^2) + h^2) / 12`` across it."""
    be = backend_of(mass, inner_radius, outer_radius, length)
    m, ri, ro, h = (be.scalar(v, k) for v, k in (
        (mass, "mass"), (inner_radius, "inner_radius"), (outer_radius, "outer_radius"),
        (length, "length"),
    ))  # fmt: skip
    radii = ri * ri + ro * ro
    along = m * radii / 2
    across = m * (3 * radii + h * h) / 12
    index = _axis_index(axis)
    return _diagonal(be, [along if i == index else across for i in range(3)])


def cylinder_inertia(mass: Scalar, radius: Scalar, length: Scalar, axis: str = "z") -> Matrix:
    """Solid cylinder about its centre: ``m r^2 / 2`` about the axis, ``m (3 r^2 + h^2) / 12``
    across it."""
    return hollow_cylinder_inertia(mass, 0, radius, length, axis)


def box_inertia(mass: Scalar, size_x: Scalar, size_y: Scalar, size_z: Scalar) -> Matrix:
    """Solid cuboid of edges ``a, b, c`` along x, y, z about its centre:
    ``diag(m (b^2 + c^2), m (a^2 + c^2), m (a^2 + b^2)) / 12``."""
    be = backend_of(mass, size_x, size_y, size_z)
    m = be.scalar(mass, "mass")
    a, b, c = (
        be.scalar(v, k) for v, k in ((size_x, "size_x"), (size_y, "size_y"), (size_z, "size_z"))
    )
    return _diagonal(
        be, [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]
    )


def sphere_inertia(mass: Scalar, radius: Scalar) -> Matrix:
    """Solid sphere about its centre: ``2 m r^2 / 5`` about every axis."""
    be = backend_of(mass, radius)
    m, r = be.scalar(mass, "mass"), be.scalar(radius, "radius")
    return _diagonal(be, [2 * m * r * r / 5] * 3)


def _pi(be: Backend) -> Scalar:
    return sp.pi if be.symbolic else math.pi


def cylinder_volume(radius: Scalar, length: Scalar, inner_radius: Scalar = 0) -> Scalar:
    """``pi (r^2 - ri^2) h`` (``ri > 0``: a tube)."""
    be = backend_of(radius, length, inner_radius)
    r, h, ri = (be.scalar(v) for v in (radius, length, inner_radius))
    return _pi(be) * (r * r - ri * ri) * h


def box_volume(size_x: Scalar, size_y: Scalar, size_z: Scalar) -> Scalar:
    """``a b c``."""
    be = backend_of(size_x, size_y, size_z)
    return be.scalar(size_x) * be.scalar(size_y) * be.scalar(size_z)


def sphere_volume(radius: Scalar) -> Scalar:
    """``4 pi r^3 / 3``."""
    be = backend_of(radius)
    r = be.scalar(radius)
    return 4 * _pi(be) * r**3 / 3
