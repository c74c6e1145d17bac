"""The one simplification policy of symkin.

General-purpose ``simplify``/``trigsimp`` do not finish on a 6-DOF arm in reasonable time, so
symkin uses two targeted steps instead:

* :func:`contract_trig`: expand, then contract products of sines and cosines into sines and
  cosines of sums of angles (Fu et al.'s rule TR10i), e.g.
  ``cos(q1)cos(q2) - sin(q1)sin(q2) -> cos(q1 + q2)``.  Applied after every matrix product
  it keeps forward kinematics readable and small.
* :func:`reduce_trig`: apply ``sin^2 + cos^2 = 1`` exactly, with sines and cosines as
  polynomial variables ``s_i``, ``c_i`` (:class:`_CircleVariables`); the factored
  determinants of :mod:`symkin.derive.determinant` use the same variables.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import symengine as se
import sympy as sp
from sympy.core.basic import _args_sortkey
from sympy.simplify.fu import TR10i


def contract_trig(expr: sp.Expr, angle_sums: bool = True) -> sp.Expr:
    """Expand ``expr`` and contract sums of products into functions of summed angles.

    With ``angle_sums=False`` (a chain without parallel joint axes, where no sum of joint
    angles can arise) only expand: TR10i's pairwise search costs seconds on a 7-DOF arm
    and would find nothing.  An expansion longer than :data:`MAX_CONTRACTED_TERMS` terms is
    not read anyway: ``expr`` comes back as it was (its product form).
    """
    expanded = expand(expr, MAX_CONTRACTED_TERMS)
    if expanded is None:
        return expr
    if not angle_sums or not expanded.has(sp.sin, sp.cos):
        return expanded
    return TR10i(expanded)


def expand(expr: sp.Expr, max_terms: int | None = None) -> sp.Expr | None:
    """``sympy.expand(expr)``, computed by SymEngine (ten to a hundred times faster on the
    products of a long chain); ``None`` when it has more than ``max_terms`` terms.

    The length is tested before the result comes back to SymPy: converting a long sum costs
    more than expanding it.
    """
    if not isinstance(expr, sp.Expr) or expr.is_Atom:
        return expr
    expanded = se.expand(se.sympify(expr))
    if max_terms is not None and isinstance(expanded, se.Add) and len(expanded.args) > max_terms:
        return None
    symbols = {s.name: s for s in expr.free_symbols}
    return sympy_from_symengine(expanded, symbols)


_REBUILT = (
    (se.Add, sp.Add),
    (se.Mul, sp.Mul),
    (se.Pow, sp.Pow),
    (se.sin, sp.sin),
    (se.cos, sp.cos),
)


def sympy_from_symengine(
    expr: se.Basic, symbols: dict[str, sp.Symbol], seen: dict | None = None
) -> sp.Expr:
    """``expr`` back in SymPy, in one pass, with ``symbols`` (by name) for its symbols.

    SymEngine drops SymPy's assumptions (``q1`` is real); rebuilding sums and products with
    our symbols in place costs half of converting and then substituting them.  ``seen``
    (SymEngine subexpression -> SymPy) may be shared by the entries of one matrix: their
    sines, cosines and products of them repeat.  Sums and products are assembled in SymPy's
    canonical order directly where that is all SymPy would do
    (:func:`canonical_sum_or_product`), skipping a collection of like terms SymEngine has
    done already.
    """
    if seen is None:
        seen = {}
    done = seen.get(expr)
    if done is None:
        done = seen[expr] = _rebuilt(expr, symbols, seen)
    return done


def _rebuilt(expr: se.Basic, symbols: dict[str, sp.Symbol], seen: dict) -> sp.Expr:
    if isinstance(expr, se.Symbol):
        return symbols.get(expr.name) or sp.sympify(expr)
    for symengine_type, sympy_type in _REBUILT:
        if isinstance(expr, symengine_type):
            args = [sympy_from_symengine(a, symbols, seen) for a in expr.args]
            if sympy_type in (sp.Add, sp.Mul):
                fast = canonical_sum_or_product(sympy_type, args)
                if fast is not None:
                    return fast
            return sympy_type(*args)
    converted = sp.sympify(expr)
    if converted.free_symbols:
        return converted.xreplace({sp.Symbol(k): v for k, v in symbols.items()})
    return converted


def canonical_sum_or_product(kind: type, args: list[sp.Expr]) -> sp.Expr | None:
    """``kind(*args)`` (``kind`` is ``sp.Add`` or ``sp.Mul``) built without SymPy's
    constructor, when that constructor would only order the arguments: like terms and like
    factors already collected (SymEngine's output, or a renaming to distinct symbols), at most
    one finite non-zero number, no nested sum or product, no number times a sum (SymPy
    distributes it), no power of a number.  The number goes first unless it is the identity,
    the rest in ``Basic.compare`` order, as SymPy's constructors leave them; ``None`` when the
    constructor must decide."""
    numbers = [a for a in args if a.is_Number]
    rest = [a for a in args if not a.is_Number]
    if len(numbers) > 1 or not rest or any(isinstance(a, kind) for a in rest):
        return None
    if kind is sp.Mul and (
        (numbers and len(rest) == 1 and rest[0].is_Add)
        or any(a.is_Pow and a.base.is_Number for a in rest)
    ):
        return None
    if numbers:
        value = float(numbers[0])
        if value == 0.0 or not math.isfinite(value):
            return None
        if numbers[0] == kind.identity:
            numbers = []
    if len(numbers) + len(rest) < 2:
        return None
    rest.sort(key=_args_sortkey)
    return kind._from_args(numbers + rest, True)


def derivative_matrix(column: sp.MatrixBase, variables: Sequence[sp.Symbol]) -> sp.Matrix:
    """``column.jacobian(variables)`` (entry ``(i, j)`` = ``d column_i / d variables_j``),
    differentiated in SymEngine and brought back with our symbols."""
    symbols = {s.name: s for s in column.free_symbols}
    entries = [se.sympify(e) for e in column]
    return sp.Matrix(
        len(entries),
        len(variables),
        [
            sympy_from_symengine(se.diff(e, se.Symbol(v.name)), symbols)
            for e in entries
            for v in variables
        ],
    )


def contract_matrix(matrix: sp.MatrixBase, angle_sums: bool = True) -> sp.ImmutableMatrix:
    """:func:`contract_trig` applied to every entry."""
    return sp.ImmutableMatrix(matrix.applyfunc(lambda e: contract_trig(e, angle_sums)))


def contract_product(
    left: sp.MatrixBase, right: sp.MatrixBase, angle_sums: bool = True
) -> sp.ImmutableMatrix:
    """:func:`contract_matrix` of ``left * right``, the product formed in SymEngine.

    SymPy distributes every floating-point factor over the long sums of a chain's transform
    as it multiplies; SymEngine's product and expansion are the cheap part.  An entry longer
    than :data:`MAX_CONTRACTED_TERMS` keeps its SymPy product form.
    """
    product = symengine_matrix(left) * symengine_matrix(right)
    symbols = {s.name: s for s in left.free_symbols | right.free_symbols}

    def product_form(i: int, j: int) -> sp.Expr:
        return sum(left[i, k] * right[k, j] for k in range(left.cols))

    return contract_symengine(product, symbols, angle_sums, product_form)


def contract_symengine(
    matrix: se.DenseMatrix,
    symbols: dict[str, sp.Symbol],
    angle_sums: bool = True,
    fallback: Callable[[int, int], sp.Expr] | None = None,
) -> sp.ImmutableMatrix:
    """:func:`contract_matrix` of a SymEngine matrix: every entry expanded by SymEngine,
    brought back to SymPy once with ``symbols`` (by name), then contracted by TR10i when
    ``angle_sums``.  An entry longer than :data:`MAX_CONTRACTED_TERMS` terms is
    ``fallback(i, j)`` (its product form) when given, else its unread expansion."""
    entries, seen = [], {}
    for i in range(matrix.rows):
        for j in range(matrix.cols):
            expanded = se.expand(matrix[i, j])
            if fallback is not None and _longer_than(expanded, MAX_CONTRACTED_TERMS):
                entries.append(fallback(i, j))
                continue
            entry = sympy_from_symengine(expanded, symbols, seen)
            contracted = angle_sums and entry.has(sp.sin, sp.cos)
            entries.append(TR10i(entry) if contracted else entry)
    return sp.ImmutableMatrix(matrix.rows, matrix.cols, entries)


def _longer_than(expr: se.Basic, terms: int) -> bool:
    return isinstance(expr, se.Add) and len(expr.args) > terms


def symengine_matrix(matrix: sp.MatrixBase) -> se.DenseMatrix:
    """``matrix`` as a SymEngine matrix, entry by entry."""
    return se.DenseMatrix(matrix.rows, matrix.cols, [se.sympify(e) for e in matrix])


# Expanded sums longer than this stay in product form (readability is lost anyway).
MAX_CONTRACTED_TERMS = 400


@dataclass(frozen=True)
class _CircleVariables:
    """Polynomial stand-ins ``s_i = sin(q_i)``, ``c_i = cos(q_i)`` for a set of angles."""

    forward: dict[sp.Expr, sp.Symbol]
    back: dict[sp.Symbol, sp.Expr]
    pairs: tuple[tuple[sp.Symbol, sp.Symbol], ...]

    @classmethod
    def of(cls, angles: Sequence[sp.Symbol]) -> _CircleVariables:
        pairs = tuple((sp.Dummy(f"c_{q}"), sp.Dummy(f"s_{q}")) for q in angles)
        forward: dict[sp.Expr, sp.Symbol] = {}
        for q, (c, s) in zip(angles, pairs, strict=True):
            forward[sp.cos(q)], forward[sp.sin(q)] = c, s
        return cls(forward, {v: k for k, v in forward.items()}, pairs)

    def polynomial(self, expr: sp.Expr) -> sp.Expr:
        # expand_trig first: sin(q1 + q2) must become products of s_i, c_i.
        return sp.expand(sp.expand_trig(expr)).xreplace(self.forward)

    def reduce(self, polynomial: sp.Expr) -> sp.Expr:
        """The remainder of ``polynomial`` modulo ``c_i^2 + s_i^2 - 1`` (c_i^2 eliminated)."""
        pairs = [(c, s) for c, s in self.pairs if polynomial.has(c) or polynomial.has(s)]
        if not pairs:
            return polynomial
        ideal = [c**2 + s**2 - 1 for c, s in pairs]
        _, remainder = sp.reduced(polynomial, ideal, *[v for pair in pairs for v in pair])
        return remainder


def reduce_trig(expr: sp.Expr, angles: Sequence[sp.Symbol]) -> sp.Expr:
    """``expr`` with ``sin^2 + cos^2 = 1`` applied (as a remainder), then contracted."""
    circle = _CircleVariables.of(angles)
    return contract_trig(circle.reduce(circle.polynomial(expr)).xreplace(circle.back))


def exact_from_floats(expr: sp.Basic) -> sp.Basic:
    """Every float in ``expr`` as the exact rational of its shortest decimal (``3.393 ->
    3393/1000``), so that identities such as ``sin^2 + cos^2 = 1`` cancel exactly instead of
    leaving ``1e-16`` terms; small denominators also keep polynomial arithmetic fast (the exact
    rational of a double has a 2^54 denominator)."""
    return expr.xreplace({f: sp.Rational(repr(float(f))) for f in expr.atoms(sp.Float)})


def floats_from_exact(expr: sp.Basic) -> sp.Basic:
    """The inverse of :func:`exact_from_floats` for printing: every non-integer rational
    coefficient back as a float (integers stay integers)."""
    return expr.xreplace(
        {r: sp.Float(float(r)) for r in expr.atoms(sp.Rational) if not r.is_Integer}
    )
