"""The robot picture, named poses, Jupyter displays and matplotlib hygiene.

The frames drawn are checked against a naive numeric DH product (tests/numeric_dh.py); a pose
in degrees against its radians by hand; the backend test fails if any plot calls
``matplotlib.use`` or opens a pyplot figure.
"""

from __future__ import annotations

import json
import math

import matplotlib
import numpy as np
import pytest

import symkin
from numeric_dh import NumericRobot
from symkin.cli import main
from symkin.errors import RobotError
from symkin.io import load_robot, robot_from_toml
from symkin.solve.draw import arm_frames, draw_arm
from symkin.solve.ellipsoid import ellipsoids_at
from symkin.solve.workspace import sample_workspace
from symkin.solve.workspace_plot import plot_ellipsoids, plot_workspace

PNG = b"\x89PNG\r\n\x1a\n"

POSED = """
name = "posed_2r"
angles = "deg"
[parameters]
L1 = 1.0
L2 = 0.5
[poses]
home = [0, 90]
folded = [45, -170]
[[joints]]
type = "revolute"
a = "L1"
[[joints]]
type = "revolute"
a = "L2"
"""


def assert_picture(path) -> None:
    import matplotlib.image

    assert path.read_bytes()[:8] == PNG
    pixels = matplotlib.image.imread(path)
    colours = np.unique(pixels.reshape(-1, pixels.shape[-1]).round(2), axis=0)
    assert len(colours) > 30


def test_plots_leave_the_backend_and_pyplot_alone(tmp_path) -> None:
    import matplotlib.pyplot as plt

    before = matplotlib.get_backend()
    matplotlib.use("svg")  # what a user might have chosen; the old code switched it to Agg
    try:
        figures = plt.get_fignums()
        model = symkin.derive(load_robot("planar_2r"), closed_forms=False)
        draw_arm(model, [0.3, 0.4], tmp_path / "arm.png", frames=True, labels=True)
        assert matplotlib.get_backend() == "svg"
        assert plt.get_fignums() == figures  # no pyplot figure opened (or left open)
    finally:
        matplotlib.use(before)
    assert_picture(tmp_path / "arm.png")


@pytest.mark.slow
def test_workspace_picture(tmp_path) -> None:
    model = symkin.derive(load_robot("puma560"), closed_forms=False)
    workspace = sample_workspace(model, 4000, chunk=2000)
    plot_workspace(workspace, tmp_path / "w.png")
    assert_picture(tmp_path / "w.png")
    q = [0.0, 0.3, -0.5, 0.0, 0.4, 0.0]
    plot_ellipsoids(model, ellipsoids_at(model, q), tmp_path / "e.png")
    assert_picture(tmp_path / "e.png")
    assert workspace._repr_png_()[:8] == PNG


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_drawn_frames_are_the_dh_product(name: str) -> None:
    robot = load_robot(name)
    model = symkin.derive(robot, closed_forms=False)
    reference = NumericRobot.from_robot(robot)
    q = np.random.default_rng(2).uniform(-1, 1, robot.dof)
    arm = arm_frames(model, q)
    np.testing.assert_allclose(arm.frames, np.array(reference.frames(q)), atol=1e-12)
    np.testing.assert_allclose(arm.tool, reference.fk(q), atol=1e-12)
    # Standard DH: joint i turns about z of frame i-1.
    np.testing.assert_allclose(arm.joint_frames[:, :3, 2], arm.frames[:-1, :3, 2], atol=1e-12)


def test_poses_are_read_in_the_files_angle_unit() -> None:
    robot = robot_from_toml(POSED, "posed.toml")
    poses = dict(robot.poses)
    assert poses["home"] == pytest.approx((0.0, math.pi / 2))
    assert poses["folded"] == pytest.approx((math.pi / 4, -170 * math.pi / 180))
    with pytest.raises(RobotError, match=r"poses.home.*2 numbers"):
        robot_from_toml(POSED.replace("home = [0, 90]", "home = [0]"), "posed.toml")
    with pytest.raises(RobotError, match="poses"):
        robot_from_toml(POSED.replace("home = [0, 90]", 'home = [0, "x"]'), "posed.toml")


@pytest.mark.slow
def test_cli_draw_with_a_named_pose(capsys, tmp_path) -> None:
    robot_file = tmp_path / "posed.toml"
    robot_file.write_text(POSED)
    out = tmp_path / "arm.png"
    status = main(["draw", str(robot_file), "--pose", "home", "--out", str(out), "--frames"])
    assert status == 0
    assert_picture(out)
    status = main(["ellipsoid", str(robot_file), "--pose", "home", "--json"])
    assert status == 0
    # At q = (0, 90 deg): tool at (L1, L2); manipulability L1 L2 |sin q2| = 0.5.
    data = json.loads(capsys.readouterr().out)
    assert data["manipulability"] == pytest.approx(0.5)
    assert data["position"] == pytest.approx([1.0, 0.5, 0.0])
    status = main(["draw", str(robot_file), "--pose", "away", "--out", str(out)])
    assert status == 2
    assert "home, folded" in capsys.readouterr().err


def test_jupyter_displays() -> None:
    robot = robot_from_toml(POSED, "posed.toml")
    model = symkin.derive(robot, closed_forms=False)
    assert model._repr_png_()[:8] == PNG
    latex = model._repr_latex_()
    assert latex.startswith("$T^{0}_{2} = ") and r"\cos" in latex and latex.endswith("$")
