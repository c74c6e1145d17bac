"""The link-by-link named forward kinematics and Jacobian (``symkin.derive.named_pose``, the
kernels' form of chains without a readable form) against the independent numeric DH product
of tests/numeric_dh.py: its FK and its complex-step Jacobian, for standard and modified DH,
prismatic and flipped joints, base and tool frames (the hand-written robots) and a generic
6R arm; and the kernels built from it keep those values.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from numeric_dh import ALL_ROBOTS, NumericRobot, overrides, reference, robot, samples
from symkin.derive import Model
from symkin.kernels import pose_kernels
from symkin.kernels.catalogue import inertial_symbols

GENERIC = Path(__file__).parent / "data" / "random_6r_generic_1.toml"


def _evaluated(rob, assignments, outputs, q, parameter_overrides=None, extra=None):
    """``outputs`` at ``q`` (and ``extra`` symbol values), the intermediates evaluated one by
    one as floats."""
    parameters = rob.parameter_values(parameter_overrides).items()
    values = {sp.Symbol(name, real=True): sp.Float(value) for name, value in parameters}
    values.update({s: sp.Float(v) for s, v in (extra or {}).items()})
    values.update(zip(symkin.joint_symbols(rob.dof), (sp.Float(v) for v in q), strict=True))
    for symbol, expr in assignments:
        values[symbol] = sp.Float(float(expr.xreplace(values)))
    return [np.array(matrix.xreplace(values), dtype=float) for matrix in outputs]


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_named_pose_is_the_dh_product(name: str) -> None:
    rob = robot(name)
    pose = Model(rob).named_pose
    ref = reference(name)
    for q in samples(name, 17, 3):
        fk, jacobian = _evaluated(
            rob,
            pose.assignments,
            [pose.forward_kinematics, pose.geometric_jacobian],
            q,
            overrides(name),
        )
        np.testing.assert_allclose(fk, ref.fk(q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(jacobian, ref.jacobian(q, method="complex"), rtol=0, atol=1e-9)


def test_generic_arm_kernels_come_from_the_named_form() -> None:
    rob = symkin.robot_from_toml(GENERIC.read_text(), GENERIC.name)
    m = Model(rob)
    assert not m.kinematics.simplified  # the contraction is not attempted (1,511 terms)
    kernels = {k.name: k for k in pose_kernels(m)}
    ref = NumericRobot.from_robot(rob)
    for q in np.random.default_rng(4).uniform(-np.pi, np.pi, size=(3, 6)):
        kernel = kernels["fk_jacobian"]
        fk, jacobian = _evaluated(rob, kernel.assignments, [o.matrix for o in kernel.outputs], q)
        np.testing.assert_allclose(fk, ref.fk(q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(jacobian, ref.jacobian(q, method="complex"), rtol=0, atol=1e-9)
        kernel = kernels["position_jacobian"]
        (jp,) = _evaluated(rob, kernel.assignments, [kernel.outputs[0].matrix], q)
        np.testing.assert_allclose(jp, ref.jacobian(q, method="complex")[:3], rtol=0, atol=1e-9)
    # The named form is shorter than the product form's CSE (484, 712, 879 operations).
    counts = {name: kernels[name].operation_counts["total"] for name in kernels}
    assert counts["fk"] < 484 and counts["jacobian"] < 712 and counts["fk_jacobian"] < 879


def test_generic_arm_static_torque_carries_the_wrench_through_named_frames() -> None:
    """``static_torque(q, w) - static_torque(q, 0) = -J^T w`` with ``J`` the complex-step
    Jacobian of the numeric DH product: the wrench enters through the named frame n."""
    rob = symkin.robot_from_toml(GENERIC.read_text(), GENERIC.name)
    m = Model(rob)
    assignments, torque = m.static_torque_recursion
    ref = NumericRobot.from_robot(rob)
    rng = np.random.default_rng(9)
    # The file has no link data: the inertial symbols get any values (they cancel).
    inertia = {symbol: rng.uniform(0.1, 1.0) for symbol in inertial_symbols(m)}
    unloaded_wrench = dict.fromkeys(m.wrench, 0.0)
    for q in rng.uniform(-np.pi, np.pi, size=(2, 6)):
        wrench = rng.normal(size=6)
        loaded, unloaded = (
            _evaluated(rob, assignments, [torque], q, extra={**inertia, **values})[0]
            for values in (dict(zip(m.wrench, wrench, strict=True)), unloaded_wrench)
        )
        expected = -ref.jacobian(q, method="complex").T @ wrench
        np.testing.assert_allclose((loaded - unloaded).ravel(), expected, rtol=0, atol=1e-9)
