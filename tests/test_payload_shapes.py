"""Robot files: a link's inertia by shape and density, and the ``[payload]`` table.

Independent checks: textbook tensors by hand; a point-mass payload at the tool under gravity
holds the same joint torques as the external wrench ``(m g, 0)`` at the tool point (another
code path: the wrench kernel); errors name the file and key.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import symkin
from symkin.errors import RobotError
from symkin.runtime.modules import generated_numpy_module

ARM = """
name = "rods"
convention = "standard"
gravity = [0, -9.81, 0]
[parameters]
L1 = 0.8
L2 = 0.6
[[joints]]
type = "revolute"
a = "L1"
[joints.link]
com = [-0.4, 0, 0]
density = 2700
shape = {{ type = "cylinder", radius = 0.02, length = 0.8, axis = "x" }}
[[joints]]
type = "revolute"
a = "L2"
[joints.link]
mass = 1.5
com = [-0.3, 0, 0]
inertia = {{ ixx = 0.001, iyy = 0.05, izz = 0.05 }}
{tool}
{payload}
"""


def load(tool: str = "", payload: str = "") -> symkin.Robot:
    return symkin.robot_from_toml(ARM.format(tool=tool, payload=payload), "rods.toml")


def test_cylinder_link_from_density_by_hand():
    link = load().joints[0].link
    mass = 2700 * math.pi * 0.02**2 * 0.8
    assert float(link.mass) == pytest.approx(mass)
    ixx, iyy, izz, ixy, ixz, iyz = (float(v) for v in link.inertia)
    assert ixx == pytest.approx(mass * 0.02**2 / 2)  # about the rod's own axis (x)
    assert iyy == pytest.approx(mass * (3 * 0.02**2 + 0.8**2) / 12)
    assert izz == pytest.approx(iyy) and ixy == ixz == iyz == 0


@pytest.mark.parametrize(
    ("shape", "expected"),
    [
        ('{ type = "box", size = [0.1, 0.2, 0.3] }', [0.13 / 12, 0.10 / 12, 0.05 / 12]),
        ('{ type = "sphere", radius = 0.1 }', [0.004] * 3),
        (
            '{ type = "tube", inner_radius = 0.1, outer_radius = 0.2, length = 0.3, axis = "y" }',
            [0.24 / 12, 0.05 / 2, 0.24 / 12],
        ),
    ],
)
def test_payload_shapes_with_a_mass(shape: str, expected: list[float]):
    # a 1 kg payload centred at the tool (= origin 2, no tool offset) and the last link
    # (1.5 kg at x = -0.3): mass, centre and tensor about the common centre by hand (Steiner)
    link = load(payload=f"[payload]\nmass = 1.0\nshape = {shape}").joints[1].link
    bare = load().joints[1].link
    assert float(link.mass) == pytest.approx(2.5)
    centre = (1.5 * -0.3 + 1.0 * 0.0) / 2.5
    assert float(link.com[0]) == pytest.approx(centre)
    steiner = 1.5 * (-0.3 - centre) ** 2 + 1.0 * (0.0 - centre) ** 2
    ixx, iyy, izz = (float(v) for v in link.inertia[:3])
    assert ixx == pytest.approx(float(bare.inertia[0]) + expected[0])
    assert iyy == pytest.approx(float(bare.inertia[1]) + expected[1] + steiner)
    assert izz == pytest.approx(float(bare.inertia[2]) + expected[2] + steiner)


def test_point_payload_equals_a_gravity_wrench_at_the_tool():
    tool = "[tool]\nxyz = [0.1, 0.05, 0]\nrpy = [0, 0, 30]"
    payload = "[payload]\nmass = 2.0\ncom = [0, 0, 0]"
    carrying = generated_numpy_module(symkin.derive(load(tool, payload)))
    bare = generated_numpy_module(symkin.derive(load(tool)))
    rng = np.random.default_rng(12)
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 2)
        weight = np.array([0.0, -9.81 * 2.0, 0.0, 0.0, 0.0, 0.0])  # m g on the payload
        expected = bare.static_torque(q, weight)
        np.testing.assert_allclose(carrying.gravity(q), expected, atol=1e-12)


@pytest.mark.parametrize(
    ("payload", "message"),
    [
        ("[payload]\nmass = 1\ninertia = { ixx = 1 }\nshape = { type = 'sphere', radius = 1 }",
         "'payload.inertia' or 'payload.shape', not both"),
        ("[payload]\nshape = { type = 'sphere', radius = 1 }", "needs 'mass' or 'density'"),
        ("[payload]\nmass = 1\nshape = { type = 'cone', radius = 1 }",
         "'payload.shape.type' must be"),
        ("[payload]\nmass = 1\nshape = { type = 'sphere', radius = -1 }",
         "'payload.shape.radius' must be > 0"),
        ("[payload]\nmass = 1\nshape = { type = 'sphere' }", "'payload.shape.radius' is missing"),
        ("[payload]\nmass = 1\nshape = { type = 'box', size = [1, 2] }",
         "'payload.shape.size' must be a list of 3"),
        ("[payload]\nmass = 1\nshape = { type = 'tube', inner_radius = 2, outer_radius = 1, "
         "length = 1 }", "must be less than 'outer_radius'"),
        ("[payload]\nmass = 1\nshape = { type = 'sphere', radius = 1, axis = 'x' }", "axis"),
        ("[payload]\ndensity = 1", "'payload.density' needs a 'shape'"),
        ("[payload]\nmas = 1", "mas"),
    ],
)  # fmt: skip
def test_bad_tables_are_one_located_error(payload: str, message: str):
    with pytest.raises(RobotError, match=r"rods\.toml") as error:
        load(payload=payload)
    assert message in str(error.value)


def test_payload_needs_the_last_link_data():
    text = ARM.format(tool="", payload="[payload]\nmass = 1.0")
    last = text.rindex("[joints.link]")
    text = text[:last] + text[text.index("[payload]") :]
    with pytest.raises(RobotError, match="'payload' needs the last joint's"):
        symkin.robot_from_toml(text, "rods.toml")
