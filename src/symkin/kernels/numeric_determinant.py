"""The determinant and manipulability computed from the Jacobian's numbers (the fallback).

When the factored determinant has no closed form within its budget (or closed forms are
switched off), the ``det`` and ``manipulability`` kernels still exist, with the same inputs and
outputs: they evaluate the geometric Jacobian (the ``jacobian`` kernel's intermediates) and
take the determinant of its task rows by Laplace expansion with shared minors, written out as
named intermediates (``n 2^(n-1)`` products, 192 for six joints; no division, so no pivoting
and no branch).  Every backend prints it like any kernel: NumPy, C (float and double, single
and batch calls), the Python extension and CasADi agree by construction, and the operation
counts are honest.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import Kernel, KernelOutput


def numeric_determinant_kernels(
    jacobian: Kernel, rows: Sequence[int], rows_text: str, unit: str, reason: str
) -> tuple[Kernel, Kernel]:
    """``det`` and ``manipulability`` (``|det J|``) of rows ``rows`` of ``jacobian``'s output
    ``J``, evaluated numerically; ``reason`` (why there is no closed form) goes into the
    description."""
    (output,) = jacobian.outputs
    entries = [[output.matrix[r, c] for c in range(output.matrix.cols)] for r in rows]
    assignments = list(jacobian.assignments)
    determinant = _minors_expansion(entries, assignments)
    where = f"of the task Jacobian (rows {rows_text}), computed numerically from the Jacobian"
    det = kernel_from_assignments(
        "det",
        f"determinant {where} ({reason})",
        jacobian.inputs,
        assignments,
        [("det", sp.Matrix([[determinant]]), "det J", "scalar", unit)],
    )
    # |det J| reuses det's intermediates: the same passes would only repeat themselves.
    (value,) = det.outputs
    absolute = sp.ImmutableMatrix([[sp.Abs(value.matrix[0])]])
    manipulability = Kernel(
        "manipulability",
        f"Yoshikawa manipulability {where} ({reason})",
        det.inputs,
        (KernelOutput("mu", absolute, "|det J|", "scalar", unit),),
        det.assignments,
    )
    return det, manipulability


def numeric_manipulability_kernel(
    jacobian: Kernel, rows: Sequence[int], rows_text: str, unit: str
) -> Kernel:
    """Yoshikawa's ``mu = sqrt(det(J J^T))`` of rows ``rows`` of ``jacobian``'s ``J`` when the
    arm is redundant (more columns than rows): the Gram matrix ``J J^T`` as named
    intermediates (symmetric: the upper triangle only), its determinant by the same minors
    expansion, and the square root of its absolute value (rounding can leave ``-1e-17`` where
    the arm is singular)."""
    (output,) = jacobian.outputs
    matrix = output.matrix
    assignments = list(jacobian.assignments)
    gram: dict[tuple[int, int], sp.Expr] = {}
    for i, row_i in enumerate(rows):
        for j, row_j in enumerate(rows[i:], start=i):
            value = sp.Add(*(matrix[row_i, c] * matrix[row_j, c] for c in range(matrix.cols)))
            gram[i, j] = gram[j, i] = _named(value, f"gram_{i}{j}", assignments)
    size = len(rows)
    entries = [[gram[i, j] for j in range(size)] for i in range(size)]
    value = sp.sqrt(sp.Abs(_minors_expansion(entries, assignments)))
    return kernel_from_assignments(
        "manipulability",
        f"Yoshikawa manipulability sqrt(det(J J^T)) of the task Jacobian (rows {rows_text}), "
        "computed numerically from the Jacobian (redundant arm: no closed form attempted)",
        jacobian.inputs,
        assignments,
        [("mu", sp.Matrix([[value]]), "sqrt(det(J J^T))", "scalar", unit)],
    )


def _minors_expansion(
    entries: list[list[sp.Expr]], assignments: list[tuple[sp.Symbol, sp.Expr]]
) -> sp.Expr:
    """``det`` of a square matrix of expressions; each minor of the last columns becomes an
    intermediate appended to ``assignments`` (``minor[rows]`` for the bit mask ``rows``)."""
    n = len(entries)
    minors: dict[int, sp.Expr] = {0: sp.Integer(1)}
    for size in range(1, n + 1):
        column = n - size
        for rows in (mask for mask in range(1 << n) if mask.bit_count() == size):
            terms, sign = [], 1
            for i in (i for i in range(n) if rows >> i & 1):
                below = minors[rows & ~(1 << i)]
                if entries[i][column] != 0 and below != 0:
                    terms.append(sign * entries[i][column] * below)
                sign = -sign
            minors[rows] = _named(sp.Add(*terms), f"minor_{rows}", assignments)
    return minors[(1 << n) - 1]


def _named(value: sp.Expr, name: str, assignments: list[tuple[sp.Symbol, sp.Expr]]) -> sp.Expr:
    """A symbol for ``value`` (recorded in ``assignments``), or ``value`` itself when it is a
    number or a single symbol."""
    if value.is_Atom:
        return value
    symbol = sp.Dummy(name, real=True)
    assignments.append((symbol, value))
    return symbol
