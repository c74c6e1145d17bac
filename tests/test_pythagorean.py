"""No ``sin(x)**2`` and ``cos(x)**2`` of one argument in one sum of a printed formula (issue 21).

The detector below is written here, independently of :mod:`symkin.derive.pythagorean`; values
are checked at random points against the unfolded expressions (the fold is an identity).
"""

from __future__ import annotations

import random
import warnings

import pytest
import sympy as sp

from symkin import derive, load_robot
from symkin.derive.pythagorean import fold_matrix, fold_pythagorean
from symkin.io.robot_file import catalogue_names
from symkin.kernels.document import DEFAULT_SECTIONS, document_content

q1, q2, a, b = sp.symbols("q1 q2 a b")


def squares(sum_: sp.Add, function) -> set:
    out = set()
    for term in sum_.args:
        for factor in sp.Mul.make_args(term):
            if (
                factor.is_Pow
                and isinstance(factor.base, function)
                and factor.exp.is_Integer
                and factor.exp >= 2
            ):
                out.add(factor.base.args[0])
    return out


def pythagorean_sums(expr) -> list:
    """Every sum in ``expr`` holding a power >= 2 of both sin(x) and cos(x) for one x."""
    found = []
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Add) and squares(node, sp.sin) & squares(node, sp.cos):
            found.append(node)
    return found


def expressions(value) -> list:
    """Every SymPy expression inside the document content (dataclasses, tuples, matrices)."""
    if isinstance(value, sp.MatrixBase):
        return list(value)
    if isinstance(value, sp.Eq):
        return [value.lhs, value.rhs]
    if isinstance(value, sp.Basic):
        return [value]
    if isinstance(value, tuple | list):
        return [e for v in value for e in expressions(v)]
    if hasattr(value, "__dataclass_fields__"):
        return [
            e
            for name in value.__dataclass_fields__
            if name != "model"
            for e in expressions(getattr(value, name))
        ]
    return []


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        (a * sp.sin(q1) ** 2 * sp.cos(q2) + a * sp.cos(q1) ** 2 * sp.cos(q2), a * sp.cos(q2)),
        (sp.atan2(0, sp.sqrt(sp.sin(q1 + q2) ** 2 + sp.cos(q1 + q2) ** 2)), sp.Integer(0)),
        (a * sp.sin(q1) ** 2 + b * sp.cos(q1) ** 2, None),  # unequal: one square left
        (sp.sin(q1) ** 4 + 2 * sp.sin(q1) ** 2 * sp.cos(q1) ** 2 + sp.cos(q1) ** 4, None),
    ],
)
def test_fold(expr, expected) -> None:
    folded = fold_pythagorean(expr)
    assert not pythagorean_sums(folded)
    if expected is not None:
        assert folded == expected
    for _ in range(5):
        point = {s: random.uniform(-3, 3) for s in (q1, q2, a, b)}
        assert float(folded.subs(point)) == pytest.approx(float(expr.subs(point)), abs=1e-12)


def test_puma_jacobian_entries() -> None:
    """The issue's example: J(3,2) of the PUMA was a2 sin^2(q1) cos(q2) + a2 cos^2(q1) cos(q2)
    + ...; by hand (z row of z_1 x (p - o_1)) it is a2 cos q2 + a3 cos(q2+q3) - d4 sin(q2+q3)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = derive(load_robot("puma560"))
    J = model.geometric_jacobian
    by_name = {s.name: s for s in J.free_symbols}
    a2, a3, d4, q2_, q3 = (by_name[n] for n in ("a2", "a3", "d4", "q2", "q3"))
    hand = a2 * sp.cos(q2_) + a3 * sp.cos(q2_ + q3) - d4 * sp.sin(q2_ + q3)
    assert sp.expand(J[2, 1] - hand) == 0
    assert sp.expand(J[2, 2] - (hand - a2 * sp.cos(q2_))) == 0
    assert not pythagorean_sums(J)


@pytest.mark.slow
@pytest.mark.parametrize("name", catalogue_names())
def test_no_pythagorean_sum_in_printed_formulas(name: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = derive(load_robot(name))
        sections = list(DEFAULT_SECTIONS) + (["dynamics"] if model.robot.dof <= 3 else [])
        content = document_content(model, sections)
    shown = expressions(content)
    assert shown
    offending = [s for e in shown for s in pythagorean_sums(e)]
    assert not offending, f"{name}: {offending[:3]}"


def test_fold_matrix_keeps_values() -> None:
    M = sp.Matrix([[a * sp.sin(q1) ** 2 + a * sp.cos(q1) ** 2 + b, sp.sin(q2)]])
    assert fold_matrix(M) == sp.ImmutableMatrix([[a + b, sp.sin(q2)]])
