"""URDF robots read by symkin against Pinocchio reading the same file.

The URDFs are those shipped inside the ``example-robot-data`` package (a test dependency, read
from the installed package, never downloaded): the Panda, the UR5, the UR3 and the Unitree Z1,
plus ``tests/data/placed_arm.urdf`` (tilted origins, a -z axis and a slanted prismatic joint,
also written as ``tests/data/placed_arm.toml`` in symkin's placement form).  Pinocchio builds
its model with ``pinocchio.buildModelFromUrdf`` on the same file; joints off symkin's chain
(the Panda's fingers) are locked at zero with ``buildReducedModel``, as symkin holds them.

Compared at random states, to 1e-9: the tip link's pose (``oMf``), the geometric Jacobian
(``LOCAL_WORLD_ALIGNED``: the tip origin's velocity and the angular velocity, in base axes,
symkin's convention), the mass matrix (``crba``) and the inverse dynamics (``rnea``, gravity
9.81 m/s^2 along -z on both sides), from symkin's generated NumPy module.
"""

from __future__ import annotations

import subprocess
import warnings
from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

import symkin
from codegen_helpers import import_path, write_tree
from symkin.errors import RobotWarning
from symkin.generate import files_for_robot

pytestmark = [pytest.mark.slow, pytest.mark.oracle]

TOLERANCE = 1e-9
STATES = 10
DATA = Path(__file__).parent / "data"

# (file inside example-robot-data's robots folder, or a tests/data file; tip link)
ROBOTS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_hand_tcp"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "tool0"),
    "z1": ("z1_description/urdf/z1.urdf", "gripperMover"),
    "placed_arm": (str(DATA / "placed_arm.urdf"), None),
}


def _pinocchio() -> ModuleType:
    try:
        import pinocchio
    except ImportError as exc:  # pragma: no cover - depends on the environment
        pytest.fail(f"Pinocchio (pip install pin) is required here: {exc}", pytrace=False)
    return pinocchio


def urdf_path(relative: str) -> Path:
    """A file of the installed example-robot-data package (or an absolute test file)."""
    if Path(relative).is_absolute():
        return Path(relative)
    try:
        package = distribution("example-robot-data")
    except PackageNotFoundError:  # pragma: no cover - depends on the environment
        pytest.fail("example-robot-data (a test dependency) is not installed", pytrace=False)
    path = Path(str(package.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    return path / relative


class Pair:
    """symkin's generated module and Pinocchio's reduced model of one URDF."""

    def __init__(self, name: str, tmp: Path) -> None:
        pin = _pinocchio()
        relative, tip = ROBOTS[name]
        path = urdf_path(relative)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RobotWarning)  # the Panda's lumped fingers
            self.robot = symkin.load_robot(path, tip=tip)
        write_tree(tmp, files_for_robot(self.robot, ("numpy",)))
        module = tmp / "numpy" / f"{self.robot.name}_kinematics.py"
        self.generated = import_path(f"oracle_{name}", module)
        full = pin.buildModelFromUrdf(str(path))
        chain = [joint.name for joint in self.robot.joints]
        others = [full.getJointId(n) for n in full.names[1:] if n not in chain]
        self.model = pin.buildReducedModel(full, others, pin.neutral(full)) if others else full
        self.data = self.model.createData()
        self.tip = self.model.getFrameId(tip or _leaf(path))
        self.joint_ids = [self.model.getJointId(n) for n in chain]

    def pin_q(self, q: np.ndarray) -> np.ndarray:
        """symkin's joint values as Pinocchio's configuration (cos/sin for continuous)."""
        configuration = np.zeros(self.model.nq)
        for value, joint_id in zip(q, self.joint_ids, strict=True):
            joint = self.model.joints[joint_id]
            if joint.nq == 2:
                configuration[joint.idx_q : joint.idx_q + 2] = np.cos(value), np.sin(value)
            else:
                configuration[joint.idx_q] = value
        return configuration

    def pin_v(self, dq: np.ndarray) -> np.ndarray:
        velocity = np.zeros(self.model.nv)
        for value, joint_id in zip(dq, self.joint_ids, strict=True):
            velocity[self.model.joints[joint_id].idx_v] = value
        return velocity

    def symkin_order(self, matrix: np.ndarray) -> np.ndarray:
        """Rows/columns of a Pinocchio ``nv`` quantity in symkin's joint order."""
        index = [self.model.joints[j].idx_v for j in self.joint_ids]
        return matrix[np.ix_(index, index)] if matrix.ndim == 2 else matrix[index]


def _leaf(path: Path) -> str:
    return {"placed_arm.urdf": "tool"}[path.name]


@pytest.fixture(scope="module", params=list(ROBOTS))
def pair(request, tmp_path_factory) -> Pair:
    return Pair(request.param, tmp_path_factory.mktemp(request.param))


def states(pair: Pair, seed: int):
    rng = np.random.default_rng(seed)
    dof = pair.robot.dof
    for _ in range(STATES):
        yield rng.uniform(-np.pi, np.pi, dof), rng.uniform(-2, 2, dof), rng.uniform(-5, 5, dof)


def assert_close(actual, expected, what: str) -> None:
    scale = max(1.0, float(np.max(np.abs(expected))))
    error = float(np.max(np.abs(np.asarray(actual) - expected)))
    assert error <= TOLERANCE * scale, f"{what}: max error {error:.3g} (scale {scale:.3g})"


def test_pinocchio_models_the_same_chain(pair):
    assert pair.model.nv == pair.robot.dof
    np.testing.assert_array_equal(pair.model.gravity.linear, [0.0, 0.0, -9.81])


def test_tip_pose_matches_pinocchio(pair):
    pin = _pinocchio()
    for q, _, _ in states(pair, 1):
        pin.framesForwardKinematics(pair.model, pair.data, pair.pin_q(q))
        expected = pair.data.oMf[pair.tip].homogeneous
        assert_close(pair.generated.fk(q), expected, f"{pair.robot.name} fk")


def test_geometric_jacobian_matches_pinocchio(pair):
    pin = _pinocchio()
    frame = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for q, _, _ in states(pair, 2):
        jacobian = pin.computeFrameJacobian(pair.model, pair.data, pair.pin_q(q), pair.tip, frame)
        expected = jacobian[:, [pair.model.joints[j].idx_v for j in pair.joint_ids]]
        assert_close(pair.generated.jacobian(q), expected, f"{pair.robot.name} J")


def test_mass_matrix_matches_crba(pair):
    pin = _pinocchio()
    for q, _, _ in states(pair, 3):
        upper = pin.crba(pair.model, pair.data, pair.pin_q(q))
        full = np.triu(upper) + np.triu(upper, 1).T
        assert_close(pair.generated.mass_matrix(q), pair.symkin_order(full), "M vs crba")


def test_inverse_dynamics_matches_rnea(pair):
    pin = _pinocchio()
    for q, dq, ddq in states(pair, 4):
        tau = pin.rnea(pair.model, pair.data, pair.pin_q(q), pair.pin_v(dq), pair.pin_v(ddq))
        ours = pair.generated.inverse_dynamics(q, dq, ddq)
        assert_close(ours, pair.symkin_order(tau), f"{pair.robot.name} tau vs rnea")


def test_placement_toml_and_urdf_of_the_test_arm_agree():
    """tests/data/placed_arm.toml (symkin's placement form) is the same arm as the URDF."""
    from_toml = symkin.derive(symkin.load_robot(DATA / "placed_arm.toml"))
    from_urdf = symkin.derive(symkin.load_robot(DATA / "placed_arm.urdf"))
    q = np.array([0.3, -0.4, 1.1, 0.05])
    fk = [symkin.kinematic_state(m, q=q).transform for m in (from_toml, from_urdf)]
    np.testing.assert_allclose(fk[0], fk[1], atol=1e-12)


@pytest.mark.parametrize("name", ["ur5", "ur3"])
def test_closed_form_ik_of_a_urdf_arm_through_its_dh_form(name, tmp_path):
    """A URDF arm whose DH form (``symkin dh``) is a known family gets closed-form IK: for
    poses Pinocchio computes at random joint values, every solution reproduces the pose in
    Pinocchio's FK, and one of them is the joint values the pose came from."""
    from symkin.solve.ik.closed_form import closed_form_ik

    pair = Pair(name, tmp_path)
    pin = _pinocchio()
    model = symkin.derive(pair.robot)
    for q, _, _ in states(pair, 17):
        pin.framesForwardKinematics(pair.model, pair.data, pair.pin_q(q))
        target = pair.data.oMf[pair.tip].homogeneous
        solutions = closed_form_ik(model, target)
        assert 1 <= len(solutions) <= 8
        for solution in solutions:
            pin.framesForwardKinematics(pair.model, pair.data, pair.pin_q(solution.q))
            assert_close(pair.data.oMf[pair.tip].homogeneous, target, "pose of a solution")
        nearest = min(
            np.max(np.abs(np.angle(np.exp(1j * (solution.q - q))))) for solution in solutions
        )
        assert nearest < 1e-6


CLOSED_DRIVER = """
#include <stdio.h>
#include "ur5_ik_closed.h"
int main(void) {
    double T[16], q[UR5_IK_CLOSED_MAX_SOLUTIONS * 6];
    int branch[UR5_IK_CLOSED_MAX_SOLUTIONS], inside[UR5_IK_CLOSED_MAX_SOLUTIONS];
    for (;;) {
        for (int i = 0; i < 16; ++i) {
            if (scanf("%lf", &T[i]) != 1) return 0;
        }
        int count = ur5_ik_closed(T, q, branch, inside);
        printf("%d", count);
        for (int i = 0; i < count * 6; ++i) printf(" %.17g", q[i]);
        printf("\\n");
    }
}
"""


@pytest.mark.needs_cc
def test_generated_c_closed_form_ik_of_the_ur5_urdf(tmp_path):
    """The C closed form `symkin derive` writes for the UR5 URDF (through its DH form),
    compiled with -Werror: every solution reproduces the pose in Pinocchio's FK."""
    pair = Pair("ur5", tmp_path / "pair")
    pin = _pinocchio()
    c = tmp_path / "out"
    write_tree(c, files_for_robot(pair.robot, ("c",), dynamics=False))
    (c / "c" / "driver.c").write_text(CLOSED_DRIVER)
    flags = ["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic"]
    sources = ["driver.c", "ur5.c", "ur5_ik_closed.c"]
    subprocess.run(["gcc", *flags, *sources, "-lm", "-o", "driver"], cwd=c / "c", check=True)
    poses = []
    for q, _, _ in states(pair, 23):
        pin.framesForwardKinematics(pair.model, pair.data, pair.pin_q(q))
        poses.append(pair.data.oMf[pair.tip].homogeneous.copy())
    text = "\n".join(" ".join(repr(float(v)) for v in pose.ravel()) for pose in poses)
    lines = subprocess.run(
        [str(c / "c" / "driver")], input=text, capture_output=True, text=True, check=True
    ).stdout.splitlines()
    for pose, line in zip(poses, lines, strict=True):
        count, *values = line.split()
        solutions = np.array(values, dtype=float).reshape(int(count), 6)
        assert len(solutions) >= 1
        for solution in solutions:
            pin.framesForwardKinematics(pair.model, pair.data, pair.pin_q(solution))
            assert_close(pair.data.oMf[pair.tip].homogeneous, pose, "pose of a C solution")
