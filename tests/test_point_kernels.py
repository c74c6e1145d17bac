"""Point-kinematics and manipulability kernels of `symkin derive`.

Expected values: the reference evaluator (itself checked against finite differences in
test_motion.py) and NumPy's own sqrt(det(J J^T)) of the generated Jacobian.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import symkin
from symkin.cli import main
from symkin.kernels import point_kernels

POINTS = ((2, (0.1, -0.05, 0.2)), (1, (-0.3, 0.0, 0.1)))


@pytest.mark.parametrize("name", ["scara", "panda", "stanford"])
def test_point_kernels_match_the_reference_evaluator(name, tmp_path):
    robot = symkin.load_robot(name)
    points = [(min(link, robot.dof), xyz) for link, xyz in POINTS]
    flags = [f"--point={link}:{','.join(map(str, xyz))}" for link, xyz in points]
    args = ["derive", name, "--out", str(tmp_path), "--emit", "numpy", *flags]
    assert main(args) == 0
    path = tmp_path / "numpy" / f"{name}_kinematics.py"
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rng = np.random.default_rng(4)
    model = symkin.derive(robot)
    for _ in range(3):
        q, dq, ddq = (rng.uniform(-1, 1, robot.dof) for _ in range(3))
        state = symkin.kinematic_state(model, q, dq, ddq, points=points)
        for k, expected in enumerate(state.points, start=1):
            position, velocity, acceleration = getattr(module, f"point{k}")(q, dq, ddq)
            np.testing.assert_allclose(position, expected.position, atol=1e-12)
            np.testing.assert_allclose(velocity, expected.velocity, atol=1e-12)
            np.testing.assert_allclose(acceleration, expected.acceleration, atol=1e-12)


@pytest.mark.parametrize("name", ["planar_2r", "scara", "puma560"])
def test_manipulability_kernel_is_yoshikawa_measure(name, tmp_path):
    assert main(["derive", name, "--out", str(tmp_path), "--emit", "numpy"]) == 0
    path = tmp_path / "numpy" / f"{name}_kinematics.py"
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    model = symkin.derive(symkin.load_robot(name))
    rows = [("x", "y", "z", "wx", "wy", "wz").index(r) for r in model.task_rows]
    states = np.random.default_rng(8).uniform(-1.5, 1.5, size=(6, model.robot.dof))
    task = module.jacobian(states)[:, rows, :]
    expected = np.sqrt(np.linalg.det(task @ np.swapaxes(task, 1, 2)))
    np.testing.assert_allclose(module.manipulability(states), expected, rtol=1e-9, atol=1e-12)


def test_puma_point_kernel_costs_a_third_of_the_u_matrix_form():
    """The recursive point-motion kernel of the PUMA's tool point (link 6).

    Old cost: 4,485 operations, measured on this machine at commit b930f3c (before the
    recursion) by CSE of the U-matrix closed forms for the point (0.1, -0.05, 0.2) in frame 6;
    the issue quotes about 2,800 for another point.  A third of it is 1,495.

    Independent bound of the recursion: per revolute link, with dense 3x3 rotations
    (``R x``: 9 multiplications, 6 additions), ``w`` 21, ``dw`` 36, the products and ``U``
    18, the origin's ``dv`` 51 and ``v`` 39, carrying ``p, v, a`` back one link 48, one sine
    and one cosine 2: 215 operations; then ``v + w x r`` and ``dv + U r`` 30 and the base
    transform 48.  So at most ``215 n + 78`` = 1,368 for six links.
    """
    model = symkin.derive(symkin.load_robot("puma560"))
    kernel = point_kernels(model, [(6, (0.1, -0.05, 0.2))])[0]
    total = kernel.operation_counts["total"]
    assert total <= 215 * 6 + 78
    assert total <= 4485 // 3
