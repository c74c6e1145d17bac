"""What every backend's template needs from a kernel, printed by one printer.

Python decides here (which inputs a kernel reads, what each entry says); templates only lay
the pieces out.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp

from symkin.kernels import Kernel, KernelOutput


@dataclass(frozen=True)
class Unpack:
    """``symbol = input[index]`` for a symbol the kernel reads."""

    symbol: str
    input: str
    index: int


@dataclass(frozen=True)
class Entry:
    """One output entry: 0-based row/column, row-major flat index, printed expression."""

    row: int
    col: int
    flat: int
    code: str
    is_zero: bool


@dataclass(frozen=True)
class OutputLayout:
    name: str
    description: str
    rows: int
    cols: int
    entries: tuple[Entry, ...]
    kind: str
    units: str = ""

    @property
    def size(self) -> int:
        return self.rows * self.cols

    @property
    def numpy_shape(self) -> tuple[int, ...]:
        """``(rows, cols)`` for a matrix, ``(rows,)`` for a vector, ``()`` for a scalar."""
        return {"scalar": (), "vector": (self.rows,)}.get(self.kind, (self.rows, self.cols))

    def numpy_index(self, entry: Entry) -> str:
        """Index of an entry after the batch dimensions: ``"..., 0, 1"``."""
        position = {"scalar": (), "vector": (entry.row,)}.get(self.kind, (entry.row, entry.col))
        return ", ".join(["...", *map(str, position)])


# Inputs that change from state to state (a batch has one row each); others are shared.
STATE_INPUTS = ("q", "dq", "ddq", "d3q", "d4q", "wrench")


@dataclass(frozen=True)
class InputLayout:
    name: str
    size: int
    description: str

    @property
    def per_state(self) -> bool:
        return self.name in STATE_INPUTS


@dataclass(frozen=True)
class Statement:
    """One line of a kernel whose outputs are stored early: ``const real target = code;``
    when ``defines``, else the store ``target = code;`` (``target`` like ``"tau[3]"``)."""

    target: str
    code: str
    defines: bool


@dataclass(frozen=True)
class KernelLayout:
    name: str
    description: str
    inputs: tuple[InputLayout, ...]
    counts: dict[str, int]
    unpack: tuple[Unpack, ...]
    unused_inputs: tuple[str, ...]
    assignments: tuple[tuple[str, str], ...]
    outputs: tuple[OutputLayout, ...]
    # A kernel with ``early_stores``: assignments and output stores in one sequence, each
    # entry right after the last intermediate it reads (entries reading none come first).
    statements: tuple[Statement, ...] = ()


def _output_layout(output: KernelOutput, printer: Callable[[sp.Expr], str]) -> OutputLayout:
    entries = tuple(
        Entry(i, j, i * output.matrix.cols + j, printer(e), e == 0)
        for i in range(output.matrix.rows)
        for j in range(output.matrix.cols)
        for e in (output.matrix[i, j],)
    )
    return OutputLayout(
        output.name,
        output.description,
        output.matrix.rows,
        output.matrix.cols,
        entries,
        output.kind,
        output.units,
    )


def kernel_layout(
    kernel: Kernel,
    printer: Callable[[sp.Expr], str],
    counts: dict[str, int] | None = None,
) -> KernelLayout:
    """What the templates need from ``kernel``, each expression printed by ``printer``;
    ``counts``: the operation counts to report (the kernel's own when ``None``; a backend
    that rewrites a kernel reports the counts of the kernel it was given)."""
    used = kernel.symbols_read
    unpack = tuple(
        Unpack(symbol.name, kernel_input.name, index)
        for kernel_input in kernel.inputs
        for index, symbol in enumerate(kernel_input.symbols)
        if symbol in used
    )
    read = {u.input for u in unpack}
    assignments = tuple((symbol.name, printer(expr)) for symbol, expr in kernel.assignments)
    outputs = tuple(_output_layout(o, printer) for o in kernel.outputs)
    return KernelLayout(
        name=kernel.name,
        description=kernel.description,
        inputs=tuple(InputLayout(i.name, len(i.symbols), i.description) for i in kernel.inputs),
        counts=kernel.operation_counts if counts is None else counts,
        unpack=unpack,
        unused_inputs=tuple(i.name for i in kernel.inputs if i.name not in read),
        assignments=assignments,
        outputs=outputs,
        statements=_interleaved(kernel, assignments, outputs) if kernel.early_stores else (),
    )


def _interleaved(
    kernel: Kernel, assignments: tuple[tuple[str, str], ...], outputs: tuple[OutputLayout, ...]
) -> tuple[Statement, ...]:
    """Assignments and output stores, each store right after the last assignment it reads."""
    position = {symbol: k for k, (symbol, _) in enumerate(kernel.assignments)}
    after: list[list[Statement]] = [[] for _ in range(len(assignments) + 1)]
    for output, layout in zip(kernel.outputs, outputs, strict=True):
        for expr, entry in zip(output.matrix, layout.entries, strict=True):
            last = max((position[s] for s in expr.free_symbols if s in position), default=-1)
            after[last + 1].append(Statement(f"{layout.name}[{entry.flat}]", entry.code, False))
    lines = list(after[0])
    for (name, code), stores in zip(assignments, after[1:], strict=True):
        lines += [Statement(name, code, True), *stores]
    return tuple(lines)
