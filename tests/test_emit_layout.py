"""What the templates get from a kernel (symkin.emit.layout), worked by hand."""

from __future__ import annotations

import sympy as sp

from symkin.emit.layout import kernel_layout
from symkin.kernels import Kernel, KernelInput, KernelOutput

q1, q2, q3, p1, t0 = sp.symbols("q1 q2 q3 p1 t0")


def small_kernel(description: object = "a test kernel") -> Kernel:
    """``t0 = sin(q3)``; output ``[q1*t0, 2]``; ``q2`` and the parameter ``p1`` unread."""
    return Kernel(
        name="small",
        description=description,
        inputs=(KernelInput("q", (q1, q2, q3), "joints"), KernelInput("p", (p1,), "lengths")),
        outputs=(KernelOutput("y", sp.ImmutableMatrix([[q1 * t0, 2]]), "out", "vector"),),
        assignments=((t0, sp.sin(q3)),),
    )


def test_layout_reads_only_the_symbols_the_kernel_uses() -> None:
    layout = kernel_layout(small_kernel(), str)
    assert [(u.symbol, u.input, u.index) for u in layout.unpack] == [("q1", "q", 0), ("q3", "q", 2)]
    assert layout.unused_inputs == ("p",)
    assert layout.assignments == (("t0", "sin(q3)"),)
    entries = layout.outputs[0].entries
    assert [(e.flat, e.code, e.is_zero) for e in entries] == [(0, "q1*t0", False), (1, "2", False)]


def test_the_symbols_read_are_found_once_per_kernel() -> None:
    kernel = small_kernel()
    assert kernel.symbols_read == {q1, q3, t0}
    assert kernel.symbols_read is kernel.symbols_read


def test_a_kernel_that_cannot_be_hashed_still_gets_its_layout() -> None:
    kernel = small_kernel(description=["not", "hashable"])
    assert kernel.symbols_read == {q1, q3, t0}
    assert [u.symbol for u in kernel_layout(kernel, str).unpack] == ["q1", "q3"]
