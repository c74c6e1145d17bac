"""The regressor and identification against outside tools.

- Pinocchio's ``computeJointTorqueRegressor`` on the URDF symkin exports: Pinocchio's
  parameters are ``m, m c, I`` (xx xy yy xz yz zz) at each *joint* frame, symkin's at each DH
  frame; the constant map between them is found through Pinocchio's own ``SE3.act`` on
  random inertias, the frames' offset from an independent NumPy DH product.
- Robotics Toolbox's ``rne`` simulates the PUMA 560 (Corke's data) and the Panda (Gaz et al.
  2019, an identified model published with feasible parameters and shipped in
  ``roboticstoolbox.models.DH.Panda``): identification recovers the base parameters.
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
import roboticstoolbox as rtb

from numeric_dh import NumericRobot
from symkin.derive.regressor import regressor, regressor_function
from symkin.derive.regressor_base import base_regressor
from symkin.emit.urdf import urdf_text
from symkin.solve.identify import identify
from symkin.solve.identify_consistency import physical_consistency

pytestmark = [pytest.mark.oracle, pytest.mark.slow]

PINOCCHIO_ORDER = ("m", "mx", "my", "mz", "xx", "xy", "yy", "xz", "yz", "zz")


def joint_frame_map(placement: pin.SE3, rng: np.random.Generator) -> np.ndarray:
    """``T`` with ``pinocchio parameters at the joint frame = T @ parameters at the DH frame``
    (both in Pinocchio's order), from ``SE3.act`` on random inertias (the map is linear)."""
    inertias = [pin.Inertia.Random() for _ in range(14)]
    before = np.array([i.toDynamicParameters() for i in inertias])
    after = np.array([placement.act(i).toDynamicParameters() for i in inertias])
    solution, *_ = np.linalg.lstsq(before, after, rcond=None)
    return solution.T


@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_regressor_matches_pinocchio_joint_torque_regressor(model_of, name):
    model = model_of(name)
    robot = model.robot
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pinocchio_model = pin.buildModelFromXML(urdf_text(robot, "oracle test"))
    data = pinocchio_model.createData()
    assert all(j.nq == 1 for j in list(pinocchio_model.joints)[1:])
    full = regressor(robot, model.kinematics)
    evaluate = regressor_function(robot, model.kinematics)
    p = base_regressor(robot, model.kinematics).parameter_values
    numeric = NumericRobot.from_robot(robot)
    rng = np.random.default_rng(5)
    for _ in range(3):
        q, dq, ddq = (rng.uniform(-1.5, 1.5, robot.dof) for _ in range(3))
        expected = pin.computeJointTorqueRegressor(pinocchio_model, data, q, dq, ddq)
        ours = evaluate(q, dq, ddq, p)
        frames = numeric.frames(q)
        pin.forwardKinematics(pinocchio_model, data, q)  # oMi: the regressor does not set it
        for i in range(robot.dof):
            placement = data.oMi[i + 1].inverse() * pin.SE3(frames[i + 1])
            columns = [full.names.index(f"{key}{i + 1}") for key in PINOCCHIO_ORDER]
            block = expected[:, 10 * i : 10 * i + 10] @ joint_frame_map(placement, rng)
            assert np.abs(ours[:, columns] - block).max() < 1e-8 * max(1.0, np.abs(block).max())


def simulated(toolbox_robot, dof: int, count: int, seed: int):
    rng = np.random.default_rng(seed)
    q, dq, ddq = (rng.uniform(-2.0, 2.0, (count, dof)) for _ in range(3))
    tau = np.array([toolbox_robot.rne(*state) for state in zip(q, dq, ddq, strict=True)])
    return q, dq, ddq, tau


def puma():
    return rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)


def test_noise_free_puma_base_parameters_are_recovered(model_of):
    model = model_of("puma560")
    base = base_regressor(model.robot, model.kinematics)
    fit = identify(model, *simulated(puma(), 6, 200, seed=1))
    expected = np.array(base.values)
    assert fit.names == base.names
    # 1e-8 relative to each parameter, or to the largest one for those that are zero.
    scale = np.maximum(np.abs(expected), 1e-3 * np.abs(expected).max())
    assert np.all(np.abs(fit.estimate - expected) <= 1e-8 * scale)
    assert physical_consistency(base, fit.estimate, fit.std).consistent


def test_noisy_puma_estimates_lie_within_three_standard_deviations(model_of):
    model = model_of("puma560")
    base = base_regressor(model.robot, model.kinematics)
    q, dq, ddq, tau = simulated(puma(), 6, 400, seed=2)
    noise = np.random.default_rng(9).normal(0.0, 0.05, tau.shape)
    fit = identify(model, q, dq, ddq, tau + noise)
    deviation = np.abs(fit.estimate - np.array(base.values)) / fit.std
    # 40 parameters: by chance one may pass 3 sigma (p = 0.0027 each); none passes 4.5.
    assert np.sum(deviation > 3.0) <= 1 and deviation.max() < 4.5
    assert np.allclose(fit.residual_rms, 0.05, rtol=0.15)
    auto = identify(model, q, dq, ddq, tau + noise, weights="auto")
    assert np.abs(auto.estimate - np.array(base.values)).max() < 5 * auto.std.max()


def test_published_identified_panda_is_recovered_and_feasible(model_of):
    """Gaz et al. (IEEE RA-L 2019) identified the Panda with physically feasible parameters;
    roboticstoolbox ships them.  Its rne data give symkin's base parameters of the same
    published values, and the estimate passes the consistency check."""
    model = model_of("panda")
    base = base_regressor(model.robot, model.kinematics)
    fit = identify(model, *simulated(rtb.models.DH.Panda(), 7, 200, seed=3))
    expected = np.array(base.values)
    scale = np.maximum(np.abs(expected), 1e-3 * np.abs(expected).max())
    assert np.all(np.abs(fit.estimate - expected) <= 1e-8 * scale)
    assert physical_consistency(base, fit.estimate, fit.std).consistent
