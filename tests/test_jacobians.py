"""Jacobians, their determinants, singularities and manipulability against independent values.

The reference Jacobian is ``tests/numeric_dh.py``'s numerical derivative of the pose (linear
rows ``dp/dq``, angular rows ``vee(dR/dq R^T)``), never the cross-product column formula;
determinants are NumPy's of that Jacobian; closed forms are typed in from textbooks.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp

from numeric_dh import (
    ALL_ROBOTS,
    CATALOGUE,
    euler_zyx,
    function,
    model,
    reference,
    robot,
    samples,
    task_rows,
    wrap,
)
from symkin.derive import Model, jacobians, simplify
from symkin.derive.kinematics import kinematics_from_robot
from symkin.errors import BudgetWarning, SymkinError

FD_TOL = 1e-6  # central differences, h = 1e-6: truncation ~1e-12, rounding ~1e-10
# Square task Jacobians.  The hand-written robots are left out of the determinant tests: with
# decimal constants in the DH table symkin's determinant takes 20 s to more than 10 minutes.
SQUARE = tuple(n for n in CATALOGUE if n != "panda")
# Derivations that take tens of seconds (Panda) or minutes (hand_standard: exact constants of
# its base and tool rotations multiply out) are checked on the other robots.
CHEAP = (*SQUARE, "hand_modified")


def exact_jacobian(name: str, q: np.ndarray) -> np.ndarray:
    """Reference geometric Jacobian by the complex step (accurate to rounding)."""
    return reference(name).jacobian(q, method="complex")


# ---------------------------------------------------------------------------------------------
# The reference itself: the two differentiation schemes agree
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["puma560", "hand_standard", "hand_modified"])
def test_reference_schemes_agree(name: str) -> None:
    for q in samples(name, 10, 2):
        np.testing.assert_allclose(
            reference(name).jacobian(q), exact_jacobian(name, q), rtol=0, atol=FD_TOL
        )


# ---------------------------------------------------------------------------------------------
# Geometric, tool-frame, position and Euler-angle Jacobians
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_geometric_jacobian_matches_finite_differences(name: str) -> None:
    jacobian = function(name, model(name).geometric_jacobian)
    assert model(name).geometric_jacobian.shape == (6, robot(name).dof)
    for q in samples(name, 11, 3):
        np.testing.assert_allclose(jacobian(q), reference(name).jacobian(q), rtol=0, atol=FD_TOL)


def test_jacobian_entries_too_long_to_contract_keep_their_product_form(monkeypatch) -> None:
    """Past MAX_CONTRACTED_TERMS an entry is not expanded for reading: the column's product
    ``R (e_z x p_local)`` stays as it is, with the same values."""
    monkeypatch.setattr(simplify, "MAX_CONTRACTED_TERMS", 3)
    kinematics = kinematics_from_robot(robot("puma560"))
    result = jacobians.geometric_jacobian(robot("puma560"), kinematics)
    nodes = (node for e in result for node in sp.preorder_traversal(e))
    assert any(node.is_Mul and any(f.is_Add for f in node.args) for node in nodes)
    jacobian = function("puma560", result)
    for q in samples("puma560", 13, 3):
        np.testing.assert_allclose(jacobian(q), reference("puma560").jacobian(q), atol=FD_TOL)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_position_jacobian_matches_finite_differences(name: str) -> None:
    jacobian = function(name, model(name).position_jacobian)
    for q in samples(name, 12, 3):
        expected = reference(name).jacobian(q)[:3]
        np.testing.assert_allclose(jacobian(q), expected, rtol=0, atol=FD_TOL)


@pytest.mark.slow
@pytest.mark.parametrize("name", CHEAP)
def test_tool_frame_jacobian_is_rotated_base_jacobian(name: str) -> None:
    jacobian = function(name, model(name).geometric_jacobian_tool)
    for q in samples(name, 13, 3):
        R = reference(name).fk(q)[:3, :3]
        rotate = np.block([[R.T, np.zeros((3, 3))], [np.zeros((3, 3)), R.T]])
        expected = rotate @ reference(name).jacobian(q)
        np.testing.assert_allclose(jacobian(q), expected, rtol=0, atol=FD_TOL)


def _pose_vector(name: str, q: np.ndarray) -> np.ndarray:
    T = reference(name).fk(q)
    return np.concatenate([T[:3, 3], euler_zyx(T[:3, :3])])


# The hand-written robots take 10 s and more here (atan2 derivatives cancelled entry by entry).
@pytest.mark.parametrize(
    "name", ["planar_2r", "planar_3r", "scara", "rpr", "cylindrical_rtt_wrist"]
)
def test_euler_zyx_jacobian_matches_finite_differences(name: str) -> None:
    jacobian = function(name, model(name).euler_zyx_jacobian)
    h = 1e-6
    for q in samples(name, 14, 3):
        assert abs(np.cos(euler_zyx(reference(name).fk(q)[:3, :3])[1])) > 0.05, "gimbal lock"
        columns = []
        for k in range(len(q)):
            step = np.zeros(len(q))
            step[k] = h
            delta = _pose_vector(name, q + step) - _pose_vector(name, q - step)
            delta[3:] = wrap(delta[3:])
            columns.append(delta / (2 * h))
        np.testing.assert_allclose(jacobian(q), np.array(columns).T, rtol=0, atol=FD_TOL)


@pytest.mark.parametrize("name", CHEAP)
def test_jacobian_derivative_matches_time_differences(name: str) -> None:
    m = model(name)
    rate = function(name, m.geometric_jacobian_derivative, m.dq)
    rng = np.random.default_rng(15)
    h = 1e-5
    for q in samples(name, 16, 2):
        dq = rng.uniform(-1.0, 1.0, len(q))
        expected = (exact_jacobian(name, q + h * dq) - exact_jacobian(name, q - h * dq)) / (2 * h)
        np.testing.assert_allclose(rate(q, dq), expected, rtol=0, atol=FD_TOL)


# ---------------------------------------------------------------------------------------------
# Task rows
# ---------------------------------------------------------------------------------------------

EXPECTED_TASK_ROWS = {
    "planar_2r": ("x", "y"),
    "scara": ("x", "y", "z"),
    "planar_3r": ("x", "y", "wz"),
    "rpr": ("x", "y", "z"),
    "cylindrical_rtt_wrist": ("x", "y", "z", "wx", "wy", "wz"),
    "puma560": ("x", "y", "z", "wx", "wy", "wz"),
    "stanford": ("x", "y", "z", "wx", "wy", "wz"),
    "ur5": ("x", "y", "z", "wx", "wy", "wz"),
    # n = 7: all six non-zero rows, in the order x, y, z, wz, wx, wy.
    "panda": ("x", "y", "z", "wz", "wx", "wy"),
    "hand_standard": ("x", "y", "z", "wz"),
    "hand_modified": ("x", "y", "z", "wz"),
}


def test_every_robot_has_expected_task_rows() -> None:
    assert set(EXPECTED_TASK_ROWS) == set(ALL_ROBOTS)
    assert set(CATALOGUE) <= set(EXPECTED_TASK_ROWS)


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_task_rows(name: str) -> None:
    m = model(name)
    assert m.task_rows == EXPECTED_TASK_ROWS[name]
    jacobian = function(name, m.task_jacobian())
    for q in samples(name, 17, 2):
        expected = task_rows(reference(name).jacobian(q), m.task_rows)
        np.testing.assert_allclose(jacobian(q), expected, rtol=0, atol=FD_TOL)


def test_explicit_task_rows_are_taken_in_the_given_order() -> None:
    m = model("planar_3r")
    jacobian = function("planar_3r", m.task_jacobian(("wz", "x", "y")))
    for q in samples("planar_3r", 18, 2):
        expected = task_rows(reference("planar_3r").jacobian(q), ("wz", "x", "y"))
        np.testing.assert_allclose(jacobian(q), expected, rtol=0, atol=FD_TOL)
    # Another choice of rows changes the determinant only by the row permutation's sign.
    difference = sp.simplify(m.determinant(("wz", "x", "y")) - m.determinant(("x", "y", "wz")))
    assert difference == 0


def test_unknown_or_repeated_task_rows_are_rejected() -> None:
    m = model("planar_2r")
    with pytest.raises(SymkinError, match="vz"):
        m.task_jacobian(("x", "vz"))
    with pytest.raises(SymkinError, match="repeat"):
        m.determinant(("x", "x"))


def test_panda_task_jacobian_is_not_square() -> None:
    m = model("panda")
    assert m.task_jacobian().shape == (6, 7)
    assert m.determinant() is None
    assert m.singular_configurations() == ()
    with pytest.raises(ValueError, match="square"):
        m.inverse_task_jacobian()


def test_too_few_rows_give_no_determinant() -> None:
    assert model("scara").determinant(("x", "y")) is None


# ---------------------------------------------------------------------------------------------
# Determinants and singular configurations
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", SQUARE)
def test_determinant_matches_numpy(name: str) -> None:
    m = model(name)
    determinant = m.determinant()
    assert determinant is not None
    value = function(name, determinant)
    for q in samples(name, 19, 4):
        expected = np.linalg.det(task_rows(exact_jacobian(name, q), m.task_rows))
        assert abs(expected) > 1e-6, "the random sample should not be singular"
        assert float(value(q)) == pytest.approx(expected, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("name", ["scara", "planar_2r"])
def test_textbook_determinant(name: str) -> None:
    L1, L2 = sp.symbols("L1 L2", real=True)
    q2 = model(name).q[1]
    assert sp.simplify(model(name).determinant() - L1 * L2 * sp.sin(q2)) == 0


def test_determinant_is_factored() -> None:
    # SCARA: exactly the product L1 * L2 * sin(q2), not an expanded sum.
    determinant = model("scara").determinant()
    assert isinstance(determinant, sp.Mul)
    assert set(determinant.args) == {*sp.symbols("L1 L2", real=True), sp.sin(model("scara").q[1])}


def _bisect(f, low: float, high: float) -> float:
    f_low = f(low)
    for _ in range(200):
        middle = 0.5 * (low + high)
        f_middle = f(middle)
        if f_middle == 0.0:
            return middle
        if (f_middle > 0) == (f_low > 0):
            low, f_low = middle, f_middle
        else:
            high = middle
        if high - low < 1e-15:
            break
    return 0.5 * (low + high)


def _solve_condition(name: str, condition: sp.Eq, q: np.ndarray) -> np.ndarray | None:
    """``q`` with one joint changed so that ``condition`` holds, or None if not found."""
    m = model(name)
    lhs = condition.lhs - condition.rhs
    if condition.lhs in m.q and not condition.rhs.free_symbols:
        q = q.copy()
        q[m.q.index(condition.lhs)] = float(condition.rhs)
        return q
    residual = function(name, lhs)
    for k, symbol in enumerate(m.q):
        if symbol not in lhs.free_symbols:
            continue

        def along(value: float, k: int = k) -> float:
            trial = q.copy()
            trial[k] = value
            return float(residual(trial))

        grid = np.linspace(-np.pi, np.pi, 721)
        values = [along(v) for v in grid]
        for low, high, f_low, f_high in zip(grid, grid[1:], values, values[1:], strict=False):
            if f_low * f_high < 0:
                solved = q.copy()
                solved[k] = _bisect(along, low, high)
                return solved
    return None


@pytest.mark.parametrize("name", SQUARE)
def test_singular_configurations_make_the_jacobian_singular(name: str) -> None:
    m = model(name)
    conditions = m.singular_configurations()
    assert conditions, "a square task Jacobian of an arm has singularities"
    n = robot(name).dof
    rng = np.random.default_rng(20)
    for condition in conditions:
        assert isinstance(condition, sp.Eq)
        assert condition.free_symbols & set(m.q)
        for _ in range(2):
            q = _solve_condition(name, condition, samples(name, int(rng.integers(1 << 30)), 1)[0])
            assert q is not None, f"cannot satisfy {condition}"
            jacobian = task_rows(exact_jacobian(name, q), m.task_rows)
            assert abs(np.linalg.det(jacobian)) < 1e-9, f"{condition} at q = {q}"
            assert np.linalg.matrix_rank(jacobian, tol=1e-8) < n, f"{condition} at q = {q}"


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("planar_2r", {"q2": [0.0, np.pi]}),
        ("scara", {"q2": [0.0, np.pi]}),
        ("planar_3r", {"q2": [-np.pi / 2, np.pi / 2]}),
    ],
)
def test_solved_singularities_of_planar_arms(name: str, expected: dict[str, list[float]]) -> None:
    # Elbow stretched or folded: q2 = 0, pi (planar 3R: the -90 deg offset shifts it by pi/2).
    found: dict[str, list[float]] = {}
    for condition in model(name).singular_configurations():
        found.setdefault(str(condition.lhs), []).append(float(condition.rhs))
    assert {k: sorted(v) for k, v in found.items()} == expected


# ---------------------------------------------------------------------------------------------
# Manipulability and the inverse
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", SQUARE)
def test_manipulability_of_square_jacobians(name: str) -> None:
    m = model(name)
    value = function(name, m.manipulability())
    for q in samples(name, 21, 3):
        jacobian = task_rows(exact_jacobian(name, q), m.task_rows)
        expected = np.sqrt(np.linalg.det(jacobian @ jacobian.T))
        assert float(value(q)) == pytest.approx(expected, rel=1e-8)
        assert float(value(q)) == pytest.approx(abs(np.linalg.det(jacobian)), rel=1e-8)


@pytest.mark.parametrize("name", ["planar_2r", "scara"])
def test_manipulability_of_non_square_rows(name: str) -> None:
    # Fewer rows than joints (here the x row alone) is the non-square, redundant case.
    m = model(name)
    rows = ("x", "y") if name == "scara" else ("x",)
    value = function(name, m.manipulability(rows))
    for q in samples(name, 22, 3):
        jacobian = task_rows(exact_jacobian(name, q), rows)
        expected = np.sqrt(np.linalg.det(jacobian @ jacobian.T))
        assert float(value(q)) == pytest.approx(expected, rel=1e-8)


@pytest.mark.parametrize("name", ["scara", "planar_2r", "planar_3r"])
def test_inverse_task_jacobian(name: str) -> None:
    m = model(name)
    inverse = function(name, m.inverse_task_jacobian())
    n = robot(name).dof
    for q in samples(name, 23, 4):
        jacobian = task_rows(exact_jacobian(name, q), m.task_rows)
        np.testing.assert_allclose(inverse(q) @ jacobian, np.eye(n), rtol=0, atol=1e-9)
        np.testing.assert_allclose(jacobian @ inverse(q), np.eye(n), rtol=0, atol=1e-9)


@pytest.mark.slow
def test_manipulability_of_redundant_panda_finishes_or_falls_back() -> None:
    """The 7-DOF Panda's symbolic sqrt(det(J J^T)) (Cauchy-Binet over the middle-frame
    Jacobian) either comes within a 5 s budget and equals the reference, or stops at the
    budget with its status and one warning; it used to run for more than 25 minutes."""
    m = Model(robot("panda"), budget=5.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        form = m.manipulability_form()
    if not form.found:
        assert (form.status, form.value) == ("over budget", None)
        assert [w.category for w in caught] == [BudgetWarning]
        assert "panda" in str(caught[0].message) and "5 s" in str(caught[0].message)
        return
    value = function("panda", form.value)
    for q in samples("panda", 24, 3):
        jacobian = exact_jacobian("panda", q)
        expected = np.sqrt(np.linalg.det(jacobian @ jacobian.T))
        assert float(value(q)) == pytest.approx(expected, rel=1e-8)
