"""The kernel passes of ``kernel_from_assignments`` (shared subexpressions, aliases, inlined
summands, common factors, absorbed signs) keep every value and a valid evaluation order.

The generated-code tests check them on the catalogue's kernels; here they run on small
hand-made cases and on random chains of named intermediates (Hypothesis), each compared with
the chain evaluated as written.
"""

from __future__ import annotations

import math

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkin.kernels import KernelInput, count_operations, kernel_from_assignments

X = sp.symbols("x0:4", real=True)
INPUTS = (KernelInput("q", X, "inputs"),)
COEFFICIENTS = (1, -1, 2, -3, sp.Float(0.5), sp.Float(-0.25), sp.Rational(1, 3))


def kernel(assignments, outputs, engine="sympy"):
    matrix = sp.Matrix(outputs)
    spec = [("o", matrix, "", "vector")]
    return kernel_from_assignments("k", "test", INPUTS, assignments, spec, engine)


DIGITS = 40


def evaluate(assignments, outputs, values: dict) -> list[float]:
    """The outputs with each intermediate evaluated in order, in 40-digit arithmetic (so the
    rounding of a regrouped sum, amplified by ``sin`` of a large argument, cannot pass for a
    wrong rewrite); an intermediate used before its definition is an error."""
    known = {k: sp.Float(v, DIGITS) for k, v in values.items()}
    for symbol, expr in assignments:
        missing = expr.free_symbols - known.keys()
        assert not missing, f"{symbol} uses {missing} before their definition"
        known[symbol] = expr.xreplace(known).evalf(DIGITS)
    return [float(e.xreplace(known).evalf(DIGITS)) for e in outputs]


def magnitude(assignments, outputs, values: dict) -> float:
    """The largest absolute value among the inputs, the intermediates and every summand of the
    outputs: the scale of the rounding error a reordered floating-point sum may make."""
    known = dict(values)
    sizes = [1.0, *(abs(float(v)) for v in values.values())]
    for symbol, expr in assignments:
        known[symbol] = sp.Float(expr.xreplace(known))
        sizes += [abs(float(t.xreplace(known))) for t in sp.Add.make_args(expr)]
    for output in outputs:
        sizes += [abs(float(t.xreplace(known))) for t in sp.Add.make_args(output)]
    return max(sizes)


def assert_same_values(original, outputs, result, values) -> None:
    expected = evaluate(original, outputs, values)
    actual = evaluate(result.assignments, list(result.outputs[0].matrix), values)
    # The passes regroup sums, so cancellation may leave a rounding error of the size of the
    # largest summand, not of the (possibly tiny) result.
    scale = magnitude(original, outputs, values)
    for a, b in zip(actual, expected, strict=True):
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12 * scale), (actual, expected)


VALUES = dict(zip(X, (0.3, -1.1, 0.7, 1.9), strict=True))


def test_duplicate_and_negated_sums_are_computed_once():
    r0, r1, r2 = sp.symbols("r0:3", real=True)
    a, b, c, _ = X
    original = [(r0, a * c + b * c), (r1, a * c + b * c), (r2, -a * c - b * c)]
    outputs = [r0 * a, r1 * b + r2, r2 * c]
    result = kernel(original, outputs)
    assert_same_values(original, outputs, result, VALUES)
    # The three names are one sum (a + b) c, computed once: (a + b) appears once.
    sums = [e for _, e in result.assignments if e.is_Add and e.free_symbols == {a, b}]
    assert len(sums) == 1
    before = count_operations([e for _, e in original] + outputs)["total"]
    assert result.operation_counts["total"] <= before - 6


def test_a_negated_product_gives_its_sign_to_its_uses():
    r0 = sp.Symbol("r0", real=True)
    a, b, c, d = X
    original = [(r0, -a * b * c)]
    outputs = [d - r0 * a, d + r0 * b]
    result = kernel(original, outputs)
    assert_same_values(original, outputs, result, VALUES)
    before = count_operations([e for _, e in original] + outputs)["total"]
    assert result.operation_counts["total"] < before


def test_a_common_factor_is_taken_out():
    a, b, c, d = X
    outputs = [a * b + a * c + a * d + b]
    result = kernel([], outputs)
    assert_same_values([], outputs, result, VALUES)
    assert result.operation_counts["multiplications"] == 1


@st.composite
def chains(draw):
    """Random named intermediates over X (sums of products, negations, copies, sines and
    squares) and three outputs that use them."""
    pool = list(X)
    assignments = []

    def term():
        factors = draw(st.lists(st.sampled_from(pool), min_size=1, max_size=2))
        first = factors[0]
        wrap = draw(st.sampled_from(("plain", "plain", "plain", "sin", "square")))
        if wrap == "sin":
            first = sp.sin(first)
        elif wrap == "square":
            first = first**2
        return draw(st.sampled_from(COEFFICIENTS)) * sp.Mul(first, *factors[1:])

    for k in range(draw(st.integers(1, 10))):
        kind = draw(st.sampled_from(("sum", "sum", "sum", "negated", "copy", "negated copy")))
        if kind.endswith("copy") and assignments:
            expr = draw(st.sampled_from(assignments))[1]
            expr = -expr if kind == "negated copy" else expr
        else:
            expr = sp.Add(*(term() for _ in range(draw(st.integers(1, 4)))))
            expr = -expr if kind == "negated" else expr
        symbol = sp.Symbol(f"r{k}", real=True)
        assignments.append((symbol, expr))
        pool.append(symbol)
    outputs = [sp.Add(*(term() for _ in range(draw(st.integers(1, 3))))) for _ in range(3)]
    return assignments, outputs


@pytest.mark.parametrize("engine", ["sympy", "symengine"])
@settings(max_examples=150, deadline=None)
@given(chains(), st.lists(st.floats(-2.0, 2.0), min_size=4, max_size=4))
def test_random_chains_keep_their_values(engine, chain, numbers):
    assignments, outputs = chain
    result = kernel(assignments, outputs, engine)
    assert_same_values(assignments, outputs, result, dict(zip(X, numbers, strict=True)))


def test_symengine_cse_shares_a_repeated_subexpression_and_keeps_assumptions():
    a, b, c, _ = X
    shared = sp.sin(a + b) * c
    outputs = [shared + a, shared * b, (a + b) ** 2]
    result = kernel([], outputs, "symengine")
    assert_same_values([], outputs, result, VALUES)
    # sin(a + b)*c (and a + b in it) is computed once: one sine in the whole kernel.
    sines = [e for _, e in result.assignments for f in sp.preorder_traversal(e) if f.func == sp.sin]
    assert len(sines) == 1
    # The inputs come back as the same (real) symbols, not SymEngine's plain ones.
    assert all(s.is_real for _, e in result.assignments for s in e.free_symbols)


def test_a_kernel_refuses_a_symbol_it_never_defines():
    from symkin.kernels import Kernel, KernelInput, KernelOutput

    x, t0, t1, stray = sp.symbols("x t0 t1 stray", real=True)
    inputs = (KernelInput("x", (x,), "input"),)

    def kernel(assignments, output):
        return Kernel("k", "test", inputs, (KernelOutput("y", sp.ImmutableMatrix([output]), "y"),),
                      tuple(assignments))  # fmt: skip

    assert kernel([(t0, x**2), (t1, t0 + x)], t1).name == "k"  # well formed
    with pytest.raises(ValueError, match="stray"):
        kernel([(t0, x * stray)], t0)  # not an input
    with pytest.raises(ValueError, match="t1"):
        kernel([(t0, t1 + x), (t1, x)], t0)  # used before it is defined
    with pytest.raises(ValueError, match="defined twice"):
        kernel([(t0, x), (t0, 2 * x)], t0)
    with pytest.raises(ValueError, match="y uses stray"):
        kernel([(t0, x)], t0 + stray)  # an output naming an unknown symbol
