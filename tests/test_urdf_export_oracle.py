"""symkin urdf against Pinocchio: the exported file, read by pinocchio.buildModelFromXML,
gives symkin's FK, geometric Jacobian, inverse dynamics (rnea) and mass matrix (crba)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from symkin import catalogue_names, derive, kinematic_state, load_robot
from symkin.emit.urdf import urdf_text
from symkin.solve.evaluate import dynamic_state

pin = pytest.importorskip("pinocchio")
pytestmark = [pytest.mark.oracle, pytest.mark.slow]


def pinocchio_q(model, q):
    """Pinocchio's configuration: continuous joints are (cos q, sin q)."""
    values = []
    for joint, value in zip(list(model.joints)[1:], q, strict=True):
        values += [np.cos(value), np.sin(value)] if joint.nq == 2 else [value]
    return np.array(values)


@pytest.mark.parametrize("name", catalogue_names())
def test_pinocchio_reads_the_exported_urdf_with_the_same_kinematics_and_dynamics(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = load_robot(name)
    model = pin.buildModelFromXML(urdf_text(robot, "oracle test"))
    # URDF has no rotor inertia; Pinocchio's armature is the same term.
    model.armature = np.array(
        [0.0 if j.link is None else float(j.link.motor_inertia) for j in robot.joints]
    )
    data = model.createData()
    symbolic = derive(robot)
    tool = model.getFrameId("tool")
    rng = np.random.default_rng(11)
    dynamics = all(j.link is not None for j in robot.joints)
    for _ in range(5):
        q, dq, ddq = (rng.uniform(-1.5, 1.5, robot.dof) for _ in range(3))
        qp = pinocchio_q(model, q)
        pin.forwardKinematics(model, data, qp)
        pin.updateFramePlacements(model, data)
        jacobian = pin.computeFrameJacobian(model, data, qp, tool, pin.LOCAL_WORLD_ALIGNED)
        state = kinematic_state(symbolic, q)
        assert np.abs(data.oMf[tool].homogeneous - state.transform).max() < 1e-9
        assert np.abs(jacobian - state.jacobian).max() < 1e-9
        if dynamics:
            expected = dynamic_state(symbolic, q, dq, ddq)
            mass = pin.crba(model, data, qp)
            mass = np.triu(mass) + np.triu(mass, 1).T
            assert np.abs(pin.rnea(model, data, qp, dq, ddq) - expected.torque).max() < 1e-9
            assert np.abs(mass - expected.mass_matrix).max() < 1e-9
