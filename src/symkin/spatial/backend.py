"""The one implementation behind every :mod:`symkin.spatial` function, for SymPy and NumPy.

If any input is a SymPy object the computation is symbolic (:class:`sympy.ImmutableMatrix` /
SymPy expressions); otherwise it is numeric (``numpy.ndarray`` float64 / ``float``).  The few
primitives that differ (sin, cos, atan2, sqrt, matrix constructor, "is this zero?") are
dispatched through :class:`Backend`; the input conversions and checks here raise
:class:`~symkin.errors.SymkinError` naming the argument.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import sympy as sp

from symkin.errors import SymkinError

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


def is_symbolic(x: object) -> bool:
    """True if ``x`` is (or contains) a SymPy object."""
    if isinstance(x, sp.Basic | sp.MatrixBase):
        return True
    if isinstance(x, np.ndarray):
        # Only object arrays can hold SymPy values; float arrays are numeric by construction.
        return x.dtype == object and any(is_symbolic(e) for e in x.flat)
    if isinstance(x, list | tuple):
        return any(is_symbolic(e) for e in x)
    return False


class Backend:
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


_NUMERIC = Backend(symbolic=False)
_SYMBOLIC = Backend(symbolic=True)


def backend_of(*args: object) -> Backend:
    """SymPy if any argument is symbolic, else NumPy."""
    return _SYMBOLIC if any(is_symbolic(a) for a in args) else _NUMERIC


def as_matrix(be: Backend, x: MatrixLike, shape: tuple[int, int], name: str) -> Matrix:
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


def as_vector(be: Backend, x: MatrixLike, n: int, name: str) -> list[Scalar]:
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


def rotation_input(R: MatrixLike, name: str = "R") -> tuple[Backend, Matrix]:
    """Backend and 3x3 matrix for an inverse map; numeric input must be a rotation."""
    be = backend_of(R)
    M = as_matrix(be, R, (3, 3), name)
    if not be.symbolic:
        check_rotation(M, name)
    return be, M


def transform_input(T: MatrixLike, name: str = "T") -> tuple[Backend, Matrix]:
    """Backend and 4x4 matrix; numeric input must be a rigid transform."""
    be = backend_of(T)
    M = as_matrix(be, T, (4, 4), name)
    if not be.symbolic:
        check_rotation(M[:3, :3], f"the rotation block of {name}")
        if not np.all(np.isfinite(M)) or np.max(np.abs(M[3] - [0, 0, 0, 1])) > ORTHONORMAL_TOL:
            raise SymkinError(f"{name} must have the bottom row [0, 0, 0, 1], got {M.tolist()}")
    return be, M


def check_rotation(M: np.ndarray, name: str) -> None:
    """Raise SymkinError unless numeric ``M`` is finite, orthonormal and has ``det M > 0``."""
    if not np.all(np.isfinite(M)):
        raise SymkinError(f"{name} must be finite, got {M.tolist()}")
    err = float(np.max(np.abs(M.T @ M - np.eye(3))))
    if err > ORTHONORMAL_TOL or np.linalg.det(M) <= 0:
        raise SymkinError(
            f"{name} must be a rotation matrix (R^T R = I within {ORTHONORMAL_TOL:g}, det R = +1), "
            f"got {M.tolist()}"
        )


def unit(be: Backend, items: Sequence[Scalar], name: str) -> list[Scalar]:
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


def singular_flag(*flags: bool | None) -> bool | None:
    """Combine "is at this singularity" flags: True if any is True, None if any undecided."""
    if any(f is True for f in flags):
        return True
    if any(f is None for f in flags):
        return None
    return False
