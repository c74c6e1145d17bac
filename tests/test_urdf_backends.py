"""Every backend on a URDF robot: tests/data/placed_arm.urdf (tilted origins, a -z axis, a
slanted prismatic joint) through the generated NumPy, C and CasADi code, the numeric IK and
the trajectory optimiser, each checked against Pinocchio reading the same file.
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np
import pytest

import symkin
from codegen_helpers import CC, SHARED, STRICT, import_path, run_parallel, write_tree
from symkin.generate import files_for_robot
from symkin.solve.ik.closed_form import has_closed_form
from symkin.solve.ik.numeric import solve_ik

pytestmark = [pytest.mark.slow, pytest.mark.oracle]

URDF = Path(__file__).parent / "data" / "placed_arm.urdf"


@pytest.fixture(scope="module")
def pinocchio_arm():
    import pinocchio

    model = pinocchio.buildModelFromUrdf(str(URDF))
    return pinocchio, model, model.createData(), model.getFrameId("tool")


def pin_q(model, q):
    """Continuous joints are (cos, sin) in Pinocchio's configuration."""
    values = []
    for joint, value in zip(model.joints[1:], q, strict=True):
        values += [np.cos(value), np.sin(value)] if joint.nq == 2 else [value]
    return np.array(values)


def expected(pinocchio_arm, q, dq, ddq):
    pin, model, data, tip = pinocchio_arm
    configuration = pin_q(model, q)
    pin.framesForwardKinematics(model, data, configuration)
    pose = data.oMf[tip].homogeneous.copy()
    frame = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    jacobian = pin.computeFrameJacobian(model, data, configuration, tip, frame)
    upper = pin.crba(model, data, configuration)
    mass = np.triu(upper) + np.triu(upper, 1).T
    tau = pin.rnea(model, data, configuration, dq, ddq)
    return {"fk": pose, "jacobian": jacobian, "mass_matrix": mass, "inverse_dynamics": tau}


@pytest.mark.needs_cc
def test_numpy_c_and_casadi_agree_with_pinocchio(tmp_path, pinocchio_arm):
    robot = symkin.load_robot(URDF)
    write_tree(tmp_path, files_for_robot(robot, ("numpy", "c", "casadi")))
    library = "libplaced_arm.so"
    command = [CC, *STRICT, *SHARED, "-o", library, "c/placed_arm.c", "-lm"]
    run_parallel({"so": command}, cwd=tmp_path)["so"].check()
    numpy_module = import_path("placed_numpy", tmp_path / "numpy" / "placed_arm_kinematics.py")
    casadi_module = import_path("placed_casadi", tmp_path / "casadi" / "placed_arm_casadi.py")
    c_library = ctypes.CDLL(str(tmp_path / library))
    rng = np.random.default_rng(16)
    for _ in range(5):
        q, dq, ddq = rng.uniform(-2, 2, (3, 4))
        want = expected(pinocchio_arm, q, dq, ddq)
        state = {
            "fk": (q,),
            "jacobian": (q,),
            "mass_matrix": (q,),
            "inverse_dynamics": (q, dq, ddq),
        }
        for name, value in want.items():
            got_numpy = np.asarray(getattr(numpy_module, name)(*state[name]), dtype=float)
            got_casadi = np.array(getattr(casadi_module, f"{name}_function")()(*state[name], []))
            got_c = _c_call(c_library, name, state[name], value.size)
            for backend, got in (("numpy", got_numpy), ("casadi", got_casadi), ("C", got_c)):
                np.testing.assert_allclose(
                    got.reshape(value.shape), value, atol=1e-9, err_msg=f"{backend} {name}"
                )


def _c_call(library, name: str, arrays, size: int) -> np.ndarray:
    out = np.full(size, np.nan)
    function = getattr(library, f"placed_arm_{name}")
    function.restype = None
    function.argtypes = [ctypes.c_void_p] * (len(arrays) + 1)
    inputs = [np.ascontiguousarray(a, dtype=float) for a in arrays]
    function(*[a.ctypes.data_as(ctypes.c_void_p) for a in inputs], out.ctypes.data)
    return out


def test_numeric_ik_reaches_a_pose_pinocchio_computed(pinocchio_arm):
    robot = symkin.load_robot(URDF)
    assert not has_closed_form(robot)  # its DH form (`symkin dh`) is no closed-form family
    model = symkin.derive(robot)
    q_star = np.array([0.4, -0.6, 0.9, 0.1])
    target = expected(pinocchio_arm, q_star, np.zeros(4), np.zeros(4))["fk"]
    result = solve_ik(model, target, np.zeros(4), position_only=True)
    assert result.success
    reached = expected(pinocchio_arm, result.q, np.zeros(4), np.zeros(4))["fk"]
    np.testing.assert_allclose(reached[:3, 3], target[:3, 3], atol=1e-8)


def test_trajectory_optimiser_runs_on_the_urdf_arm():
    model = symkin.derive(symkin.load_robot(URDF))
    problem = symkin.TrajectoryProblem(
        start=(0.0, 0.0, 0.0, 0.05), goal=(0.5, -0.3, 0.4, 0.1), final_time=1.0, intervals=10
    )
    motion = symkin.optimal_trajectory(model, problem)
    np.testing.assert_allclose(motion.q[0], problem.start, atol=1e-8)
    np.testing.assert_allclose(motion.q[-1], problem.goal, atol=1e-6)
