"""The readable (angle-sum contracted) forward kinematics and Jacobian under the budget, with
the product form as fallback (issue 15).

Expected values are independent of symkin's derivations: the naive NumPy DH product of
tests/numeric_dh.py and its central-difference Jacobian; the catalogue's angle sums are read
off the arms' parallel axes by hand (SCARA: joints 1 and 2 vertical; PUMA: joints 2 and 3).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from numeric_dh import NumericRobot
from symkin.cli import main
from symkin.derive import Model
from symkin.derive.kinematics import has_parallel_revolute_axes
from symkin.derive.readable import INLINE_TERMS, MAX_TERMS, expanded_size, readable_form
from symkin.errors import BudgetWarning

DATA = Path(__file__).parent / "data"
ARM = DATA / "random_8r_right_1.toml"


def _arm() -> symkin.Robot:
    return symkin.robot_from_toml(ARM.read_text(), ARM.name)


def test_tiny_budget_falls_back_to_the_product_form_with_one_warning() -> None:
    rob = _arm()
    assert expanded_size(rob) > INLINE_TERMS  # else the contraction runs without a deadline
    m = Model(rob, budget=1e-6)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fk, jacobian = m.forward_kinematics, m.geometric_jacobian
        m.kinematics.frame_transforms  # noqa: B018 - later reads must not warn again
    assert [w.category for w in caught] == [BudgetWarning]
    message = str(caught[0].message)
    assert rob.name in message and "angle-sum contraction" in message
    assert "budget of 1e-06 s" in message and "product form" in message
    assert not m.kinematics.simplified
    reference = NumericRobot.from_robot(rob)
    q = m.q
    value_of_fk = sp.lambdify(q, fk, "numpy")
    value_of_jacobian = sp.lambdify(q, jacobian, "numpy")
    for angles in np.random.default_rng(11).uniform(-np.pi, np.pi, size=(4, rob.dof)):
        np.testing.assert_allclose(value_of_fk(*angles), reference.fk(angles), atol=1e-12)
        expected = reference.jacobian(angles)
        np.testing.assert_allclose(value_of_jacobian(*angles), expected, atol=1e-7)


@pytest.mark.parametrize(
    ("name", "angle_sum"), [("scara", "sin(q1 + q2)"), ("puma560", "sin(q2 + q3)")]
)
def test_catalogue_robots_keep_their_contracted_form_whatever_the_budget(
    name: str, angle_sum: str
) -> None:
    """Below the size measure's threshold no deadline applies: the readable form never
    depends on the budget or on the machine's speed."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", BudgetWarning)
        m = Model(symkin.load_robot(name), budget=1e-6)
        fk, jacobian = m.forward_kinematics, m.geometric_jacobian
    expected = sp.sympify(
        angle_sum, locals={f"q{i}": sp.Symbol(f"q{i}", real=True) for i in (1, 2, 3)}
    )
    assert m.kinematics.simplified
    assert fk.has(expected) and jacobian.has(expected)


@pytest.mark.slow
def test_cli_over_budget_prints_one_line_and_exits_0(capsys: pytest.CaptureFixture[str]) -> None:
    status = main(["show", str(ARM), "--budget", "0.000001", "--kinematics-only", "--no-cache"])
    captured = capsys.readouterr()
    assert status == 0 and "Traceback" not in captured.err
    lines = [line for line in captured.err.splitlines() if "angle-sum contraction" in line]
    assert len(lines) == 1 and "--budget" in lines[0] and "random_8r_right_numeric_1" in lines[0]
    assert "q1" in captured.out


def _long_arm(joints: int) -> symkin.Robot:
    """Twists 90, 0, -90 degrees (parallel axes: angle sums), every a and d non-zero."""
    rows = "".join(
        f'[[joints]]\ntype = "revolute"\na = {0.1 + 0.03 * k}\nd = {0.2 - 0.02 * k}\n'
        f'alpha = "{("pi/2", "0", "-pi/2")[k % 3]}"\n\n'
        for k in range(joints)
    )
    text = f'name = "long_{joints}r"\nconvention = "standard"\n\n{rows}'
    return symkin.robot_from_toml(text, f"long_{joints}r.toml")


@pytest.mark.slow
def test_hopeless_contraction_is_not_attempted() -> None:
    """A 12-joint chain's T expands to thousands of terms: the contraction is refused at once
    (one warning, product form kept) instead of spending the budget; FK stays right."""
    arm = _long_arm(12)
    assert expanded_size(arm) > MAX_TERMS and has_parallel_revolute_axes(arm)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        form = readable_form(arm, 20.0)
        assert not Model(arm, budget=20.0).kinematics.simplified
    assert form.status == "over budget" and "not attempted" in form.note
    assert [w.category for w in caught] == [BudgetWarning, BudgetWarning]
    q = np.linspace(-1.0, 1.0, 12)
    value = sp.lambdify(symkin.joint_symbols(12), Model(arm).forward_kinematics)(*q)
    assert np.allclose(np.array(value, dtype=float), NumericRobot.from_robot(arm).fk(q))
