"""Factored determinants of matrices polynomial in the sines and cosines of the joint angles.

Sines and cosines become ring variables ``s_i``, ``c_i`` (see
:class:`~symkin.derive.simplify._CircleVariables`); the determinant is a polynomial in them,
computed by division-free Laplace expansion with shared minors; its exact factors, reduced on
the circle ``c_i^2 + s_i^2 = 1`` and contracted back to trigonometric form, read as a
textbook writes them (SCARA: ``L1*L2*sin(q2)``).

What keeps it fast on generic arms (issue 15):

* no division: Bareiss' elimination divides polynomials in ten variables with 17-digit
  rational coefficients and did not finish in minutes on a 6R arm with generic twists;
* a long polynomial is reduced on the circle inside the ring (a pass over its terms) before
  anything else, and fully factored only when the result is short
  (:data:`MAX_FACTORED_TERMS`); otherwise only its monomial factors (``sin(q5)``) and numeric
  content split off;
* decimals become the rationals of their shortest decimal text (small denominators).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from itertools import combinations, product
from math import comb

import symengine as se
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from symkin.derive.budget import NUMERIC_FALLBACK, OVER_BUDGET, ClosedForm
from symkin.derive.simplify import _CircleVariables, contract_trig, exact_from_floats
from symkin.errors import BudgetWarning

# A polynomial (after reduction on the circle) with more terms than this is not factored in
# full: it would not read as a product anyway, and factor_list grows fast with its length.
MAX_FACTORED_TERMS = 300
# A determinant with more terms than this is reduced on the circle before it is factored.
REDUCE_FIRST_TERMS = 2000
# Past this :func:`expansion_size_estimate` the factored determinant is not attempted: the
# polynomial does not factor into anything readable, and the numeric fallback is cheaper.
MAX_EXPANSION_ESTIMATE = 5000


def expansion_size_estimate(matrix: sp.MatrixBase) -> int:
    """A cheap size measure of ``matrix``'s determinant (or Gram determinant): the product,
    over the ``rows`` columns with the longest entries, of each column's longest entry in
    terms (sines and cosines expanded by SymEngine, milliseconds).

    Every term of a Laplace expansion is a product of one entry per column, so this is the
    count of terms one expansion term can spread into.  Measured on 6R arms: catalogue robots
    and right-angle twists 24 to 960 (their determinants factor into a few short sines and
    cosines), generic twists about 25,000 (an 8,000-character polynomial that does not factor,
    found after 7 s of CPU).
    """
    longest = sorted(
        max(_term_count(matrix[i, j]) for i in range(matrix.rows)) for j in range(matrix.cols)
    )
    size = 1
    for terms in longest[-matrix.rows :]:
        size *= max(terms, 1)
    return size


def too_large_to_factor(quantity: str, robot: str, matrix: sp.MatrixBase) -> ClosedForm | None:
    """The fallback of a determinant past :data:`MAX_EXPANSION_ESTIMATE` (one
    :class:`~symkin.errors.BudgetWarning` saying so), or None when it is worth attempting."""
    size = expansion_size_estimate(matrix)
    if size <= MAX_EXPANSION_ESTIMATE:
        return None
    warning = BudgetWarning(
        f"{robot}: the {quantity} was not attempted: its expansion measures {size:,} "
        f"(more than {MAX_EXPANSION_ESTIMATE:,}; a determinant this long does not factor into "
        f"a readable form); {NUMERIC_FALLBACK}"
    )
    warnings.warn(warning, stacklevel=5)
    return ClosedForm(quantity, OVER_BUDGET, None, warning.message_for({}))


def _term_count(expr: sp.Expr) -> int:
    expanded = se.expand(se.sympify(expr))
    return len(expanded.args) if isinstance(expanded, se.Add) else int(expanded != 0)


def factored_determinant(matrix: sp.MatrixBase, angles: Sequence[sp.Symbol]) -> sp.Expr:
    """Determinant of a square matrix polynomial in ``sin``/``cos`` of ``angles``, factored.

    Exact on the polynomial ring (SymPy's ``DomainMatrix``); decimals in the matrix are made
    exact rationals for the ring and printed as floats again at the end.
    """
    if not matrix.is_square:
        raise ValueError("determinant of a non-square matrix")
    return _factored(matrix, angles, determinant_by_minors)


def factored_gram_determinant(matrix: sp.MatrixBase, angles: Sequence[sp.Symbol]) -> sp.Expr:
    """``det(J J^T)`` of a wide matrix ``J`` (rows <= columns), factored.

    By the Cauchy-Binet formula it is the sum of the squared determinants of the square
    submatrices made of ``rows`` of the columns (7 for a 7-joint arm's 6 x 7 Jacobian), each
    computed like :func:`factored_determinant`'s; no product ``J J^T`` is ever expanded.
    """
    return _factored(matrix, angles, _gram_by_cauchy_binet)


def _gram_by_cauchy_binet(matrix: DomainMatrix) -> object:
    rows, columns = matrix.shape
    total = matrix.domain.zero
    for chosen in combinations(range(columns), rows):
        minor = determinant_by_minors(matrix.extract(list(range(rows)), list(chosen)))
        total += minor * minor
    return total


def _factored(
    matrix: sp.MatrixBase, angles: Sequence[sp.Symbol], determinant: Callable[..., object]
) -> sp.Expr:
    circle = _CircleVariables.of(angles)
    polynomial_matrix = sp.Matrix(matrix).applyfunc(circle.polynomial)
    inexact = polynomial_matrix.has(sp.Float)
    if inexact:
        polynomial_matrix = polynomial_matrix.applyfunc(_rational_coefficients)
    domain_matrix = DomainMatrix.from_Matrix(polynomial_matrix)
    value = _rational_polynomial(domain_matrix.domain, determinant(domain_matrix))
    if isinstance(value, sp.Expr):
        return sp.nfloat(value, 15) if inexact else value
    return _readable_factors(circle, value, inexact)


def _rational_polynomial(domain: object, value: object) -> object:
    """``value`` as a polynomial over the integers or rationals (irrational constants such as
    ``sqrt(3)`` of a 60-degree twist become generators), or a SymPy number if it is one."""
    if domain.is_PolynomialRing and (domain.domain.is_ZZ or domain.domain.is_QQ):
        return value
    expr = domain.to_sympy(value)
    if expr.is_number:
        return expr
    polynomial = sp.Poly(expr)
    ring, *_ = sp.ring(polynomial.gens, polynomial.domain)
    return ring.from_dict(polynomial.as_dict(native=True))


def determinant_by_minors(matrix: DomainMatrix) -> object:
    """Laplace expansion along the columns with every minor computed once (division free).

    ``minors[rows]`` is the determinant of the rows in the bit mask ``rows`` and the last
    ``len(rows)`` columns; an n x n matrix needs at most ``n 2^(n-1)`` ring products (192 for
    n = 6) and no division.
    """
    entries = matrix.to_list()
    n = len(entries)
    minors = {0: matrix.domain.one}
    for size in range(1, n + 1):
        column = n - size
        for rows in (mask for mask in range(1 << n) if mask.bit_count() == size):
            total, sign = matrix.domain.zero, 1
            for i in (i for i in range(n) if rows >> i & 1):
                if entries[i][column]:
                    total += sign * entries[i][column] * minors[rows & ~(1 << i)]
                sign = -sign
            minors[rows] = total
    return minors[(1 << n) - 1]


def _readable_factors(circle: _CircleVariables, determinant: sp.Expr, inexact: bool) -> sp.Expr:
    """Exact factors of a ring polynomial, each reduced on the circle and contracted.

    Factoring comes before the reduction when the polynomial is short: the remainder of a
    product is not the product of the remainders, and the factors a reader expects (PUMA:
    ``a3 sin(q3) + d4 cos(q3)``) are those of the plain polynomial.  Factors constant on the
    circle (``s_1^2 + c_1^2``) fold into the coefficient.  ``inexact``: rounding noise is
    dropped from each reduced factor, and the numeric coefficient multiplies the one remaining
    sum (``0.3*(2*s + c)`` would show two meaningless roundings).
    """
    ring = determinant.ring
    pairs = _ring_pairs(circle, ring)
    if not determinant:
        return sp.Integer(0)
    if len(determinant) > REDUCE_FIRST_TERMS:
        determinant = _reduce_on_circle(determinant, pairs)
    coefficient, factors = _cheap_or_full_factors(determinant)
    value = ring.domain.to_sympy(coefficient)
    readable: list[tuple[sp.Expr, int]] = []
    for factor, multiplicity in factors:
        reduced = _reduce_on_circle(factor, pairs)
        reduced = _chop(reduced) if inexact else reduced
        if reduced.is_ground:
            value *= (
                ring.domain.to_sympy(reduced.LC if reduced else ring.domain.zero) ** multiplicity
            )
        else:
            readable.append((reduced.as_expr(), multiplicity))
    sums = [i for i, (f, m) in enumerate(readable) if f.is_Add and m == 1]
    if inexact and len(sums) == 1:
        factor, _ = readable[sums[0]]
        readable[sums[0]], value = (sp.expand(value * factor), 1), sp.Integer(1)
    result = value
    for factor, multiplicity in readable:
        trigonometric = factor.xreplace(circle.back)
        if len(sp.Add.make_args(factor)) <= MAX_FACTORED_TERMS:
            # Angle-sum contraction is quadratic in the terms; a longer factor does not read
            # as a formula anyway (a generic 6R arm's: 8,000 characters, 30 s of TR10i).
            trigonometric = contract_trig(trigonometric)
        result *= trigonometric**multiplicity
    return sp.nfloat(result, 15) if inexact else result


def _ring_pairs(circle: _CircleVariables, ring: object) -> list[tuple[int, int]]:
    """Indices ``(c_i, s_i)`` of each circle pair among the ring's generators."""
    index = {symbol: k for k, symbol in enumerate(ring.symbols)}
    return [(index[c], index[s]) for c, s in circle.pairs if c in index and s in index]


def _reduce_on_circle(polynomial: object, pairs: list[tuple[int, int]]) -> object:
    """The remainder modulo every ``c_i^2 + s_i^2 - 1``: ``c_i^(2k+r) -> c_i^r (1 - s_i^2)^k``.

    One pass over the terms (the normal form for the lexicographic order with ``c_i`` first),
    instead of SymPy's general multivariate division, which takes tens of seconds on the
    16,000-term determinant of a generic 6R arm.
    """
    ring = polynomial.ring
    result: dict[tuple[int, ...], object] = {}
    for monomial, coefficient in polynomial.items():
        exponents = list(monomial)
        expansions = []
        for c, s in pairs:
            half, exponents[c] = divmod(exponents[c], 2)
            expansions.append([(s, 2 * j, (-1) ** j * comb(half, j)) for j in range(half + 1)])
        for choice in product(*expansions):
            term = list(exponents)
            value = coefficient
            for s, power, weight in choice:
                term[s] += power
                value = value * weight
            key = tuple(term)
            result[key] = result.get(key, ring.domain.zero) + value
    return ring.from_dict({m: v for m, v in result.items() if v})


def _cheap_or_full_factors(polynomial: object) -> tuple[object, list[tuple[object, int]]]:
    """``factor_list`` of a short polynomial; of a long one only its monomial factors and
    numeric content, the rest left as one factor (the cheap test that factoring can pay)."""
    if len(polynomial) <= MAX_FACTORED_TERMS:
        return polynomial.factor_list()
    ring = polynomial.ring
    smallest = [min(exponents) for exponents in zip(*polynomial.monoms(), strict=True)]
    rest = ring.from_dict(
        {
            tuple(e - m for e, m in zip(monomial, smallest, strict=True)): v
            for monomial, v in polynomial.items()
        }
    )
    content, primitive = rest.primitive()
    factors = [(ring.gens[k], e) for k, e in enumerate(smallest) if e]
    return content, [*factors, (primitive, 1)]


def _chop(polynomial: object, relative: float = 1e-12) -> object:
    """Drop terms whose coefficient is rounding noise next to the largest one."""
    if not polynomial:
        return polynomial
    size = polynomial.ring.domain.to_sympy
    largest = max(abs(float(size(v))) for v in polynomial.values())
    return polynomial.ring.from_dict(
        {m: v for m, v in polynomial.items() if abs(float(size(v))) > relative * largest}
    )


def _rational_coefficients(expr: sp.Expr) -> sp.Expr:
    """Every numeric constant (``0.3``, ``sqrt(3)/2``) as the exact rational of its shortest
    decimal (``0.3 -> 3/10``): small denominators keep the ring arithmetic fast, where the
    exact rational of the double has a 2^54 denominator."""
    return exact_from_floats(sp.nfloat(expr, 17))


def factor_trig(expr: sp.Expr, angles: Sequence[sp.Symbol]) -> sp.Expr:
    """Factor ``expr``, polynomial in ``sin``/``cos`` of ``angles``, into readable factors."""
    return factored_determinant(sp.Matrix([[expr]]), angles)
