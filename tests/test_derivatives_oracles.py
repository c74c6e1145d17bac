"""Derivative kernels against Pinocchio's analytical derivatives on the same robot:
``computeRNEADerivatives`` (dtau/dq, dtau/dv, M) and ``computeABADerivatives`` (dddq/dq,
dddq/dv, M^-1), and ``getFrameJacobianTimeVariation`` (dJ/dt, LOCAL_WORLD_ALIGNED, symkin's
base-frame convention).  Robots: the PUMA through symkin's URDF export (rotor inertia as
Pinocchio's armature), the UR5 and the Panda from example-robot-data's URDFs, read by both.
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest

import symkin
from symkin.emit.urdf import urdf_text
from test_urdf_oracles import Pair

pytestmark = [pytest.mark.oracle, pytest.mark.slow]

TOLERANCE = 1e-9


class Exported:
    """symkin's robot and Pinocchio's model of symkin's URDF export of it."""

    def __init__(self, name: str) -> None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.robot = symkin.load_robot(name)
        self.model = pin.buildModelFromXML(urdf_text(self.robot, "oracle test"))
        self.model.armature = np.array([float(j.link.motor_inertia) for j in self.robot.joints])
        self.data = self.model.createData()
        self.tip = self.model.getFrameId("tool")
        self.joint_ids = list(range(1, self.model.njoints))

    pin_q = Pair.pin_q
    pin_v = Pair.pin_v
    symkin_order = Pair.symkin_order


def _close(actual, expected, what: str) -> None:
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(np.asarray(actual) - expected)))
    assert error <= TOLERANCE * scale, f"{what}: max error {error:.3g} (scale {scale:.3g})"


def _columns(pair, matrix: np.ndarray) -> np.ndarray:
    """Pinocchio's columns (``nv`` order) in symkin's joint order (rows stay 6)."""
    return matrix[:, [pair.model.joints[j].idx_v for j in pair.joint_ids]]


@pytest.fixture(scope="module", params=["puma560", "ur5", "panda"])
def pair(request, tmp_path_factory):
    if request.param == "puma560":
        return Exported("puma560")
    return Pair(request.param, tmp_path_factory.mktemp(request.param))


def test_derivatives_match_pinocchio(pair):
    model = symkin.derive(pair.robot)
    frame = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    rng = np.random.default_rng(19)
    for _ in range(5):
        q, dq, ddq = (rng.uniform(-1.5, 1.5, pair.robot.dof) for _ in range(3))
        ours = symkin.dynamics_derivatives(model, q, dq, ddq)
        qp, vp, ap = pair.pin_q(q), pair.pin_v(dq), pair.pin_v(ddq)
        pin.computeRNEADerivatives(pair.model, pair.data, qp, vp, ap)
        _close(ours.dtau_dq, pair.symkin_order(pair.data.dtau_dq), "dtau/dq")
        _close(ours.dtau_ddq, pair.symkin_order(pair.data.dtau_dv), "dtau/ddq")
        tau = pin.rnea(pair.model, pair.data, qp, vp, ap)
        _close(ours.torque, pair.symkin_order(tau), "tau")
        pin.computeABADerivatives(pair.model, pair.data, qp, vp, tau)
        inverse = np.triu(pair.data.Minv) + np.triu(pair.data.Minv, 1).T
        _close(ours.dddq_dq, pair.symkin_order(pair.data.ddq_dq), "dddq/dq")
        _close(ours.dddq_ddq, pair.symkin_order(pair.data.ddq_dv), "dddq/ddq")
        _close(ours.dddq_dtau, pair.symkin_order(inverse), "dddq/dtau")
        pin.computeJointJacobiansTimeVariation(pair.model, pair.data, qp, vp)
        pin.updateFramePlacements(pair.model, pair.data)
        rate = pin.getFrameJacobianTimeVariation(pair.model, pair.data, pair.tip, frame)
        _close(ours.jacobian_dot, _columns(pair, rate), "dJ/dt")
