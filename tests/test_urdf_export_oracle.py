"""symkin urdf and symkin dh against Pinocchio.

The exported file, read by pinocchio.buildModelFromXML, gives symkin's FK, geometric Jacobian,
inverse dynamics (rnea) and mass matrix (crba); the DH model extracted from a placed (URDF-like)
robot has the FK and inverse dynamics Pinocchio computes from the same arm written by hand as
URDF (tests/data/dh_placed_arm.urdf)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from numeric_dh import NumericRobot
from symkin import catalogue_names, derive, kinematic_state, load_robot, robot_from_toml
from symkin.derive.dh_extraction import extract_dh
from symkin.emit.robot_toml import robot_toml
from symkin.emit.urdf import urdf_text
from symkin.solve.evaluate import dynamic_state

DATA = Path(__file__).parent / "data"

pytestmark = [pytest.mark.oracle, pytest.mark.slow]


def pinocchio_q(model, q):
    """Pinocchio's configuration: continuous joints are (cos q, sin q)."""
    values = []
    for joint, value in zip(list(model.joints)[1:], q, strict=True):
        values += [np.cos(value), np.sin(value)] if joint.nq == 2 else [value]
    return np.array(values)


def robot_named(name: str):
    """A catalogue robot, or a file of tests/data (short test ids, no machine paths)."""
    return load_robot(DATA / name if name.endswith(".toml") else name)


@pytest.mark.parametrize("name", [*catalogue_names(), "placed_arm.toml"])
def test_pinocchio_reads_the_exported_urdf_with_the_same_kinematics_and_dynamics(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robot_named(name)
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


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_model_of_a_placed_arm_matches_pinocchio_on_its_hand_written_urdf(convention):
    model = pin.buildModelFromUrdf(str(DATA / "dh_placed_arm.urdf"))
    data = model.createData()
    tool = model.getFrameId("tool")
    source = load_robot(DATA / "placed_arm.toml")
    written = robot_toml(extract_dh(source, convention).robot, "oracle test")
    extracted = robot_from_toml(written, "placed_arm_dh.toml")
    reference = NumericRobot.from_robot(extracted)  # the naive DH product, no symkin algebra
    symbolic = derive(extracted)
    rng = np.random.default_rng(5)
    for _ in range(5):
        q, dq, ddq = (rng.uniform(-1.5, 1.5, 4) for _ in range(3))
        q[3] = rng.uniform(0, 0.2)
        qp = pinocchio_q(model, q)
        pin.forwardKinematics(model, data, qp)
        pin.updateFramePlacements(model, data)
        assert np.abs(data.oMf[tool].homogeneous - reference.fk(q)).max() < 1e-12
        torque = dynamic_state(symbolic, q, dq, ddq).torque
        assert np.abs(pin.rnea(model, data, qp, dq, ddq) - torque).max() < 1e-9


@pytest.mark.parametrize("name", ["panda", "placed_arm.toml", "dh_tilted_arm.toml"])
def test_mujoco_reads_the_exported_urdf_with_the_same_pose_and_inverse_dynamics(name):
    """MuJoCo needs mass on every moving body (robots with inertial data) and a tensor that
    obeys the triangle inequality (not the PUMA's published link 3)."""
    import mujoco  # a test dependency ([test] extras): missing is a failure, not a skip

    robot = robot_named(name)
    text = urdf_text(robot, "oracle test")
    opening = text.index(">", text.index("<robot")) + 1
    # MuJoCo's own URDF extension: keep the fixed tool body instead of fusing it into link n.
    compiler = '<mujoco><compiler fusestatic="false" discardvisual="true"/></mujoco>'
    model = mujoco.MjModel.from_xml_string(text[:opening] + compiler + text[opening:])
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT  # no limit forces
    data = mujoco.MjData(model)
    tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
    symbolic = derive(robot)
    rng = np.random.default_rng(13)
    for _ in range(4):
        q, dq, ddq = (rng.uniform(-1.5, 1.5, robot.dof) for _ in range(3))
        data.qpos[:], data.qvel[:] = q, dq
        mujoco.mj_forward(model, data)
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = data.xmat[tool].reshape(3, 3), data.xpos[tool]
        assert np.abs(pose - kinematic_state(symbolic, q).transform).max() < 1e-9
        data.qacc[:] = ddq
        mujoco.mj_inverse(model, data)
        torque = dynamic_state(symbolic, q, dq, ddq).torque
        assert np.abs(data.qfrc_inverse - torque).max() < 1e-9
