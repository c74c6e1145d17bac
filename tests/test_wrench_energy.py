"""External wrench, statics and energies against independent sources.

* planar 2R statics by hand (closed-form torques of a tip force and moment);
* ``-J^T w`` against Robotics Toolbox's ``jacob0`` of a DHRobot built from our PUMA table;
* the Newton–Euler pass with the wrench as its outer boundary against Lagrange's ``-J^T w``;
* ``T`` against ``sum 1/2 m v_c^2 + 1/2 w^T I_c w`` with velocities from finite differences
  of the forward kinematics, ``V`` against ``sum m g z_c`` by hand;
* the torques of a wrench on the UR5 (example-robot-data's URDF) against Pinocchio's ``rnea``
  with the wrench as an external force on the last joint (``fext``, local frame);
* the power balance ``dT/dt + dV/dt = dq^T (tau - F)`` along a polynomial motion.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp

import symkin
from numeric_dh import without_inertials
from symkin.errors import RobotWarning
from symkin.io import robot_from_toml
from symkin.runtime.modules import generated_numpy_module

STATES = 8


def _puma() -> symkin.Robot:
    with warnings.catch_warnings():  # Corke's lumped inertias: a documented RobotWarning
        warnings.simplefilter("ignore", RobotWarning)
        return symkin.load_robot("puma560")


@pytest.fixture(scope="module")
def puma():
    model = symkin.derive(_puma())
    return model, generated_numpy_module(model)


@pytest.fixture(scope="module")
def planar():
    # Without the file's inertial data: pi stays an input.
    bare = robot_from_toml(without_inertials("planar_2r"), "planar_2r.toml")
    model = symkin.derive(bare)
    return model, generated_numpy_module(model)


def test_planar_2r_statics_by_hand(planar):
    # Spong eq. 4.117 worked out for the planar elbow: a tip force (fx, fy) and a moment nz.
    _, module = planar
    rng = np.random.default_rng(18)
    l1, l2 = 1.0, 1.0
    pi = rng.uniform(0.5, 2.0, 20)  # no inertial data in the file; the arm lies flat (G = 0)
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, 2)
        w = rng.normal(size=6)
        fx, fy, nz = w[0], w[1], w[5]
        s1, c1 = np.sin(q[0]), np.cos(q[0])
        s12, c12 = np.sin(q.sum()), np.cos(q.sum())
        hold = np.array(
            [
                fx * (l1 * s1 + l2 * s12) - fy * (l1 * c1 + l2 * c12) - nz,
                l2 * (fx * s12 - fy * c12) - nz,
            ]
        )
        np.testing.assert_allclose(module.wrench_torque(q, w), hold, atol=1e-12)
        np.testing.assert_allclose(module.static_torque(q, w, pi=pi), hold, atol=1e-12)


@pytest.mark.slow
@pytest.mark.oracle
def test_wrench_torque_matches_robotics_toolbox_jacob0(puma):
    import roboticstoolbox as rtb  # a test dependency: missing it is a failure, not a skip

    model, module = puma
    values = model.robot.parameter_values()
    params = {s: values[s.name] for s in model.robot.parameter_symbols}
    links = []
    for joint in model.robot.joints:
        number = {k: float(getattr(joint, k).subs(params)) for k in ("d", "a", "alpha", "theta")}
        links.append(
            rtb.RevoluteDH(
                d=number["d"], a=number["a"], alpha=number["alpha"], offset=number["theta"]
            )
        )
    tool = np.array(model.robot.tool, dtype=float)
    base = np.array(model.robot.base, dtype=float)
    arm = rtb.DHRobot(links, tool=tool, base=base)
    rng = np.random.default_rng(470)
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, 6)
        w = rng.normal(size=6) * [10, 10, 10, 1, 1, 1]
        expected = -arm.jacob0(q).T @ w
        np.testing.assert_allclose(module.wrench_torque(q, w), expected, atol=1e-10)


@pytest.mark.slow
def test_newton_euler_boundary_equals_lagrange_term(puma):
    # tau with the wrench as Newton–Euler's outer boundary == tau + (-J^T w), symbolically
    # derived two ways, compared at random numbers (substituting the named intermediates).
    model, module = puma
    assignments, torque = model.inverse_dynamics_wrench_recursion
    values = model.robot.parameter_values()
    rng = np.random.default_rng(637)
    for _ in range(3):
        q, dq, ddq = (rng.uniform(-2, 2, 6) for _ in range(3))
        w = rng.normal(size=6)
        numbers = {s: values[s.name] for s in model.robot.parameter_symbols}
        for symbols, vector in ((model.q, q), (model.dq, dq), (model.ddq, ddq), (model.wrench, w)):
            numbers.update(zip(symbols, map(float, vector), strict=True))
        for symbol, expr in assignments:
            numbers[symbol] = float(expr.xreplace(numbers))
        recursion = np.array([float(e.xreplace(numbers)) for e in torque])
        summed = module.inverse_dynamics(q, dq, ddq) + module.wrench_torque(q, w)
        np.testing.assert_allclose(recursion, summed, atol=1e-9)


def _link_poses(model, q):
    fk = symkin.numeric_function(model, sp.Matrix.vstack(*model.frame_transforms[1:]))
    return fk(q).reshape(model.robot.dof, 4, 4)


def _centre(pose: np.ndarray, com: np.ndarray) -> np.ndarray:
    return pose[:3, :3] @ com + pose[:3, 3]


@pytest.mark.slow
def test_energies_from_link_velocities(puma):
    model, module = puma
    robot = model.robot
    rng = np.random.default_rng(3)
    h = 1e-6
    gravity = np.array(robot.gravity, dtype=float)
    for _ in range(3):
        q, dq = rng.uniform(-2, 2, 6), rng.uniform(-1, 1, 6)
        poses = _link_poses(model, q)
        ahead, behind = _link_poses(model, q + h * dq), _link_poses(model, q - h * dq)
        kinetic = potential = 0.0
        for i, joint in enumerate(robot.joints):
            link = joint.link
            mass, com = float(link.mass), np.array(link.com, dtype=float)
            inertia = np.array(link.inertia_matrix, dtype=float)
            velocity = (_centre(ahead[i], com) - _centre(behind[i], com)) / (2 * h)
            rate = (ahead[i][:3, :3] - behind[i][:3, :3]) / (2 * h) @ poses[i][:3, :3].T
            omega = np.array([rate[2, 1], rate[0, 2], rate[1, 0]])
            world = poses[i][:3, :3] @ inertia @ poses[i][:3, :3].T
            kinetic += 0.5 * mass * velocity @ velocity + 0.5 * omega @ world @ omega
            kinetic += 0.5 * float(link.motor_inertia) * dq[i] ** 2
            potential -= mass * gravity @ _centre(poses[i], com)
        t, v, lagrangian = module.energy(q, dq)
        assert t == pytest.approx(kinetic, rel=1e-7)
        assert v == pytest.approx(potential, rel=1e-9, abs=1e-9)
        assert lagrangian == pytest.approx(t - v, abs=1e-12)


@pytest.mark.parametrize("name", ["planar_2r", pytest.param("puma560", marks=pytest.mark.slow)])
def test_power_balance_along_a_motion(name, planar, request):
    # dT/dt + dV/dt = dq^T tau for q(t) = q0 + v t + a t^2 / 2 (neither file has friction)
    model, module = planar if name == "planar_2r" else request.getfixturevalue("puma")
    n = model.robot.dof
    rng = np.random.default_rng(21)
    q0, v, a = rng.uniform(-2, 2, n), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    extra = {"pi": rng.uniform(0.5, 2.0, 20)} if name == "planar_2r" else {}
    h = 1e-5

    def energy(t):
        kinetic, potential, _ = module.energy(q0 + v * t + a * t * t / 2, v + a * t, **extra)
        return kinetic + potential

    rate = (energy(0.3 + h) - energy(0.3 - h)) / (2 * h)
    q, dq = q0 + v * 0.3 + a * 0.045, v + a * 0.3
    power = dq @ module.inverse_dynamics(q, dq, a, **extra)
    assert rate == pytest.approx(power, rel=1e-6)


@pytest.mark.slow
@pytest.mark.oracle
def test_ur5_wrench_matches_pinocchio_rnea_with_fext():
    import pinocchio as pin  # a test dependency: missing it is a failure, not a skip

    from test_urdf_oracles import urdf_path

    path = urdf_path("ur_description/urdf/ur5_robot.urdf")
    robot = symkin.load_robot(path, tip="tool0")
    module = generated_numpy_module(symkin.derive(robot))
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    assert model.nq == model.nv == robot.dof  # revolute joints only, in chain order
    tool = model.getFrameId("tool0")
    last = model.njoints - 1
    rng = np.random.default_rng(637)
    for _ in range(STATES):
        q, dq, ddq = (rng.uniform(-2, 2, 6) for _ in range(3))
        w = rng.normal(size=6) * [20, 20, 20, 2, 2, 2]
        pin.framesForwardKinematics(model, data, q)
        point = data.oMf[tool].translation
        # w at the tool point, base axes -> a spatial force about the base origin -> joint 6
        about_origin = pin.Force(w[:3], w[3:] + np.cross(point, w[:3]))
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        fext[last] = data.oMi[last].actInv(about_origin)
        expected = pin.rnea(model, data, q, dq, ddq, fext)
        ours = module.inverse_dynamics(q, dq, ddq) + module.wrench_torque(q, w)
        np.testing.assert_allclose(ours, expected, atol=1e-9 * max(1.0, np.abs(expected).max()))
