"""Kernels: named inputs, named outputs and one common-subexpression elimination.

A :class:`Kernel` is what every backend prints.  The CSE runs once, here, so the NumPy, C and
CasADi versions of a kernel share the same intermediates and the same operation counts.  A
kernel is checked when it is made: every symbol an assignment or output uses is an input or
an earlier intermediate, so no backend can print a name it never defines.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from symkin.kernels.operations import visual_counts
from symkin.symbols import unused_prefix

# Kinds reported in operation counts, from SymPy's count_ops(visual=True) names.
OPERATION_KINDS: Mapping[str, tuple[str, ...]] = {
    "additions": ("ADD", "SUB"),
    "multiplications": ("MUL", "NEG"),
    "divisions": ("DIV",),
    "trig": ("SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ATAN2"),
    "sqrt": ("SQRT",),
    "powers": ("POW",),
}


@dataclass(frozen=True)
class KernelInput:
    """A vector input: its name in generated code and its symbols in order."""

    name: str
    symbols: tuple[sp.Symbol, ...]
    description: str


@dataclass(frozen=True)
class KernelOutput:
    """A matrix output (row-major in C), expressed in the kernel's intermediates."""

    name: str
    matrix: sp.ImmutableMatrix
    description: str
    # "matrix", "vector" or "scalar": how array backends shape it (a 1-DOF mass matrix is a
    # 1x1 matrix, a 1-DOF gravity vector has one entry, a determinant is a scalar).
    kind: str = "matrix"
    # SI units of the entries, per row, column or joint where they differ (kernels.units).
    units: str = ""

    @property
    def shape(self) -> tuple[int, int]:
        return self.matrix.shape

    @property
    def size(self) -> int:
        return self.matrix.rows * self.matrix.cols


@dataclass(frozen=True)
class Kernel:
    """One function of generated code: ``outputs = f(inputs)`` after CSE."""

    name: str
    description: str
    inputs: tuple[KernelInput, ...]
    outputs: tuple[KernelOutput, ...]
    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...]
    # Compiled backends store each output entry right after the last intermediate it reads
    # (set by kernels.schedule.scheduled, whose order assumes it), not all at the end.
    early_stores: bool = False

    def __post_init__(self) -> None:
        """Every symbol used is an input or an intermediate defined before its use, and each
        intermediate is defined once: otherwise a backend would print an undefined name."""
        known = {s for kernel_input in self.inputs for s in kernel_input.symbols}
        for symbol, expr in self.assignments:
            _check_defined(self.name, symbol.name, expr, known)
            if symbol in known:
                raise ValueError(f"kernel {self.name}: {symbol.name} is defined twice")
            known.add(symbol)
        for output in self.outputs:
            for expr in output.matrix:
                _check_defined(self.name, output.name, expr, known)

    @cached_property
    def symbols_read(self) -> frozenset[sp.Symbol]:
        """Every symbol the assignments and outputs read (found once: each backend lays out
        the same kernels, and the walk is as long as printing a small one)."""
        return frozenset().union(
            *(e.free_symbols for _, e in self.assignments),
            *(output.matrix.free_symbols for output in self.outputs),
        )

    @cached_property
    def operation_counts(self) -> dict[str, int]:
        """Operations by kind over all assignments and outputs, plus ``total``."""
        expressions = [e for _, e in self.assignments]
        expressions += [e for output in self.outputs for e in output.matrix]
        return count_operations(expressions)


def _check_defined(kernel: str, where: str, expr: sp.Expr, known: set[sp.Symbol]) -> None:
    unknown = expr.free_symbols - known
    if unknown:
        names = ", ".join(sorted(s.name for s in unknown))
        raise ValueError(f"kernel {kernel}: {where} uses {names}, not an input or earlier result")


def _sqrt_count(expr: sp.Expr) -> int:
    return sum(
        1
        for node in sp.preorder_traversal(expr)
        if node.is_Pow and node.exp in (sp.S.Half, -sp.S.Half)
    )


def count_operations(expressions: Sequence[sp.Expr]) -> dict[str, int]:
    """Arithmetic operations by kind (SymPy's ``count_ops``, square roots split from powers)."""
    raw: Counter[str] = Counter()
    for expr in expressions:
        raw.update(visual_counts(expr))
        square_roots = _sqrt_count(expr)
        raw["SQRT"] += square_roots
        raw["POW"] -= square_roots
    counts = {kind: sum(raw[name] for name in names) for kind, names in OPERATION_KINDS.items()}
    counts["total"] = sum(counts.values())
    return counts


def intermediate_prefix(expressions: Sequence[sp.Expr]) -> str:
    """``t`` for intermediates ``t0, t1, ...``, unless an input is already named ``t<k>``."""
    return unused_prefix("t", (s.name for e in expressions for s in e.free_symbols))


def kernel_from_outputs(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    outputs: Sequence[tuple[str, sp.MatrixBase, str]],
) -> Kernel:
    """Run one CSE over all outputs and package the result.

    The intermediates are numbered deterministically in the order SymPy's ``cse`` emits them.
    """
    matrices = [sp.ImmutableMatrix(matrix) for _, matrix, *_ in outputs]
    prefix = intermediate_prefix([e for m in matrices for e in m])
    assignments, reduced = sp.cse(matrices, symbols=sp.numbered_symbols(prefix, real=True))
    kernel_outputs = tuple(
        KernelOutput(spec[0], sp.ImmutableMatrix(matrix), *spec[2:])
        for spec, matrix in zip(outputs, reduced, strict=True)
    )
    return Kernel(name, description, tuple(inputs), kernel_outputs, tuple(assignments))
