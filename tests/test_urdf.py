"""Reading URDF files: the chain, folded fixed joints, lumped links, limits, names, and every
bad input as one message naming the file and the joint or link (library and CLI, exit 2).

Small URDFs are written inline; expected values are worked by hand in the comments.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from symkin.cli import main
from symkin.errors import ParameterError, RobotError, RobotWarning
from symkin.io.urdf import robot_from_urdf

INERTIAL = (
    '<inertial><origin xyz="{c}"/><mass value="{m}"/>'
    '<inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial>'
)


def link(name: str, mass: float | None = None, com: str = "0 0 0", inertia: float = 0.01) -> str:
    body = "" if mass is None else INERTIAL.format(c=com, m=mass, i=inertia)
    return f'<link name="{name}">{body}</link>'


def joint(name, parent, child, kind="revolute", xyz="0 0 0", rpy="0 0 0", axis="0 0 1", extra=""):
    limit = '<limit lower="-1" upper="1" velocity="2" effort="30"/>' if kind == "revolute" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}{extra}</joint>'
    )


def urdf(*parts: str, name: str = "two_link") -> str:
    return f'<?xml version="1.0"?><robot name="{name}">{"".join(parts)}</robot>'


# A planar 2R along x: links 0.5 and 0.3 m, a fixed flange 0.1 m beyond the second joint.
TWO_LINK = urdf(
    link("base"),
    link("upper", 2.0, "0.25 0 0"),
    link("fore", 1.0, "0.15 0 0"),
    link("flange", 0.5, "0 0 0"),
    joint("shoulder", "base", "upper"),
    joint("elbow", "upper", "fore", xyz="0.5 0 0"),
    joint("flange_joint", "fore", "flange", kind="fixed", xyz="0.3 0 0"),
)


def test_planar_two_link_pose_and_folded_flange():
    robot = robot_from_urdf(TWO_LINK, "two.urdf")
    assert robot.convention == "placement" and robot.dof == 2
    assert [j.name for j in robot.joints] == ["shoulder", "elbow"]
    fk = sp.lambdify([symkin.joint_symbols(2)], symkin.derive(robot).forward_kinematics)
    q1, q2 = 0.4, -1.1
    # Tip = 0.5 (cos q1, sin q1) + 0.3 (cos(q1+q2), sin(q1+q2)), by hand.
    expected_x = 0.5 * math.cos(q1) + 0.3 * math.cos(q1 + q2)
    expected_y = 0.5 * math.sin(q1) + 0.3 * math.sin(q1 + q2)
    pose = np.array(fk([q1, q2]), dtype=float)
    np.testing.assert_allclose(pose[:2, 3], [expected_x, expected_y], atol=1e-15)


def test_fixed_link_is_lumped_into_the_moving_body():
    robot = robot_from_urdf(TWO_LINK, "two.urdf")
    body = robot.joints[1].link
    # fore (1 kg at x = 0.15) + flange (0.5 kg at x = 0.3): 1.5 kg at x = 0.2; about that
    # centre, the y and z moments gain 1 * 0.05^2 + 0.5 * 0.1^2 = 0.0075.
    assert float(body.mass) == pytest.approx(1.5)
    assert [float(c) for c in body.com] == pytest.approx([0.2, 0.0, 0.0])
    ixx, iyy, izz = (float(v) for v in body.inertia[:3])
    assert (ixx, iyy, izz) == pytest.approx((0.02, 0.0275, 0.0275))


def test_limits_velocity_and_effort_are_carried_continuous_has_none():
    text = TWO_LINK.replace('name="elbow" type="revolute"', 'name="elbow" type="continuous"')
    robot = robot_from_urdf(text, "two.urdf")
    shoulder, elbow = robot.joints
    assert shoulder.limits == (-1.0, 1.0)
    assert (shoulder.max_velocity, shoulder.max_effort) == (2.0, 30.0)
    assert elbow.type == "revolute" and elbow.limits is None


def test_names_are_made_valid_identifiers():
    text = TWO_LINK.replace('"shoulder"', '"Shoulder-Pan"').replace(
        'robot name="two_link"', 'robot name="UR5e"'
    )
    robot = robot_from_urdf(text, "two.urdf")
    assert robot.name == "ur5e"
    assert robot.joints[0].name == "Shoulder_Pan"


def test_several_leaves_need_a_tip_and_tip_base_choose_the_chain():
    text = TWO_LINK.replace(
        "</robot>", link("camera") + joint("cam", "upper", "camera", kind="fixed") + "</robot>"
    )
    with pytest.raises(RobotError, match=r"2 leaves \(flange, camera\)"):
        robot_from_urdf(text, "two.urdf")
    with pytest.warns(RobotWarning, match="held at zero and their links lumped .*: elbow"):
        assert robot_from_urdf(text, "two.urdf", tip="camera").dof == 1
    short = robot_from_urdf(text, "two.urdf", base="upper", tip="flange")
    assert [j.name for j in short.joints] == ["elbow"]


def test_load_robot_reads_urdf_files(tmp_path: Path):
    path = tmp_path / "two.urdf"
    path.write_text(TWO_LINK, encoding="utf-8")
    robot = symkin.load_robot(path)
    assert robot.file == str(path) and robot.source == "two.urdf"
    with pytest.raises(RobotError, match="tip or base link is chosen in URDF files only"):
        symkin.load_robot("planar_2r", tip="x")


def test_non_unit_axis_is_normalised_and_said_once():
    text = TWO_LINK.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 3"/>', 1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robot_from_urdf(text, "two.urdf")
    said = [str(w.message) for w in caught if issubclass(w.category, RobotWarning)]
    assert said == [
        "two.urdf: joint 'shoulder': 'axis' [0.0, 0.0, 3.0] is not a unit vector; normalised"
    ]
    assert robot.joints[0].placement == sp.ImmutableMatrix(sp.eye(4))


def test_urdf_without_inertials_asks_for_them_when_dynamics_need_numbers():
    bare = urdf(link("a"), link("b"), joint("j", "a", "b"), name="bare")
    robot = robot_from_urdf(bare, "bare.urdf")
    assert robot.joints[0].link is None
    model = symkin.derive(robot)
    from symkin.solve.evaluate import dynamics_arguments

    with pytest.raises(ParameterError, match=r"^bare.urdf: bare has no inertial data for m1"):
        dynamics_arguments(model)


BAD = {
    "malformed": ("<robot name='x'><link name='a'></robot>", "not a valid URDF"),
    "missing-link": (
        urdf(link("a"), joint("j", "a", "nowhere")),
        "joint 'j': child link 'nowhere' does not exist",
    ),
    "two-parents": (
        urdf(link("a"), link("b"), link("c"), joint("j1", "a", "c"), joint("j2", "b", "c")),
        "link 'c' is the child of joints 'j1' and 'j2': a loop",
    ),
    "cycle": (
        urdf(link("a"), link("b"), joint("j1", "a", "b"), joint("j2", "b", "a")),
        "a loop through link",
    ),
    "floating": (
        urdf(link("a"), link("b"), joint("j", "a", "b", kind="floating")),
        "joint 'j' is floating",
    ),
    "negative-effort": (
        TWO_LINK.replace('effort="30"', 'effort="-1"', 1),
        "joint 'shoulder': <limit effort> must be positive (0: not given), got -1",
    ),
    "planar": (urdf(link("a"), link("b"), joint("j", "a", "b", kind="planar")),
               "joint 'j' is planar"),
    "mimic": (
        urdf(
            link("a"), link("b"), link("c"), joint("j1", "a", "b"),
            joint("j2", "b", "c", extra='<mimic joint="j1"/>'),
        ),
        "joint 'j2' mimics joint 'j1'",
    ),
    "zero-axis": (urdf(link("a"), link("b"), joint("j", "a", "b", axis="0 0 0")),
                  "joint 'j': 'axis' must be a nonzero direction"),
    "only-fixed": (urdf(link("a"), link("b"), joint("j", "a", "b", kind="fixed")),
                   "no moving joint between link 'a' and link 'b'"),
    # The parser takes inf/NaN and repeated names; before these checks an infinite origin was a
    # message without file or joint, the rest loaded silently.
    "infinite-origin": (urdf(link("a"), link("b"), joint("j", "a", "b", xyz="inf 0 0")),
                        "joint 'j': origin xyz must be finite numbers"),
    "nan-rpy": (urdf(link("a"), link("b"), joint("j", "a", "b", rpy="0 nan 0")),
                "joint 'j': origin rpy must be finite numbers"),
    "lower-above-upper": (
        urdf(link("a"), link("b"), joint("j", "a", "b").replace('lower="-1" upper="1"',
                                                                 'lower="1" upper="-1"')),
        "joint 'j': limit lower=1.0 is above upper=-1.0",
    ),
    "repeated-joint": (urdf(link("a"), link("b"), link("c"), joint("j", "a", "b"),
                            joint("j", "b", "c")),
                       "two joints are named 'j'"),
    "repeated-link": (urdf(link("a"), link("b", 1.0), link("b"), joint("j", "a", "b")),
                      "two links are named 'b'"),
    "negative-mass": (urdf(link("a"), link("b", -1.0), joint("j", "a", "b")),
                      "link 'b': inertial mass must be >= 0, got -1"),
    "not-psd": (
        urdf(link("a"), link("b", 1.0).replace('ixy="0"', 'ixy="0.5"'), joint("j", "a", "b")),
        "link 'b': the inertia tensor is not positive semi-definite",
    ),
}  # fmt: skip


def test_elements_symkin_does_not_read_cannot_make_a_file_invalid():
    """PR2's old-style <transmission> and iCub's <texture> without a filename (both in
    example-robot-data, loaded by Pinocchio) made the strict parser reject the whole file."""
    extras = (
        '<material name="m"><texture/></material>'
        '<transmission name="t"><type>x</type><joint name="shoulder"/></transmission>'
    )
    text = TWO_LINK.replace('<link name="upper">', f'<link name="upper"><visual>{extras}</visual>')
    text = text.replace("</robot>", f"{extras}<gazebo><x/></gazebo></robot>")
    loaded = robot_from_urdf(text, "extras.urdf")
    assert loaded == robot_from_urdf(TWO_LINK, "extras.urdf")


@pytest.mark.parametrize("case", list(BAD))
def test_bad_urdf_is_one_message_naming_file_and_joint_or_link(case):
    text, message = BAD[case]
    with pytest.raises(RobotError) as caught:
        robot_from_urdf(text, "bad.urdf")
    assert str(caught.value).startswith("bad.urdf: ")
    assert message in str(caught.value)


@pytest.mark.parametrize(
    "case", ["malformed", "missing-link", "mimic", "zero-axis", "infinite-origin", "negative-mass"]
)
def test_cli_reports_bad_urdf_in_one_line_exit_2(case, tmp_path, capsys):
    path = tmp_path / "bad.urdf"
    path.write_text(BAD[case][0], encoding="utf-8")
    code = main(["show", str(path)])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err.startswith(f"symkin: error: {path}: ") and BAD[case][1] in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_cli_names_the_leaves_and_takes_tip(tmp_path, capsys):
    text = TWO_LINK.replace(
        "</robot>", link("camera") + joint("cam", "upper", "camera", kind="fixed") + "</robot>"
    )
    path = tmp_path / "tree.urdf"
    path.write_text(text, encoding="utf-8")
    assert main(["show", str(path)]) == 2
    assert "2 leaves (flange, camera)" in capsys.readouterr().err
    assert main(["eval", str(path), "--tip", "flange", "--q", "0.4,-1.1", "--json"]) == 0
    out = capsys.readouterr().out
    assert '"position"' in out


def test_cli_asks_for_missing_inertials_naming_the_file(tmp_path, capsys):
    path = tmp_path / "bare.urdf"
    path.write_text(urdf(link("a"), link("b"), joint("j", "a", "b"), name="bare_cli"), "utf-8")
    code = main(["eval", str(path), "--q", "0.1", "--dq", "0", "--ddq", "0", "--dynamics"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(
        f"symkin: error: {path}: bare_cli has no inertial data for m1"
    )
    assert len(err.strip().splitlines()) == 1


def test_a_long_robot_name_is_shortened_to_the_limit():
    robot = robot_from_urdf(
        TWO_LINK.replace('robot name="two_link"', f'robot name="{"R" * 300}"'), "u.urdf"
    )
    assert robot.name == "r" * 58  # 64 characters less room for the "_robot" suffix
