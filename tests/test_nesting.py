"""Expanded sums nested joint by joint (derive/nesting.py) and the readable forms that use it.

Expected values: products multiplied by hand (the RPR arm, small sums), SymPy's ``expand`` for
the value of every nested entry, and SymPy's own constructors for the shape.
"""

from __future__ import annotations

import sympy as sp

from symkin import derive, load_robot
from symkin.derive.nesting import nest_by_joints, nest_matrix

q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
a, b, d = sp.symbols("a b d", real=True)
c1, s1, c2, s2, c3, s3 = sp.cos(q1), sp.sin(q1), sp.cos(q2), sp.sin(q2), sp.cos(q3), sp.sin(q3)


def test_terms_are_grouped_base_joint_outermost():
    expr = sp.expand(a * c1 * c2 + b * c1 * s2 * c3 + d * s1 + a * s1 * s3 + b)
    nested = nest_by_joints(expr, (q1, q2, q3))
    expected = c1 * (a * c2 + b * c3 * s2) + s1 * (d + a * s3) + b
    assert sp.srepr(nested) == sp.srepr(expected)


def test_prismatic_variable_is_a_joint_factor():
    # q2 of a prismatic joint groups like a sine or cosine: s1 (q2 + a s3), not q2 s1 + a s1 s3.
    expr = sp.expand(s1 * (q2 + a * s3) - c1 * d)
    assert nest_by_joints(expr, (q1, q2, q3)) == s1 * (q2 + a * s3) - c1 * d


def test_value_is_the_expanded_sum():
    expr = sp.expand((a * c1 + s1 * (b + c2)) * (c3 - d * s2 * s3 + q2) * (sp.Float(0.107) + s1))
    nested = nest_by_joints(expr, (q1, q2, q3))
    assert sp.expand(nested - expr) == 0
    assert sp.count_ops(nested) < sp.count_ops(expr)


def test_non_sums_come_back_unchanged():
    assert nest_by_joints(a * c1 * s2, (q1, q2)) == a * c1 * s2
    assert nest_by_joints(sp.Integer(3), (q1,)) == 3
    assert nest_matrix(sp.Matrix([[c1, 0]]), (q1,)) == sp.ImmutableMatrix([[c1, 0]])


def test_rpr_readable_pose_is_the_hand_product():
    """A1 = Rz(q1) Rx(90), A2 = Rz(90) Tz(q2) Rx(90), A3 = Rz(q3) Tx(L3) multiplied by hand:
    p = ((q2 + L3 s3) s1, -(q2 + L3 s3) c1, L3 c3), the shape the nesting gives."""
    m = derive(load_robot("rpr"))
    (L3,) = (s for s in m.forward_kinematics.free_symbols if s.name == "L3")
    p1, p2, p3 = m.q
    reach = p2 + L3 * sp.sin(p3)
    assert m.forward_kinematics[0, 3] == reach * sp.sin(p1)
    assert m.forward_kinematics[1, 3] == -reach * sp.cos(p1)
    assert m.forward_kinematics[2, 3] == L3 * sp.cos(p3)


def test_panda_readable_forms_are_nested_and_shorter_than_expanded():
    m = derive(load_robot("panda"))
    entries = [*m.forward_kinematics, *m.geometric_jacobian]
    expanded = [sp.expand(e) for e in entries]
    assert sp.count_ops(entries) < 0.6 * sp.count_ops(expanded)
    # The outermost factors are joint 1's: cos(q1)*(...) + sin(q1)*(...) for the tool's x.
    x = m.forward_kinematics[0, 3]
    assert {t.as_independent(m.q[0])[1] for t in x.args} == {sp.cos(m.q[0]), sp.sin(m.q[0])}
