"""Condition number, smallest singular value and the operational-space inertia.

Expected values come from hand derivations for the planar 2R (singular values from the 2 x 2
eigenvalue formula of ``J J^T``; ``M`` and ``Lambda`` of point masses at the link ends) and from
Robotics Toolbox for the PUMA 560 (its ``manipulability`` measures and ``J^-T M J^-1`` from its
own ``jacob0`` and ``inertia``).
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

import symkin
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.errors import RobotWarning, SymkinError
from symkin.io import robot_from_toml
from symkin.kernels import inertial_symbols
from symkin.solve.evaluate import dynamic_state, singular_value_measures

L1, L2 = 0.7, 0.4
M1, M2 = 2.0, 0.5


@pytest.fixture(scope="module")
def planar() -> symkin.Model:
    # Without the file's inertial data: the point masses below are set through overrides.
    return symkin.derive(robot_from_toml(without_inertials("planar_2r"), "planar_2r.toml"))


def point_masses(model: symkin.Model) -> dict[str, float]:
    """Masses m1, m2 at the far ends of the links: standard DH frame i sits there, so the
    centres of mass are the frame origins and the links have no inertia of their own."""
    values = {s.name: 0.0 for s in inertial_symbols(model)}
    values.update(m1=M1, m2=M2, L1=L1, L2=L2)
    return values


def hand_singular_values(q1: float, q2: float) -> tuple[float, float]:
    """``(smallest singular value, condition number)`` of the planar 2R Jacobian by hand.

    ``J = [[-l1 s1 - l2 s12, -l2 s12], [l1 c1 + l2 c12, l2 c12]]``: the eigenvalues of
    ``J J^T`` are ``(t -+ sqrt(t^2 - 4 d^2)) / 2`` with ``d = det J = l1 l2 s2`` and
    ``t = trace(J J^T)`` = the squared column lengths ``l1^2 + l2^2 + 2 l1 l2 c2`` and ``l2^2``.
    """
    d = L1 * L2 * math.sin(q2)
    t = L1**2 + 2 * L2**2 + 2 * L1 * L2 * math.cos(q2)
    root = math.sqrt(t * t - 4 * d * d)
    small, large = (t - root) / 2, (t + root) / 2
    return math.sqrt(small), math.sqrt(large / small)


def test_planar_singular_values_by_hand(planar: symkin.Model) -> None:
    rng = np.random.default_rng(41)
    for q in rng.uniform(-np.pi, np.pi, (8, 2)):
        state = symkin.kinematic_state(planar, q, overrides={"L1": L1, "L2": L2})
        smallest, condition = hand_singular_values(*q)
        assert state.smallest_singular_value == pytest.approx(smallest, rel=1e-9)
        assert state.condition_number == pytest.approx(condition, rel=1e-9)


def test_planar_stretched_out_is_singular(planar: symkin.Model) -> None:
    state = symkin.kinematic_state(planar, [0.4, 0.0], overrides={"L1": L1, "L2": L2})
    assert state.smallest_singular_value < 1e-15
    assert state.condition_number == math.inf


def test_measures_of_an_orthogonal_and_a_rank_deficient_matrix() -> None:
    assert singular_value_measures(np.diag([3.0, -3.0])) == (3.0, 1.0)
    assert singular_value_measures(np.diag([2.0, 0.5, 0.0])) == (0.0, math.inf)
    # 2 x 3 (fewer rows than joints): the two singular values 4 and 1.
    assert singular_value_measures(np.array([[0.0, 4.0, 0.0], [1.0, 0.0, 0.0]])) == (1.0, 4.0)


def test_eval_prints_the_measures(capsys: pytest.CaptureFixture[str]) -> None:
    """At q = (-30 deg, 90 deg) with unit links J = [[-0.366, -0.866], [1.366, 0.5]]:
    ``t = 3``, ``d = 1``, eigenvalues of ``J J^T`` ``(3 -+ sqrt 5)/2``, so the singular values
    are the golden ratio and its inverse."""
    assert main(["eval", "planar_2r", "--q", "-30deg,90deg"]) == 0
    golden = (1 + math.sqrt(5)) / 2
    lines = capsys.readouterr().out.splitlines()
    index = lines.index("task rows x, y: det = 1, manipulability = 1")
    assert lines[index + 1] == (
        f"  condition number = {golden**2:.6g}, smallest singular value = {1 / golden:.6g}"
    )
    assert main(["eval", "planar_2r", "--q", "-30deg,90deg", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["condition_number"] == pytest.approx(golden**2, rel=1e-12)
    assert data["smallest_singular_value"] == pytest.approx(1 / golden, rel=1e-12)
    assert main(["eval", "planar_2r", "--q", "0,0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["condition_number"] is None  # infinite: JSON has no infinity
    assert data["smallest_singular_value"] == pytest.approx(0.0, abs=1e-15)


# ---------------------------------------------------------------------------------------------
# Operational-space inertia
# ---------------------------------------------------------------------------------------------


def hand_mass_matrix(q2: float) -> np.ndarray:
    """Point masses: ``M = m1 J1^T J1 + m2 J^T J`` with ``J1`` the Jacobian of the elbow."""
    c2 = math.cos(q2)
    m11 = M1 * L1**2 + M2 * (L1**2 + L2**2 + 2 * L1 * L2 * c2)
    m12 = M2 * (L2**2 + L1 * L2 * c2)
    return np.array([[m11, m12], [m12, M2 * L2**2]])


def hand_lambda(q1: float, q2: float) -> np.ndarray:
    """``Lambda = J^-T M J^-1 = m2 I + m1 (J1 J^-1)^T (J1 J^-1)``.

    ``J1 J^-1 = [-s1; c1] [c12, s12] / s2`` (``J1 = l1 [-s1, 0; c1, 0]``, ``J^-1`` the adjugate
    over ``l1 l2 s2``), so ``Lambda = m2 I + m1 / s2^2 u u^T`` with ``u = (c12, s12)``, the
    direction of link 2: pushing the tool along link 2 also moves the elbow mass.
    """
    u = np.array([math.cos(q1 + q2), math.sin(q1 + q2)])
    return M2 * np.eye(2) + M1 / math.sin(q2) ** 2 * np.outer(u, u)


def test_planar_operational_space_inertia_by_hand(planar: symkin.Model) -> None:
    values = point_masses(planar)
    rng = np.random.default_rng(42)
    for q in rng.uniform(-np.pi, np.pi, (6, 2)):
        mass = dynamic_state(planar, q, overrides=values).mass_matrix
        np.testing.assert_allclose(mass, hand_mass_matrix(q[1]), rtol=1e-12, atol=1e-12)
        inertia = symkin.operational_space_inertia(planar, q, overrides=values)
        np.testing.assert_allclose(inertia, hand_lambda(*q), rtol=1e-9, atol=1e-12)


def test_operational_space_inertia_at_a_singularity_raises(planar: symkin.Model) -> None:
    with pytest.raises(SymkinError, match="loses rank"):
        symkin.operational_space_inertia(planar, [0.3, 0.0], overrides=point_masses(planar))
    with pytest.raises(SymkinError, match="loses rank"):  # three rows, two joints
        symkin.operational_space_inertia(
            planar, [0.3, 1.0], rows=("x", "y", "wz"), overrides=point_masses(planar)
        )


# ---------------------------------------------------------------------------------------------
# Robotics Toolbox: the PUMA 560 (same DH table; its d1 pedestal does not change J or M)
# ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def puma() -> symkin.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotWarning)  # Corke's link 3 tensor, documented
        return symkin.derive(symkin.load_robot("puma560"))


@pytest.fixture(scope="module")
def toolbox_puma():
    import roboticstoolbox as rtb  # a test dependency: missing it is a failure

    return rtb.models.DH.Puma560()


@pytest.mark.oracle
def test_puma_measures_match_robotics_toolbox(puma, toolbox_puma) -> None:
    """rtb's ``manipulability`` uses ``jacob0`` (base frame, rows v then w, as ours) and
    ``axes="all"``: 'invcondition' is ``1 / cond(J)``, 'minsingular' the smallest value."""
    rng = np.random.default_rng(43)
    for q in rng.uniform(-np.pi, np.pi, (6, 6)):
        state = symkin.kinematic_state(puma, q)
        inverse = toolbox_puma.manipulability(q, method="invcondition")
        smallest = toolbox_puma.manipulability(q, method="minsingular")
        assert 1 / state.condition_number == pytest.approx(inverse, rel=1e-9)
        assert state.smallest_singular_value == pytest.approx(smallest, rel=1e-9)
        yoshikawa = toolbox_puma.manipulability(q, method="yoshikawa")
        assert state.manipulability == pytest.approx(yoshikawa, rel=1e-9)


@pytest.mark.oracle
def test_puma_operational_space_inertia_matches_robotics_toolbox(puma, toolbox_puma) -> None:
    """``J^-T M J^-1`` from rtb's ``jacob0`` and ``inertia`` (which includes the rotor
    inertias ``G^2 Jm``, as the catalogue file does)."""
    rng = np.random.default_rng(44)
    for q in rng.uniform(-np.pi, np.pi, (4, 6)):
        inverse = np.linalg.inv(toolbox_puma.jacob0(q))
        expected = inverse.T @ toolbox_puma.inertia(q) @ inverse
        actual = symkin.operational_space_inertia(puma, q)
        scale = np.max(np.abs(expected))
        np.testing.assert_allclose(actual, expected, rtol=0, atol=1e-8 * scale)


@pytest.mark.oracle
def test_puma_operational_space_inertia_matches_pinocchio(puma) -> None:
    """``(J M^-1 J^T)^-1`` from Pinocchio's ``crba`` (plus the rotor inertias, which its model
    leaves out) and its Jacobian of DH frame 6 in world-aligned axes (``[v; w]``, as ours)."""
    from test_dynamics_oracles import pinocchio_model

    pin, model = pinocchio_model(puma.robot)
    last = puma.robot.joints[-1]
    flange = pin.SE3(np.eye(3), np.array([float(last.a), 0.0, float(last.d)]))
    assert float(last.alpha) == 0.0 and float(last.theta) == 0.0  # frame 6 = joint 6 + (a, d)
    frame = model.addFrame(pin.Frame("flange", model.njoints - 1, flange, pin.FrameType.OP_FRAME))
    data = model.createData()
    rotor = np.diag([float(j.link.motor_inertia) for j in puma.robot.joints])
    rng = np.random.default_rng(45)
    for q in rng.uniform(-np.pi, np.pi, (4, 6)):
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T + rotor
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        expected = np.linalg.inv(jacobian @ np.linalg.solve(mass, jacobian.T))
        actual = symkin.operational_space_inertia(puma, q)
        scale = np.max(np.abs(expected))
        np.testing.assert_allclose(actual, expected, rtol=0, atol=1e-8 * scale)
