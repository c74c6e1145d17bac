"""Every catalogue robot has inertial data, and every dynamics command works on it (issue 21).

The robots without published data carry uniform solid cylinders whose material and dimensions
their files state; :data:`CYLINDERS` types those dimensions again, and the masses and tensors
are recomputed here from the textbook solid-cylinder formulas (m = rho pi r^2 l; about the
COM, m r^2 / 2 about the axis and m (3 r^2 + l^2) / 12 across it), to the files' four
significant digits.  The UR5's masses and COMs are Robotics Toolbox's (``models.DH.UR5``),
compared with the installed toolbox.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from symkin import load_robot
from symkin.cli import main
from symkin.io.robot_file import catalogue_names

ALU, STEEL = 2700.0, 7850.0
X, Y, Z = np.eye(3)

# robot: per link (density, radius, length, axis in frame i, COM in frame i)
CYLINDERS = {
    "planar_2r": [(ALU, 0.02, 1.0, X, (-0.5, 0, 0))] * 2,
    "planar_3r": [
        (ALU, 0.02, 1.0, X, (-0.5, 0, 0)),
        (ALU, 0.02, 0.8, X, (-0.4, 0, 0)),
        (ALU, 0.02, 0.5, X, (-0.25, 0, 0)),
    ],
    "scara": [
        (ALU, 0.03, 0.325, X, (-0.1625, 0, 0)),
        (ALU, 0.025, 0.225, X, (-0.1125, 0, 0)),
        (STEEL, 0.01, 0.2, Z, (0, 0, 0.1)),
    ],
    "rpr": [
        (ALU, 0.05, 0.2, Y, (0, 0, 0)),
        (ALU, 0.025, 1.0, Y, (0, -0.5, 0)),
        (ALU, 0.02, 1.0, X, (-0.5, 0, 0)),
    ],
    "cylindrical_rtt_wrist": [
        (ALU, 0.06, 0.5, Z, (0, 0, -0.25)),
        (ALU, 0.08, 0.15, Y, (0, 0, 0)),
        (ALU, 0.03, 0.8, Z, (0, 0, -0.4)),
        (ALU, 0.03, 0.06, Z, (0, 0, 0)),
        (ALU, 0.03, 0.06, Z, (0, 0, 0)),
        (ALU, 0.03, 0.1, Z, (0, 0, -0.05)),
    ],
    "stanford": [
        (ALU, 0.06, 0.412, Y, (0, 0.206, 0)),
        (ALU, 0.05, 0.154, Y, (0, -0.077, 0)),
        (ALU, 0.03, 1.0, Z, (0, 0, -0.5)),
        (ALU, 0.03, 0.06, Z, (0, 0, 0)),
        (ALU, 0.03, 0.06, Z, (0, 0, 0)),
        (ALU, 0.02, 0.263, Z, (0, 0, -0.1315)),
    ],
}


def cylinder(density: float, radius: float, length: float, axis: np.ndarray):
    mass = density * math.pi * radius**2 * length
    along = np.outer(axis, axis)
    tensor = mass * radius**2 / 2 * along + mass * (3 * radius**2 + length**2) / 12 * (
        np.eye(3) - along
    )
    return mass, tensor


def numbers(link) -> tuple[float, np.ndarray, np.ndarray]:
    return (
        float(link.mass),
        np.array([float(c) for c in link.com]),
        np.array(link.inertia_matrix, dtype=float),
    )


def quietly_load(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # catalogue data load without any warning
        return load_robot(name)


@pytest.mark.parametrize("name", catalogue_names())
def test_every_catalogue_link_has_physical_data(name: str) -> None:
    robot = quietly_load(name)
    for joint in robot.joints:
        assert joint.link is not None, f"{name}: a link without inertial data"
        mass, _, tensor = numbers(joint.link)
        moments = np.linalg.eigvalsh(tensor)
        assert mass >= 0 and moments[0] >= 0


@pytest.mark.parametrize("name", sorted(CYLINDERS))
def test_cylinder_data_follow_from_the_stated_dimensions(name: str) -> None:
    robot = quietly_load(name)
    for joint, (density, radius, length, axis, com) in zip(
        robot.joints, CYLINDERS[name], strict=True
    ):
        mass, tensor = cylinder(density, radius, length, axis)
        got_mass, got_com, got_tensor = numbers(joint.link)
        assert got_mass == pytest.approx(mass, rel=5e-4)
        np.testing.assert_allclose(got_com, com, atol=1e-12)
        np.testing.assert_allclose(got_tensor, tensor, rtol=5e-4, atol=1e-12)


def test_ur5_masses_and_coms_are_the_toolbox_values() -> None:
    from roboticstoolbox.models.DH import UR5

    reference = UR5()
    for joint, link in zip(quietly_load("ur5").joints, reference.links, strict=True):
        mass, com, tensor = numbers(joint.link)
        assert mass == link.m
        np.testing.assert_array_equal(com, np.asarray(link.r, dtype=float))
        assert np.all(np.linalg.eigvalsh(tensor) > 0)


def configurations(name: str) -> tuple[list[float], list[float]]:
    """A start inside the joint limits and a goal 0.2 further (or back, at an upper limit)."""
    start, goal = [], []
    for joint in quietly_load(name).joints:
        low, high = joint.limits or (-math.inf, math.inf)
        value = min(max(0.3, low + 0.1), high - 0.1)
        start.append(value)
        goal.append(value + 0.2 if value + 0.2 < high else value - 0.2)
    return start, goal


def text(values: list[float]) -> str:
    return ",".join(repr(v) for v in values)


@pytest.mark.slow
@pytest.mark.parametrize("name", catalogue_names())
def test_eval_dynamics_on_every_catalogue_robot(name: str, capsys) -> None:
    """M symmetric positive definite and tau = M ddq + c + G + F at the printed state."""
    q, _ = configurations(name)
    n = len(q)
    dq, ddq = [0.3] * n, [-0.2] * n
    argv = ["eval", name, "--q", text(q), "--dq", text(dq), "--ddq", text(ddq), "--dynamics"]
    assert main([*argv, "--json"]) == 0
    captured = capsys.readouterr()
    assert "warning" not in captured.err
    data = json.loads(captured.out)
    M = np.array(data["M"])
    np.testing.assert_allclose(M, M.T, atol=1e-12)
    assert np.linalg.eigvalsh(M)[0] > 0
    assert np.all(np.isfinite(data["tau"]))


@pytest.mark.slow
@pytest.mark.parametrize("name", catalogue_names())
def test_trajopt_on_every_catalogue_robot(name: str, tmp_path, capsys) -> None:
    """The issue's failure: `symkin trajopt planar_2r` ended with twenty missing symbols."""
    start, goal = configurations(name)
    argv = ["trajopt", name, "--from", text(start), "--to", text(goal)]
    status = main([*argv, "--time", "1", "--intervals", "8", "--out", str(tmp_path)])
    assert status == 0, capsys.readouterr().err
    result = json.loads((tmp_path / "trajectory.json").read_text())
    assert result
