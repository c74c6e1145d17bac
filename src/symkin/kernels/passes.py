"""Rewrite passes over named intermediates that already share their subexpressions (the
Newton–Euler recursion's): keep what the outputs need, inline single-use summands, factor out
common factors, absorb signs, and number what is left ``t0, t1, ...``.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence

import sympy as sp

from symkin.kernels.engine_cse import symengine_cse
from symkin.kernels.rename import renamed, renamed_matrix
from symkin.kernels.spec import (
    Kernel,
    KernelInput,
    KernelOutput,
    count_operations,
    intermediate_prefix,
)


def kernel_from_assignments(
    name: str,
    description: str,
    inputs: Sequence[KernelInput],
    assignments: Sequence[tuple[sp.Symbol, sp.Expr]],
    outputs: Sequence[tuple[str, sp.MatrixBase, str]],
    engine: str = "sympy",
) -> Kernel:
    """A kernel from named intermediates that already share their subexpressions.

    Keeps only the intermediates the outputs need (in definition order) and renames them
    ``t0, t1, ...`` so the text does not depend on how many were recorded before.
    ``engine``: whose CSE finds the shared subexpressions, ``"sympy"`` (``sympy.cse``) or
    ``"symengine"`` (:func:`symengine_cse`: about twice as fast on a generic arm's dynamics,
    but up to a few per cent more operations; see :func:`symkin.kernels.catalogue.cse_engine`).
    """
    matrices = [sp.ImmutableMatrix(m) for _, m, *_ in outputs]
    needed = _needed(list(assignments), matrices)
    kept, matrices = _shared_subexpressions(needed, matrices, CSE_ENGINES[engine])
    kept, matrices = _summands_inlined(*_without_aliases(kept, matrices))
    # Factoring makes new sums, some the negatives of others.
    kept, matrices = _without_aliases(*_common_factors_out(kept, matrices))
    kept, matrices = _signs_absorbed(kept, matrices)
    prefix = intermediate_prefix([e for _, e in kept] + [e for m in matrices for e in m])
    renaming = {old: sp.Symbol(f"{prefix}{k}", real=True) for k, (old, _) in enumerate(kept)}
    memo: dict = {}
    named = tuple((renaming[s], renamed(e, renaming, memo)) for s, e in kept)
    kernel_outputs = tuple(
        KernelOutput(spec[0], renamed_matrix(matrix, renaming, memo), *spec[2:])
        for spec, matrix in zip(outputs, matrices, strict=True)
    )
    return Kernel(name, description, tuple(inputs), kernel_outputs, named)


CSE_ENGINES: dict[str, Callable[..., tuple[list[tuple[sp.Symbol, sp.Expr]], list]]] = {
    "sympy": sp.cse,
    "symengine": symengine_cse,
}


def _summands_inlined(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Substitute an intermediate used once, as a plain term of a sum (``tau1 = 0.78*ddq1 +
    t100``), so like terms merge (``t100 = 1.88*ddq1 + ...``).  Nowhere else: a number times
    an inlined sum would be distributed, costing multiplications."""
    uses: Counter[sp.Symbol] = Counter()
    expressions = [e for _, e in assignments] + [e for m in matrices for e in m]
    for expr in expressions:
        uses.update(expr.free_symbols)
    definitions = dict(assignments)

    def inlined(expr: sp.Expr) -> sp.Expr:
        if not expr.is_Add:
            return expr
        if not any(t in definitions and uses[t] == 1 for t in expr.args):
            return expr  # nothing to inline: no new sum to build
        terms = [definitions[t] if t in definitions and uses[t] == 1 else t for t in expr.args]
        return sp.Add(*terms)

    substituted = [(s, inlined(e)) for s, e in assignments]
    matrices = [m.applyfunc(inlined) for m in matrices]
    return _needed(substituted, matrices), matrices


def _signs_absorbed(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Name ``a + b`` instead of ``-a - b`` and ``a*b`` instead of ``-a*b`` (one negation
    fewer) and let the uses take the sign: ``x - t`` costs what ``x + t`` does.  Kept only
    where the whole kernel gets shorter."""
    flipped: dict[sp.Symbol, sp.Expr] = {}
    result = []
    for symbol, expr in assignments:
        expr = expr.xreplace(flipped)
        if (expr.is_Add and all(t.could_extract_minus_sign() for t in expr.args)) or (
            expr.is_Mul and expr.as_coeff_Mul()[0] < 0
        ):
            flipped[symbol] = -symbol
            expr = -expr
        result.append((symbol, expr))
    if not flipped:
        return assignments, matrices
    flipped_matrices = [m.xreplace(flipped) for m in matrices]
    before = [e for _, e in assignments] + [e for m in matrices for e in m]
    after = [e for _, e in result] + [e for m in flipped_matrices for e in m]
    # Only the expressions that changed are counted (xreplace returns the same object else).
    changed = [k for k, (old, new) in enumerate(zip(before, after, strict=True)) if old is not new]
    saving = (
        count_operations([before[k] for k in changed])["total"]
        - count_operations([after[k] for k in changed])["total"]
    )
    return (result, flipped_matrices) if saving > 0 else (assignments, matrices)


def _needed(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> list[tuple[sp.Symbol, sp.Expr]]:
    """The intermediates the outputs need, in definition order (dead ones dropped)."""
    needed: set[sp.Symbol] = set().union(*(m.free_symbols for m in matrices))
    kept = []
    for symbol, expr in reversed(assignments):
        if symbol in needed:
            kept.append((symbol, expr))
            needed |= expr.free_symbols
    return kept[::-1]


def _common_factors_out(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Take a factor shared by terms of a sum out of it: ``a*x + a*y + z`` becomes
    ``a*u + z`` with a new intermediate ``u = x + y``, one multiplication fewer.

    CSE shares whole subexpressions but never factors, and the recursions leave many such
    sums (``0.00288*t45 + 0.00288*t58``).  The inner sum gets a name of its own because
    SymPy would distribute a number over a sum again.
    """
    counter = iter(range(10**9))
    result: list[tuple[sp.Symbol, sp.Expr]] = []

    def factored(expr: sp.Expr) -> sp.Expr:
        if not expr.is_Add:
            return expr
        terms = sp.Add.make_args(expr)
        occurrences: Counter[sp.Expr] = Counter()
        for term in terms:
            occurrences.update(_factors(term))
        if not occurrences:
            return expr
        factor, count = max(occurrences.items(), key=lambda kv: (kv[1], sp.default_sort_key(kv[0])))
        if count < 2:
            return expr
        inside = [_divided(t, factor) for t in terms if factor in _factors(t)]
        outside = [t for t in terms if factor not in _factors(t)]
        inner = factored(sp.Add(*inside))
        if not inner.is_Atom:
            symbol = sp.Symbol(f"_factor{next(counter)}", real=True)
            result.append((symbol, inner))
            inner = symbol
        return factor * inner + factored(sp.Add(*outside))

    for symbol, expr in assignments:
        result.append((symbol, factored(expr)))
    return result, [m.applyfunc(factored) for m in matrices]


def _factors(term: sp.Expr) -> set[sp.Expr]:
    """The factors of one term of a sum, its coefficient's size among them unless it is 1."""
    coefficient, rest = term.as_coeff_Mul()
    factors = set(sp.Mul.make_args(rest)) - {sp.Integer(1)}
    if not _is_unit(coefficient):
        factors.add(abs(coefficient))
    return factors


def _is_unit(number: sp.Number) -> bool:
    # SymPy 1.13+ holds Float(1.0) != Integer(1); both mean no multiplication here.
    return abs(float(number)) == 1.0


def _divided(term: sp.Expr, factor: sp.Expr) -> sp.Expr:
    """``term / factor`` for a factor of the term, without leaving a ``1.0*`` behind."""
    coefficient, rest = term.as_coeff_Mul()
    if factor.is_Number:
        coefficient = coefficient / factor
    else:
        rest = rest / factor
    if _is_unit(coefficient):
        coefficient = sp.Integer(1 if coefficient > 0 else -1)
    return coefficient * rest


def _without_aliases(
    assignments: list[tuple[sp.Symbol, sp.Expr]], matrices: list[sp.ImmutableMatrix]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """Substitute intermediates that copy a symbol or a number, or an earlier intermediate or
    its negative (``t7 = -t3``; ``t9 = t4 - t2`` after ``t8 = t2 - t4``): CSE does not see
    that ``x`` and ``-x`` share their work, and factoring makes sums CSE never saw."""
    aliases: dict[sp.Symbol, sp.Expr] = {}
    defined: dict[frozenset, sp.Symbol] = {}
    kept = []
    for symbol, expr in assignments:
        expr = expr.xreplace(aliases)
        # Terms as (coefficient, rest) pairs: negating them is cheap, unlike -expr in SymPy.
        terms = [t.as_coeff_Mul() for t in sp.Add.make_args(expr)]
        negated = frozenset((-c, rest) for c, rest in terms)
        if expr.is_Atom or (terms[0][0] == -1 and len(terms) == 1 and terms[0][1].is_Atom):
            aliases[symbol] = expr
        elif frozenset(terms) in defined:
            aliases[symbol] = defined[frozenset(terms)]
        elif negated in defined:
            aliases[symbol] = -defined[negated]
        else:
            defined[frozenset(terms)] = symbol
            kept.append((symbol, expr))
    return kept, [m.xreplace(aliases) for m in matrices]


def _shared_subexpressions(
    assignments: list[tuple[sp.Symbol, sp.Expr]],
    matrices: list[sp.ImmutableMatrix],
    cse: Callable[..., tuple[list[tuple[sp.Symbol, sp.Expr]], list]] = sp.cse,
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.ImmutableMatrix]]:
    """One CSE over named intermediates and outputs (``sin(q1)`` once, not per quantity).

    Each new subexpression is placed just before its first use, which is after every
    intermediate it refers to, so the order stays a valid evaluation order.
    """
    expressions = [e for _, e in assignments] + list(matrices)
    found, reduced = cse(expressions, symbols=sp.numbered_symbols("_cse", real=True))
    definitions = dict(found)
    placed: set[sp.Symbol] = set()
    ordered: list[tuple[sp.Symbol, sp.Expr]] = []

    def place(expr: sp.Expr) -> None:
        for symbol in sorted(expr.free_symbols & definitions.keys(), key=sp.default_sort_key):
            if symbol not in placed:
                place(definitions[symbol])
                placed.add(symbol)
                ordered.append((symbol, definitions[symbol]))

    for (symbol, _), expr in zip(assignments, reduced, strict=False):
        place(expr)
        ordered.append((symbol, expr))
    outputs = [sp.ImmutableMatrix(m) for m in reduced[len(assignments) :]]
    for matrix in outputs:
        place(matrix)
    return ordered, outputs
