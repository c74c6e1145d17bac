"""The statement order of symkin.kernels.schedule: a valid evaluation order that keeps few
values alive, the same values, and the C lines that store each output entry early."""

from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkin.emit.c import emit_c
from symkin.emit.layout import kernel_layout
from symkin.kernels import Kernel, KernelInput, KernelOutput, derivatives
from symkin.kernels.derivatives import inverse_dynamics_derivatives_kernel
from symkin.kernels.schedule import greedy_order, scheduled

x, y = sp.symbols("x y", real=True)
a0, a1, a2, b0, b1, b2 = sp.symbols("a0 a1 a2 b0 b1 b2", real=True)


def two_chains() -> Kernel:
    """``a2 = (sin x * x)^2`` and ``b2 = (cos x * y)^2``, written interleaved, so two values
    are alive at every step; outputs ``[a2, b2, y]``."""
    return Kernel(
        "chains",
        "two chains",
        (KernelInput("q", (x, y), "inputs"),),
        (KernelOutput("o", sp.ImmutableMatrix([a2, b2, y]), "out", "vector"),),
        (
            (a0, sp.sin(x)),
            (b0, sp.cos(x)),
            (a1, a0 * x),
            (b1, b0 * y),
            (a2, a1**2),
            (b2, b1**2),
        ),
    )


def test_a_chain_is_finished_and_stored_before_the_next_one_starts():
    # By hand: a0 and b0 are ready and end no life (tie: a0, the first); then a1 ends a0's,
    # a2 ends a1's and o[0] is stored; b0, b1, b2 follow.  o[2] = y reads no intermediate.
    reads = [(), (), (0,), (1,), (2,), (3,)]
    assert greedy_order(reads, [(4,), (5,), ()]) == [0, 2, 4, 1, 3, 5]
    layout = kernel_layout(scheduled(two_chains()), str)
    lines = [(s.target, s.code, s.defines) for s in layout.statements]
    assert lines == [
        ("o[2]", "y", False),
        ("t0", "sin(x)", True),
        ("t1", "t0*x", True),
        ("t2", "t1**2", True),
        ("o[0]", "t2", False),
        ("t3", "cos(x)", True),
        ("t4", "t3*y", True),
        ("t5", "t4**2", True),
        ("o[1]", "t5", False),
    ]


def test_a_kernel_without_early_stores_keeps_its_layout():
    layout = kernel_layout(two_chains(), str)
    assert layout.statements == ()
    assert [name for name, _ in layout.assignments] == ["a0", "b0", "a1", "b1", "a2", "b2"]


def test_the_c_source_stores_each_entry_right_after_the_last_intermediate_it_reads(model_of):
    model = model_of("planar_2r")
    source = emit_c(model.robot, (inverse_dynamics_derivatives_kernel(model),))["c/planar_2r.c"]
    body = source.split("void planar_2r_inverse_dynamics_derivatives(", 1)[1]
    body = body.split("{\n", 1)[1].split("\n}\n", 1)[0]
    newest = -1  # the intermediate t<k> defined last so far
    stores = 0
    for line in body.splitlines():
        target, code = line.strip().rstrip(";").split(" = ", 1)
        read = [int(k) for k in re.findall(r"\bt(\d+)\b", code)]
        if target.startswith("const"):
            defined = re.fullmatch(r"const double t(\d+)", target)
            if defined:
                assert int(defined[1]) == newest + 1  # numbered in the order of the lines
                newest += 1
            continue
        stores += 1
        assert max(read, default=-1) == newest, line
    assert stores == 2 + 4 + 4


@st.composite
def dags(draw):
    """Random reads: assignment k reads some of 0 .. k-1; entries read any of them."""
    size = draw(st.integers(1, 30))
    reads = [
        tuple(sorted(draw(st.sets(st.integers(0, k - 1), max_size=3)))) if k else ()
        for k in range(size)
    ]
    entries = draw(st.lists(st.sets(st.integers(0, size - 1), max_size=3), max_size=8))
    return reads, [tuple(sorted(e)) for e in entries]


@settings(max_examples=200, deadline=None)
@given(dags())
def test_every_assignment_comes_after_what_it_reads(dag):
    reads, entries = dag
    order = greedy_order(reads, entries)
    assert sorted(order) == list(range(len(reads)))
    position = {k: n for n, k in enumerate(order)}
    for k, operands in enumerate(reads):
        assert all(position[j] < position[k] for j in operands)


def peak_alive(kernel: Kernel) -> int:
    """Most intermediates alive at once (defined, read again later) with every output entry
    stored right after the last intermediate it reads."""
    last: dict[sp.Symbol, int] = {}
    position = {s: k for k, (s, _) in enumerate(kernel.assignments)}
    for k, (_, expr) in enumerate(kernel.assignments):
        for symbol in expr.free_symbols & position.keys():
            last[symbol] = k
    for output in kernel.outputs:
        for expr in output.matrix:
            used = [position[s] for s in expr.free_symbols & position.keys()]
            for symbol in expr.free_symbols & position.keys():
                end = max(used) if kernel.early_stores else len(position)
                last[symbol] = max(last.get(symbol, -1), end)
    return max(
        sum(1 for symbol, k in position.items() if k <= n < last.get(symbol, -1))
        for n in position.values()
    )


def evaluate(kernel: Kernel, values: dict) -> np.ndarray:
    known = dict(values)
    for symbol, expr in kernel.assignments:
        known[symbol] = float(expr.xreplace(known))
    return np.array([float(e.xreplace(known)) for o in kernel.outputs for e in o.matrix])


@pytest.mark.parametrize("name", ["rpr", "planar_3r"])
def test_the_derivative_kernel_keeps_its_values_with_fewer_values_alive(
    name, model_of, monkeypatch
):
    model = model_of(name)
    ordered = inverse_dynamics_derivatives_kernel(model)
    monkeypatch.setattr(derivatives, "scheduled", lambda kernel: kernel)
    written = derivatives.inverse_dynamics_derivatives_kernel(model)  # the sweeps' order
    assert ordered.early_stores and not written.early_stores
    rng = np.random.default_rng(4)
    symbols = [s for i in ordered.inputs for s in i.symbols]
    values = dict(zip(symbols, rng.uniform(-1.0, 1.0, len(symbols)), strict=True))
    assert np.allclose(evaluate(ordered, values), evaluate(written, values), rtol=1e-12)
    assert peak_alive(ordered) < peak_alive(written)
