"""DH extraction (symkin dh): published tables come back, FK and dynamics are kept.

Expected values: the published DH tables typed here from their sources (the UR support
article's UR5 table; the Franka Control Interface documentation's Panda table, modified
convention, flange 0.107 m along z7) and the naive NumPy DH model of tests/numeric_dh.py.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from numeric_dh import NumericRobot
from symkin import derive, load_robot, robot_from_toml
from symkin.derive import dh_proof
from symkin.derive.dh_extraction import extract_dh
from symkin.derive.dh_proof import (
    prove_forward_kinematics,
    random_configurations,
    symbolic_difference,
)
from symkin.emit.robot_toml import robot_toml
from symkin.errors import RobotError

DATA = Path(__file__).parent / "data"
# (theta offset, d, a, alpha) per row, alpha in degrees, lengths in metres.
UR5_PUBLISHED = [
    (0, 0.089159, 0, 90),
    (0, 0, -0.425, 0),
    (0, 0, -0.39225, 0),
    (0, 0.10915, 0, 90),
    (0, 0.09465, 0, -90),
    (0, 0.0823, 0, 0),
]
# Modified: (theta offset, d_i, a_{i-1}, alpha_{i-1}); the flange is the tool Tz(0.107).
PANDA_PUBLISHED = [
    (0, 0.333, 0, 0),
    (0, 0, 0, -90),
    (0, 0.316, 0, 90),
    (0, 0, 0.0825, 90),
    (0, 0.384, -0.0825, -90),
    (0, 0, 0, 90),
    (0, 0, 0.088, 90),
]


def rows_of(robot):
    return [
        (float(j.theta), float(j.d), float(j.a), math.degrees(float(j.alpha))) for j in robot.joints
    ]


def test_ur5_extracted_table_is_the_published_one():
    extraction = extract_dh(load_robot("ur5"), "standard")
    assert np.allclose(rows_of(extraction.robot), UR5_PUBLISHED, atol=1e-12)
    assert extraction.robot.base == sp.eye(4) and extraction.robot.tool == sp.eye(4)
    assert [s.case for s in extraction.steps] == [
        "intersecting",
        "parallel",
        "parallel",
        "intersecting",
        "intersecting",
        "coincident",
    ]


def test_panda_extracted_table_is_the_published_one_with_the_flange_as_tool():
    extraction = extract_dh(load_robot("panda"), "modified")
    assert np.allclose(rows_of(extraction.robot), PANDA_PUBLISHED, atol=1e-12)
    flange = np.eye(4)
    flange[2, 3] = 0.107
    assert extraction.robot.base == sp.eye(4)
    assert np.allclose(np.array(extraction.robot.tool, dtype=float), flange, atol=1e-15)
    assert extraction.robot.joints[1].alpha == -sp.pi / 2  # exact, not a float


def fk_difference(source, extracted, count=30):
    """Largest FK difference; the naive model has no flip, so a flipped joint gets -q."""
    reference, candidate = NumericRobot.from_robot(source), NumericRobot.from_robot(extracted)
    signs = np.array([-1.0 if joint.flip else 1.0 for joint in source.joints])
    return max(
        np.abs(reference.fk(signs * q) - candidate.fk(q)).max()
        for q in random_configurations(source, count, seed=7)
    )


@pytest.mark.slow
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_generic_tilted_arm_keeps_its_forward_kinematics(convention):
    source = load_robot(DATA / "dh_tilted_arm.toml")
    extraction = extract_dh(source, convention)
    assert fk_difference(source, extraction.robot) < 1e-12
    proof = prove_forward_kinematics(extraction)
    assert proof.method == "symbolic" and proof.symbolic_error < 1e-12
    assert not any(j.flip for j in extraction.robot.joints)


@pytest.mark.slow
@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize(
    "name", ["cylindrical_rtt_wrist", "panda", "planar_3r", "puma560", "rpr", "scara", "stanford"]
)
def test_every_catalogue_robot_keeps_its_forward_kinematics(name, convention):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        source = load_robot(name)
    extraction = extract_dh(source, convention)
    assert fk_difference(source, extraction.robot) < 1e-12
    assert prove_forward_kinematics(extraction).method == "symbolic"


def test_the_symbolic_comparison_sees_a_wrong_table():
    source = load_robot("ur5")
    model = extract_dh(source).robot
    joints = list(model.joints)
    joints[2] = replace(joints[2], d=sp.Float(1e-6))
    assert symbolic_difference(source, replace(model, joints=tuple(joints))) > 1e-7


def test_over_budget_the_proof_is_numeric_and_says_why(monkeypatch):
    monkeypatch.setattr(dh_proof, "SYMBOLIC_COEFFICIENTS", 10)
    proof = prove_forward_kinematics(extract_dh(load_robot("planar_2r")))
    assert proof.method == "numeric" and "budget" in proof.reason
    assert proof.numeric_error < 1e-12 and proof.configurations == 100
    assert "numeric only" in proof.summary()


@pytest.mark.parametrize(
    ("file", "words"),
    [
        ("dh_coincident_revolutes.toml", "joints 1 and 2 turn about the same line"),
        ("dh_parallel_prismatics.toml", "prismatic joint along the previous axis"),
    ],
)
def test_degenerate_chains_are_explained_not_tabled(file, words):
    with pytest.raises(RobotError, match=words) as caught:
        extract_dh(load_robot(DATA / file))
    assert str(caught.value).startswith(f"{DATA / file}: ")  # the file, not only the robot


def test_degenerate_urdf_names_the_file_and_the_joints():
    from symkin.io.urdf import robot_from_urdf

    link = '<link name="{}"/>'
    joint = (
        '<joint name="{}" type="continuous"><parent link="{}"/><child link="{}"/>'
        '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/></joint>'
    )
    text = (
        '<robot name="r">' + "".join(link.format(n) for n in "abc")
        + joint.format("yaw", "a", "b") + joint.format("spin", "b", "c") + "</robot>"
    )  # fmt: skip
    with pytest.raises(RobotError) as caught:
        extract_dh(robot_from_urdf(text, "twice.urdf"))
    assert str(caught.value).startswith("twice.urdf: joints 1 (yaw) and 2 (spin) turn about")


@pytest.mark.slow
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_written_robot_file_has_the_sources_dynamics(convention):
    from symkin.solve.evaluate import dynamic_state

    source = load_robot(DATA / "dh_tilted_arm.toml")
    text = robot_toml(extract_dh(source, convention).robot, "test")
    written = robot_from_toml(text, "written.toml")
    assert written.convention == convention
    rng = np.random.default_rng(3)
    for q in random_configurations(source, 4, seed=5):
        dq, ddq = rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 4)
        expected = dynamic_state(derive(source), q, dq, ddq)
        got = dynamic_state(derive(written), q, dq, ddq)
        assert np.allclose(got.mass_matrix, expected.mass_matrix, atol=1e-12)
        assert np.allclose(got.torque, expected.torque, atol=1e-11)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["panda", "puma560", "stanford", "scara"])
def test_round_trip_dh_urdf_dh_keeps_table_fk_and_dynamics(name, tmp_path):
    """DH -> symkin urdf -> load_robot(.urdf) -> symkin dh: the same table, FK and dynamics
    (rigid-body dynamics: URDF has no rotor inertia, so the PUMA's motor_inertia stays out)."""
    from symkin.emit.urdf import urdf_text
    from symkin.solve.evaluate import dynamic_state

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        source = load_robot(name)
        path = tmp_path / f"{name}.urdf"
        path.write_text(urdf_text(source, "round trip"))
        loaded = load_robot(path)
    direct = extract_dh(source, source.convention).robot
    again = extract_dh(loaded, source.convention).robot
    assert np.allclose(rows_of(again), rows_of(direct), atol=1e-9)
    assert fk_difference(source, again) < 1e-12
    if all(j.link is not None for j in source.joints):
        rigid = tuple(replace(j, link=replace(j.link, motor_inertia=0)) for j in source.joints)
        source = replace(source, joints=rigid)
        rng = np.random.default_rng(2)
        for q in random_configurations(source, 3, seed=9):
            dq, ddq = rng.uniform(-1, 1, source.dof), rng.uniform(-1, 1, source.dof)
            expected = dynamic_state(derive(source), q, dq, ddq).torque
            got = dynamic_state(derive(again), q, dq, ddq).torque
            assert np.allclose(got, expected, atol=1e-9)


def test_nearly_round_source_values_are_snapped_and_the_proof_says_so():
    """A URDF-style 1.57079632679 for pi/2 (UR's files): the table gets exact right angles,
    the FK moves by ~1e-11, and the proof explains the difference instead of failing."""
    text = (
        'name = "near_right"\nconvention = "placement"\nangles = "rad"\n'
        '[[joints]]\ntype = "revolute"\norigin = { xyz = [0, 0, 0.089159] }\naxis = [0, 0, 1]\n'
        '[[joints]]\ntype = "revolute"\n'
        "origin = { xyz = [0, 0.13585, 0], rpy = [0, 1.57079632679, 0] }\naxis = [0, 1, 0]\n"
        '[[joints]]\ntype = "revolute"\norigin = { xyz = [0, -0.1197, 0.425] }\naxis = [0, 1, 0]\n'
    )
    extraction = extract_dh(robot_from_toml(text, "near_right.toml"))
    assert all(j.alpha.is_zero or j.alpha.has(sp.pi) for j in extraction.robot.joints)
    proof = prove_forward_kinematics(extraction)
    assert 1e-13 < proof.numeric_error < 1e-9 and "not exactly round" in proof.snapping


def example_robot_data_file(relative: str) -> Path:
    from importlib.metadata import distribution

    robots = "cmeel.prefix/share/example-robot-data/robots"
    return Path(str(distribution("example-robot-data").locate_file(robots))) / relative


@pytest.mark.slow
def test_panda_urdf_of_example_robot_data_gives_the_published_table():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the fingers are lumped into the hand, said as a warning
        urdf = load_robot(
            example_robot_data_file("panda_description/urdf/panda.urdf"), tip="panda_link8"
        )
    extraction = extract_dh(urdf, "modified")
    assert np.allclose(rows_of(extraction.robot), PANDA_PUBLISHED, atol=1e-12)
    assert extraction.robot.base == sp.eye(4)
    assert np.allclose(np.array(extraction.robot.tool, dtype=float)[:3, 3], [0, 0, 0.107])


@pytest.mark.slow
def test_ur5_urdf_of_example_robot_data_gives_the_published_table_up_to_half_turns():
    """UR's base_link has its x axis opposite to the DH base frame's: every x axis turns half a
    turn about its z, which negates a and alpha; the tool frame adds theta_6 = pi
    (docs/dh-extraction.md)."""
    urdf = load_robot(example_robot_data_file("ur_description/urdf/ur5_robot.urdf"), tip="tool0")
    rows = rows_of(extract_dh(urdf, "standard").robot)
    turned = [(theta, d, -a, -alpha) for theta, d, a, alpha in UR5_PUBLISHED]
    turned[5] = (math.pi, *turned[5][1:])
    assert np.allclose(rows, turned, atol=1e-9)
