"""Robot files (TOML) -> Robot: valid files, every validation error, and property tests."""

from __future__ import annotations

import datetime as dt
import math
import time
import warnings
from pathlib import Path
from typing import Any

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symkin.errors import RobotError, RobotWarning
from symkin.io import catalogue_names, load_robot, robot_file, robot_from_toml, robot_tables
from symkin.names import robot_name_reason
from symkin.robot import Robot

FILE = "robots/arm.toml"
HEADER = 'name = "arm"\n'
PI = sp.pi


def S(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


def load(text: str) -> Robot:
    return robot_from_toml(text, FILE)


def error_of(text: str) -> str:
    with pytest.raises(RobotError) as info:
        load(text)
    return str(info.value)


def same(x: sp.Expr, y: sp.Expr) -> bool:
    return sp.expand(sp.sympify(x) - sp.sympify(y)) == 0


# Independent reference rotations (active, right-handed), not symkin.spatial.
def Rx(t: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[1, 0, 0], [0, sp.cos(t), -sp.sin(t)], [0, sp.sin(t), sp.cos(t)]])


def Ry(t: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[sp.cos(t), 0, sp.sin(t)], [0, 1, 0], [-sp.sin(t), 0, sp.cos(t)]])


def Rz(t: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[sp.cos(t), -sp.sin(t), 0], [sp.sin(t), sp.cos(t), 0], [0, 0, 1]])


def frame(xyz: list[sp.Expr], rpy: list[sp.Expr]) -> sp.Matrix:
    R = Rz(rpy[2]) * Ry(rpy[1]) * Rx(rpy[0])
    T = sp.eye(4)
    T[:3, :3] = R
    T[:3, 3] = sp.Matrix(xyz)
    return T


def matrices_equal(a: sp.MatrixBase, b: sp.MatrixBase) -> bool:
    return a.shape == b.shape and all(same(x, y) for x, y in zip(a, b, strict=True))


# --------------------------------------------------------------------------------------------
# A minimal TOML writer (no third-party TOML writer is installed).  Every value is written
# inline, which is valid TOML and reads back into the same Python structure.
# --------------------------------------------------------------------------------------------


def toml_string(text: str) -> str:
    out = []
    for ch in text:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return repr(value)  # nan, inf, -inf, 1e-05 are valid TOML as written by repr
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, dt.date):
        return value.isoformat()
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        pairs = (f"{toml_string(k)} = {toml_value(v)}" for k, v in value.items())
        return "{" + ", ".join(pairs) + "}"
    raise TypeError(value)


def to_toml(document: dict[str, Any]) -> str:
    return "".join(f"{toml_string(k)} = {toml_value(v)}\n" for k, v in document.items())


def test_toml_writer_round_trips() -> None:
    import tomllib

    doc = {
        "a": 1,
        "b": -0.5,
        "c": 'x"\\\n\x7f',
        "d": [1, [2.5, "z"]],
        "e": {"f g": {"h": True}},
        "j": [{"k": 1}],
        "day": dt.date(2020, 1, 2),
    }
    assert tomllib.loads(to_toml(doc)) == doc


# --------------------------------------------------------------------------------------------
# Valid files
# --------------------------------------------------------------------------------------------

RPR = """
name = "rpr_example"
title = "RPR arm of the lecture notes, Table 14-1"
source = "lecture notes, chapter 14"
convention = "standard"
angles = "deg"
gravity = [0, 0, -9.81]

[parameters]
L3 = 1.0

[[joints]]
type = "revolute"
alpha = 90
name = "shoulder"
limits = [-170, 170]

[[joints]]
type = "prismatic"
theta = 90
alpha = 90
limits = [0, 0.5]

[[joints]]
type = "revolute"
a = "L3"
"""


def test_contract_example_loads() -> None:
    robot = load(RPR)
    assert robot.name == "rpr_example"
    assert robot.title == "RPR arm of the lecture notes, Table 14-1"
    assert robot.source == "lecture notes, chapter 14"
    assert robot.file == FILE
    assert robot.convention == "standard"
    assert robot.parameters == (("L3", 1.0),)
    assert robot.dof == 3
    j1, j2, j3 = robot.joints
    assert (j1.type, j1.theta, j1.d, j1.a, j1.alpha) == ("revolute", 0, 0, 0, PI / 2)
    assert j1.name == "shoulder"
    assert j1.limits == pytest.approx((-math.radians(170), math.radians(170)))
    assert (j2.type, j2.theta, j2.alpha) == ("prismatic", PI / 2, PI / 2)
    assert j2.limits == (0.0, 0.5)  # prismatic limits are lengths, never scaled
    assert j3.a == S("L3")
    assert robot.gravity == (0, 0, sp.Float("-9.81"))
    assert robot.base == sp.eye(4) and robot.tool == sp.eye(4)


def test_modified_convention_is_kept() -> None:
    robot = load(HEADER + 'convention = "modified"\n[[joints]]\ntype = "revolute"\nalpha = -90\n')
    assert robot.convention == "modified"
    assert robot.joints[0].alpha == -PI / 2


def test_prismatic_joint_with_constant_theta_and_offset() -> None:
    robot = load(HEADER + '[[joints]]\ntype = "prismatic"\ntheta = -90\nd = 0.25\na = 2\n')
    joint = robot.joints[0]
    assert joint.theta == -PI / 2
    assert joint.d == sp.Float("0.25")
    assert joint.a == sp.Integer(2) and isinstance(joint.a, sp.Integer)


def test_negative_a_and_d_are_kept() -> None:
    # PUMA-type tables have a2 < 0 and d2 < 0; they must never be rejected or abs()'d.
    robot = load(HEADER + '[[joints]]\ntype = "revolute"\na = -0.4318\nd = -0.1\n')
    assert robot.joints[0].a == sp.Float("-0.4318")
    assert robot.joints[0].d == sp.Float("-0.1")


def test_numbers_integers_exact_floats_as_float() -> None:
    robot = load(HEADER + '[[joints]]\ntype = "revolute"\na = 2.0\nd = 0.1\n')
    assert isinstance(robot.joints[0].a, sp.Integer) and robot.joints[0].a == 2
    assert isinstance(robot.joints[0].d, sp.Float) and robot.joints[0].d == sp.Float("0.1")


def test_parameters_with_and_without_values() -> None:
    text = HEADER + (
        '[parameters]\nL1 = 0.5\nL2 = "symbol"\nh = 2\n'
        '[[joints]]\ntype = "revolute"\na = "L1"\nd = "-L2/2"\n'
        '[[joints]]\ntype = "revolute"\na = "2*L1 + 0.1"\nd = "h**2"\n'
    )
    robot = load(text)
    assert robot.parameters == (("L1", 0.5), ("L2", None), ("h", 2.0))
    assert robot.parameter_symbols == (S("L1"), S("L2"), S("h"))
    j1, j2 = robot.joints
    assert j1.a == S("L1") and j1.d == -S("L2") / 2
    assert same(j2.a, 2 * S("L1") + sp.Float("0.1"))
    assert j2.d == S("h") ** 2
    assert robot.joints[0].a.is_real  # parameters are real symbols


def test_expressions_with_pi_are_radians_even_in_a_degree_file() -> None:
    text = HEADER + '[[joints]]\ntype = "revolute"\ntheta = "pi/2"\nalpha = "-pi/4 + pi"\n'
    robot = load(text)
    assert robot.joints[0].theta == PI / 2
    assert robot.joints[0].alpha == 3 * PI / 4


def test_parameter_in_angle_field_is_radians() -> None:
    text = HEADER + '[parameters]\nphi = 0.3\n[[joints]]\ntype = "revolute"\ntheta = "phi"\n'
    assert load(text).joints[0].theta == S("phi")


def test_numeric_string_in_angle_field_follows_the_file_unit() -> None:
    deg = load(HEADER + '[[joints]]\ntype = "revolute"\ntheta = "-90"\nalpha = "45/2"\n')
    assert deg.joints[0].theta == -PI / 2
    assert deg.joints[0].alpha == PI / 8
    rad = load(HEADER + 'angles = "rad"\n[[joints]]\ntype = "revolute"\ntheta = "-90"\n')
    assert rad.joints[0].theta == -90


def test_degree_floats_are_converted_exactly() -> None:
    robot = load(HEADER + '[[joints]]\ntype = "revolute"\nalpha = 22.5\ntheta = 0.1\n')
    assert robot.joints[0].alpha == PI / 8
    assert robot.joints[0].theta == sp.Rational(1, 10) * PI / 180


DEG_FILE = """
name = "arm"
angles = "deg"
[[joints]]
type = "revolute"
theta = 30
alpha = -90
limits = [-90, 180]
[[joints]]
type = "prismatic"
theta = 90
limits = [0, 2]
[tool]
xyz = [0, 0, 0.1]
rpy = [90, 0, 45]
[base]
rpy = [0, -30, 0]
"""

RAD_FILE = """
name = "arm"
angles = "rad"
[[joints]]
type = "revolute"
theta = "pi/6"
alpha = "-pi/2"
limits = ["-pi/2", "pi"]
[[joints]]
type = "prismatic"
theta = "pi/2"
limits = [0, 2]
[tool]
xyz = [0, 0, 0.1]
rpy = ["pi/2", 0, "pi/4"]
[base]
rpy = [0, "-pi/6", 0]
"""


def test_degrees_and_radians_give_the_same_robot() -> None:
    deg, rad = load(DEG_FILE), load(RAD_FILE)
    assert deg == rad
    assert deg.joints[0].limits == pytest.approx((-math.pi / 2, math.pi))
    assert deg.joints[1].limits == (0.0, 2.0)


def test_plain_radian_numbers_are_not_scaled() -> None:
    robot = load(HEADER + 'angles = "rad"\n[[joints]]\ntype = "revolute"\nalpha = 1.5\n')
    assert robot.joints[0].alpha == sp.Float("1.5")


def test_tool_and_base_transforms() -> None:
    robot = load(DEG_FILE)
    expected_tool = frame([0, 0, sp.Float("0.1")], [PI / 2, 0, PI / 4])
    expected_base = frame([0, 0, 0], [0, -PI / 6, 0])
    assert matrices_equal(robot.tool, expected_tool)
    assert matrices_equal(robot.base, expected_base)
    assert isinstance(robot.tool, sp.ImmutableMatrix)


def test_tool_with_parameter_expressions() -> None:
    text = HEADER + (
        '[parameters]\nL = "symbol"\n[[joints]]\ntype = "revolute"\n'
        '[tool]\nxyz = ["L", 0, "-L/2"]\n'
    )
    robot = load(text)
    assert matrices_equal(robot.tool, frame([S("L"), 0, -S("L") / 2], [0, 0, 0]))


def test_default_gravity_and_custom_gravity() -> None:
    assert load(HEADER + '[[joints]]\ntype = "revolute"\n').gravity == (0, 0, sp.Float("-9.81"))
    robot = load(HEADER + 'gravity = [0, -9.81, 0]\n[[joints]]\ntype = "revolute"\n')
    assert robot.gravity == (0, sp.Float("-9.81"), 0)


LINK_FILE = """
name = "arm"
[parameters]
L3 = 1.0
m = "symbol"
[[joints]]
type = "revolute"
[joints.link]
mass = 2.0
com = [0, 0, "L3/2"]
inertia = { ixx = 0.02, iyy = 0.02, izz = 0.004, ixy = -0.001 }
motor_inertia = 0.003
friction = { coulomb = 0.5, viscous = 0.1, stribeck = { static = 0.7, velocity = 0.05 } }
[[joints]]
type = "revolute"
[joints.link]
mass = "m"
"""


def test_inertial_data() -> None:
    robot = load(LINK_FILE)
    link = robot.joints[0].link
    assert link is not None
    assert link.mass == 2
    assert link.com == (0, 0, S("L3") / 2)
    assert link.inertia == tuple(
        sp.Float(v) if v else 0 for v in ("0.02", "0.02", "0.004", "-0.001", None, None)
    )
    assert link.motor_inertia == sp.Float("0.003")
    assert (link.coulomb, link.viscous) == (sp.Float("0.5"), sp.Float("0.1"))
    assert (link.stribeck_static, link.stribeck_velocity) == (sp.Float("0.7"), sp.Float("0.05"))
    second = robot.joints[1].link
    assert second is not None
    assert second.mass == S("m")  # parameter without value: no physical check possible
    assert second.com == (0, 0, 0)
    assert second.inertia == (0,) * 6
    assert (second.motor_inertia, second.coulomb, second.viscous) == (0, 0, 0)
    assert second.stribeck_static is None and second.stribeck_velocity is None


def test_joint_without_link_table_has_no_link() -> None:
    assert load(HEADER + '[[joints]]\ntype = "revolute"\n').joints[0].link is None


def test_parameter_named_like_link_symbol_is_fine_when_link_has_data() -> None:
    text = HEADER + "[parameters]\nm1 = 3\n" + REV + '[joints.link]\nmass = "m1"\n'
    assert load(text).joints[0].link.mass == S("m1")  # type: ignore[union-attr]


def test_inertia_of_a_point_mass_and_a_rod_are_accepted() -> None:
    for inertia in ("{}", "{ ixx = 0.1, iyy = 0.1 }", "{ ixx = 1, iyy = 1, izz = 2 }"):
        text = HEADER + REV + f"[joints.link]\nmass = 1\ninertia = {inertia}\n"
        assert load(text).joints[0].link is not None


# --------------------------------------------------------------------------------------------
# Loading by name or path
# --------------------------------------------------------------------------------------------


def test_load_from_path_string_and_path(tmp_path: Path) -> None:
    path = tmp_path / "arm.toml"
    path.write_text(RPR, encoding="utf-8")
    from_string = load_robot(str(path))
    from_path = load_robot(path)
    assert from_string == from_path == load(RPR)
    assert from_string.file == str(path)


def test_relative_path_is_kept_as_given(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "arm.toml").write_text(RPR, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert load_robot("sub/arm.toml").file == "sub/arm.toml"


def test_missing_file_is_a_robot_error(tmp_path: Path) -> None:
    shown = str(tmp_path / "nope.toml")
    with pytest.raises(RobotError, match=r"nope\.toml: cannot read the file"):
        load_robot(shown)


def test_catalogue_file_name_as_path_hints_at_the_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(robot_file, "catalogue_names", lambda: ["scara"])
    with pytest.raises(RobotError, match="give just its name: 'scara'"):
        load_robot("scara.toml")


def test_directory_is_a_robot_error(tmp_path: Path) -> None:
    with pytest.raises(RobotError, match="not a regular file"):
        load_robot(tmp_path)


def test_non_utf8_file_is_a_robot_error(tmp_path: Path) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes('name = "arm"\ntitle = "Gel\xe4nk"\n'.encode("latin-1"))
    with pytest.raises(RobotError, match=r"latin1\.toml: the file is not UTF-8 text"):
        load_robot(path)


def test_errors_from_a_path_name_that_path(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(HEADER + '[[joints]]\ntype = "rotary"\n', encoding="utf-8")
    with pytest.raises(RobotError) as info:
        load_robot(path)
    assert str(info.value).startswith(f"{path}: joint 1: 'type'")


def test_catalogue_names_are_sorted_strings() -> None:
    names = catalogue_names()
    assert names == sorted(names)
    assert all(isinstance(n, str) and not n.endswith(".toml") for n in names)


@pytest.mark.parametrize("name", catalogue_names())
def test_every_catalogue_robot_loads(name: str) -> None:
    robot = load_robot(name)
    assert robot.file == f"robots/{name}.toml"


def test_unknown_catalogue_name_lists_names_and_hints(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(robot_file, "catalogue_names", lambda: ["puma560", "scara", "stanford"])
    with pytest.raises(RobotError) as info:
        load_robot("scarra")
    message = str(info.value)
    assert "unknown robot 'scarra'" in message
    assert "did you mean 'scara'?" in message
    assert "puma560, scara, stanford" in message


def test_unknown_catalogue_name_with_the_real_catalogue() -> None:
    with pytest.raises(RobotError, match="unknown robot 'no_such_robot'"):
        load_robot("no_such_robot")


# --------------------------------------------------------------------------------------------
# Errors: one RobotError naming file, joint and key
# --------------------------------------------------------------------------------------------

REV = '[[joints]]\ntype = "revolute"\n'


def joint_with(lines: str) -> str:
    return HEADER + REV + lines


def link_with(lines: str) -> str:
    return HEADER + REV + "[joints.link]\n" + lines


ERROR_CASES: list[tuple[str, str, list[str]]] = [
    # (id, file text, substrings the message must contain)
    ("toml-syntax", HEADER + REV + "alpha = = 3\n", ["not valid TOML", "line 4"]),
    ("toml-unclosed", HEADER + "gravity = [0, 0,\n", ["not valid TOML", "end of document"]),
    ("unknown-top", HEADER + 'convension = "standard"\n' + REV,
     ["unknown key 'convension'", "did you mean 'convention'?"]),
    ("unknown-joint", HEADER + REV + REV + "alhpa = 90\n",
     ["joint 2: unknown key 'alhpa'", "did you mean 'alpha'?"]),
    ("unknown-link", link_with("mas = 1\n"),
     ["joint 1: unknown key 'link.mas'", "did you mean 'mass'?"]),
    ("unknown-inertia", link_with("mass = 1\ninertia = { ixxx = 1 }\n"),
     ["joint 1: unknown key 'link.inertia.ixxx'", "did you mean 'ixx'?"]),
    ("unknown-friction", link_with("mass = 1\nfriction = { columb = 1 }\n"),
     ["unknown key 'link.friction.columb'", "did you mean 'coulomb'?"]),
    ("unknown-stribeck", link_with("mass = 1\nfriction = { stribeck = { statik = 1 } }\n"),
     ["unknown key 'link.friction.stribeck.statik'", "did you mean 'static'?"]),
    ("unknown-tool", HEADER + REV + "[tool]\nrpyy = [0, 0, 0]\n",
     ["unknown key 'tool.rpyy'", "did you mean 'rpy'?"]),
    ("unknown-no-hint", HEADER + REV + "zzzzzz = 1\n", ["joint 1: unknown key 'zzzzzz'"]),
    ("missing-type", HEADER + REV + "[[joints]]\nalpha = 90\n",
     ["joint 2: 'type' is missing", '"revolute" or "prismatic"']),
    ("bad-type", HEADER + REV + '[[joints]]\ntype = "rotary"\n',
     [f'{FILE}: joint 2: \'type\' must be "revolute" or "prismatic", got "rotary"']),
    ("type-number", HEADER + "[[joints]]\ntype = 1\n", ["joint 1: 'type' must be", "got 1"]),
    ("list-for-number", joint_with("a = [1, 2]\n"),
     ["joint 1: 'a' must be a number or an expression string, got [1, 2]"]),
    ("bool-for-number", joint_with("d = true\n"), ["joint 1: 'd'", "got true"]),
    ("table-for-number", joint_with("theta = { x = 1 }\n"), ["joint 1: 'theta'", "a table"]),
    ("date-for-number", joint_with("alpha = 1979-05-27\n"), ["joint 1: 'alpha'", "1979-05-27"]),
    ("expr-syntax", joint_with('a = "1 +"\n'), ["joint 1: 'a' is not a valid expression"]),
    ("expr-call", joint_with('a = "sin(1)"\n'), ["'a'", "a function call"]),
    ("expr-import", joint_with("a = \"__import__('os').system('true')\"\n"),
     ["'a' is not a valid expression", "function call"]),
    ("expr-attribute", joint_with('a = "pi.real"\n'), ["'a'", "an attribute"]),
    ("expr-lambda", joint_with('a = "lambda: 1"\n'), ["'a' is not a valid expression"]),
    ("expr-string-literal", joint_with("a = \"'x'\"\n"), ["'a'", "literal 'x'"]),
    ("expr-complex", joint_with('a = "2j"\n'), ["'a'", "literal 2j"]),
    ("expr-comparison", joint_with('a = "1 < 2"\n'), ["'a'", "a comparison"]),
    ("expr-floordiv", joint_with('a = "7 // 2"\n'), ["'a'", "FloorDiv"]),
    ("expr-unknown-name", HEADER + '[parameters]\nL1 = 1\n' + REV + 'a = "L11 * 2"\n',
     ["joint 1: 'a'", "unknown name 'L11'", "did you mean 'L1'?", "declared parameters: L1"]),
    ("expr-joint-variable", joint_with('theta = "q1"\n'), ["'theta'", "unknown name 'q1'"]),
    ("expr-empty", joint_with('a = ""\n'), ["joint 1: 'a'", "empty string"]),
    ("expr-too-long", joint_with('a = "' + "1+" * 300 + '1"\n'), ["'a' is longer than 500"]),
    ("expr-huge-power", joint_with('a = "9**9**9"\n'), ["'a'", "exponent"]),
    ("expr-big-power", joint_with('a = "10.0**99 * 10**99 * 10**99 * 10**99"\n'),
     ["'a' holds the constant", "outside 1e-300..1e300"]),
    ("expr-overflow-power", joint_with('a = "(10**90)**50"\n'), ["'a'", "power"]),
    ("expr-complex-power", joint_with('a = "(-1)**0.5"\n'), ["'a'", "power"]),
    ("expr-div-zero", joint_with('a = "1/0"\n'), ["joint 1: 'a' is not finite"]),
    ("expr-zero-over-zero", joint_with('a = "0/0"\n'), ["joint 1: 'a' is not finite"]),
    ("nan", joint_with("a = nan\n"), ["joint 1: 'a' must be a finite number, got nan"]),
    ("inf", joint_with("d = inf\n"), ["joint 1: 'd' must be a finite number, got inf"]),
    ("minus-inf", joint_with("alpha = -inf\n"), ["joint 1: 'alpha'", "got -inf"]),
    ("huge-int", joint_with("a = 1" + "0" * 320 + "\n"), ["joint 1: 'a' is too large"]),
    ("no-joints", HEADER, ["the joint list is empty"]),
    ("empty-joints", HEADER + "joints = []\n", ["the joint list is empty"]),
    ("joints-number", HEADER + "joints = 3\n", ["'joints' must be an array of tables"]),
    ("joints-table", HEADER + "[joints]\ntype = 'revolute'\n", ["'joints' must be an array"]),
    ("link-before-joint", HEADER + "[joints.link]\nmass = 1\n", ["'joints' must be an array"]),
    ("joint-not-table", HEADER + "joints = [1]\n", ["joint 1: each entry of 'joints'"]),
    ("duplicate-joint-names", HEADER + REV + 'name = "elbow"\n' + REV + REV + 'name = "elbow"\n',
     ["joint 3: 'name' \"elbow\" is already used by joint 1"]),
    ("bad-joint-name", joint_with('name = "2nd"\n'), ["joint 1: 'name' must match [a-z]"]),
    ("joint-name-upper", joint_with('name = "Elbow"\n'), ["joint 1: 'name' must match"]),
    ("joint-name-number", joint_with("name = 2\n"), ["joint 1: 'name' must match"]),
    ("bad-convention", HEADER + 'convention = "craig"\n' + REV,
     ["'convention' must be \"standard\" or \"modified\" or \"placement\", got \"craig\""]),
    ("bad-angles", HEADER + 'angles = "degrees"\n' + REV,
     ["'angles' must be \"deg\" or \"rad\", got \"degrees\""]),
    ("gravity-length", HEADER + "gravity = [0, -9.81]\n" + REV,
     ["'gravity' must be a list of 3 values, got [0, -9.81]"]),
    ("gravity-number", HEADER + "gravity = -9.81\n" + REV, ["'gravity' must be a list of 3"]),
    ("gravity-element", HEADER + 'gravity = [0, 0, "g"]\n' + REV,
     ["'gravity[2]'", "unknown name 'g'"]),
    ("tool-xyz-length", HEADER + REV + "[tool]\nxyz = [0, 0]\n",
     ["'tool.xyz' must be a list of 3"]),
    ("base-rpy-length", HEADER + REV + "[base]\nrpy = [0, 0, 0, 0]\n",
     ["'base.rpy' must be a list of 3"]),
    ("tool-not-table", HEADER + "tool = 1\n" + REV, ["'tool' must be a table"]),
    ("com-length", link_with("mass = 1\ncom = [0, 0, 0, 0]\n"),
     ["joint 1: 'link.com' must be a list of 3"]),
    ("bad-robot-name", 'name = "Arm"\n' + REV, ["'name' must match [a-z][a-z0-9_]*, got \"Arm\""]),
    ("robot-name-number", "name = 3\n" + REV, ["'name' must match", "got 3"]),
    ("missing-robot-name", REV, ["'name' is missing"]),
    ("title-not-string", HEADER + "title = 3\n" + REV, ["'title' must be a string"]),
    ("source-not-string", HEADER + "source = [1]\n" + REV, ["'source' must be a string"]),
    ("negative-mass", link_with("mass = -2.0\n"), ["joint 1: 'link.mass' must be >= 0, got -2"]),
    ("negative-mass-parameter", HEADER + "[parameters]\nmb = -1\n" + REV
     + '[joints.link]\nmass = "2*mb"\n', ["joint 1: 'link.mass' must be >= 0, got -2"]),
    ("missing-mass", link_with("com = [0, 0, 0]\n"), ["joint 1: 'link.mass' is missing"]),
    ("link-not-table", joint_with("link = 3\n"), ["joint 1: 'link' must be a table"]),
    ("link-array", HEADER + REV + "[[joints.link]]\nmass = 1\n",
     ["joint 1: 'link' must be a table"]),
    ("inertia-negative", link_with("mass = 1\ninertia = { ixx = -1, iyy = -1, izz = -1 }\n"),
     ["joint 1: 'link.inertia.ixx' must be >= 0 (a moment of inertia), got -1"]),
    ("inertia-not-psd", link_with("mass = 1\ninertia = { ixx = 1, iyy = 1, izz = 1, ixy = 2 }\n"),
     ["joint 1: 'link.inertia' is not positive semi-definite"]),
    ("inertia-not-table", link_with("mass = 1\ninertia = [1, 1, 1]\n"),
     ["joint 1: 'link.inertia' must be a table"]),
    ("negative-motor-inertia", link_with("mass = 1\nmotor_inertia = -0.1\n"),
     ["'link.motor_inertia' must be >= 0"]),
    ("negative-viscous", link_with("mass = 1\nfriction = { viscous = -0.1 }\n"),
     ["'link.friction.viscous' must be >= 0"]),
    ("stribeck-missing-velocity", link_with("mass = 1\nfriction = { stribeck = { static = 1 } }\n"),
     ["'link.friction.stribeck.velocity' is missing"]),
    ("stribeck-zero-velocity",
     link_with("mass = 1\nfriction = { stribeck = { static = 1, velocity = 0 } }\n"),
     ["'link.friction.stribeck.velocity' must be > 0"]),
    ("limits-reversed", joint_with("limits = [170, -170]\n"),
     ["joint 1: 'limits' must be [low, high] with low < high, got [170, -170]"]),
    ("limits-equal", joint_with("limits = [1, 1]\n"), ["joint 1: 'limits'", "low < high"]),
    ("limits-length", joint_with("limits = [1, 2, 3]\n"), ["joint 1: 'limits' must be a list"]),
    ("limits-number", joint_with("limits = 170\n"), ["joint 1: 'limits' must be a list"]),
    ("limits-bool", joint_with("limits = [true, 2]\n"), ["joint 1: 'limits[0]'"]),
    ("limits-parameter", HEADER + "[parameters]\nL = 1\n" + REV + 'limits = [0, "L"]\n',
     ["joint 1: 'limits[1]'", "not of parameters"]),
    ("parameters-not-table", HEADER + "parameters = 1\n" + REV, ["'parameters' must be a table"]),
    ("parameter-bad-name", HEADER + '[parameters]\n"2x" = 1\n' + REV,
     ["'parameters.2x'", "identifier"]),
    ("parameter-keyword", HEADER + "[parameters]\nlambda = 1\n" + REV,
     ["'parameters.lambda'", "identifier"]),
    ("parameter-pi", HEADER + "[parameters]\npi = 3\n" + REV, ["'parameters.pi'", "reserved"]),
    ("parameter-sin", HEADER + "[parameters]\nsin = 3\n" + REV, ["'parameters.sin'", "reserved"]),
    ("parameter-q", HEADER + "[parameters]\nq1 = 3\n" + REV, ["'parameters.q1'", "joint variable"]),
    ("parameter-ddq", HEADER + "[parameters]\nddq12 = 3\n" + REV, ["'parameters.ddq12'", "joint"]),
    ("parameter-value", HEADER + '[parameters]\nL = "abc"\n' + REV,
     ["'parameters.L' must be a number or \"symbol\", got \"abc\""]),
    ("parameter-bool", HEADER + "[parameters]\nL = false\n" + REV, ["'parameters.L'", "false"]),
    ("parameter-nan", HEADER + "[parameters]\nL = nan\n" + REV, ["'parameters.L'", "finite"]),
    ("parameter-link-clash", HEADER + "[parameters]\nm1 = 2\n" + REV,
     ["'parameters.m1'", "link 1", "no [joints.link] data"]),
]  # fmt: skip


# Tensors that violate the triangle inequality load with a RobotWarning (published models with
# lumped link inertias, e.g. Corke's PUMA 560, have them); negative moments and non-PSD
# tensors stay errors (ERROR_CASES).
WARNING_CASES: list[tuple[str, str, list[str]]] = [
    ("inertia-triangle", link_with("mass = 1\ninertia = { ixx = 1, iyy = 1, izz = 3 }\n"),
     ["joint 1: 'link.inertia' violates the triangle inequality", "ixx + iyy >= izz",
      "got 1 + 1 < 3"]),
    ("inertia-triangle-other", link_with("mass = 1\ninertia = { ixx = 5, iyy = 1, izz = 1 }\n"),
     ["'link.inertia' violates the triangle inequality", "iyy + izz >= ixx"]),
    ("inertia-triangle-third", link_with("mass = 1\ninertia = { ixx = 1, iyy = 5, izz = 1 }\n"),
     ["'link.inertia' violates the triangle inequality", "izz + ixx >= iyy"]),
    ("inertia-principal-triangle",
     link_with("mass = 1\ninertia = { ixx = 1, iyy = 1, izz = 1, ixy = 0.9 }\n"),
     ["joint 1: 'link.inertia': the principal moments", "triangle inequality"]),
    ("inertia-parameter-defaults", HEADER + "[parameters]\nJzz = 3\n" + REV
     + '[joints.link]\nmass = 1\ninertia = { ixx = 1, iyy = 1, izz = "Jzz" }\n',
     ["'link.inertia' violates the triangle inequality"]),
    ("corke-puma-link-1", link_with("mass = 0\ninertia = { iyy = 0.35 }\n"),
     ["joint 1: 'link.inertia' violates the triangle inequality", "izz + ixx >= iyy"]),
]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "expected"), [c[1:] for c in WARNING_CASES], ids=[c[0] for c in WARNING_CASES]
)
def test_triangle_inequality_violation_warns_and_loads(text: str, expected: list[str]) -> None:
    with pytest.warns(RobotWarning) as record:
        robot = load(text)
    assert robot.joints[0].link is not None
    assert len(record) == 1  # one warning per tensor, not one per violated inequality
    message = str(record[0].message)
    assert message.startswith(f"{FILE}: ")
    for part in expected:
        assert part in message


def test_physical_inertia_loads_without_warning() -> None:
    text = link_with("mass = 1\ninertia = { ixx = 1, iyy = 2, izz = 3, ixy = 0.1 }\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobotWarning)
        assert load(text).joints[0].link is not None


def test_not_psd_stays_an_error_even_when_the_triangle_is_also_violated() -> None:
    text = link_with("mass = 1\ninertia = { ixx = 1, iyy = 1, izz = 3, ixy = 2 }\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobotWarning)  # the error must come first, not a warning
        assert "is not positive semi-definite" in error_of(text)


@pytest.mark.parametrize(
    ("text", "expected"), [c[1:] for c in ERROR_CASES], ids=[c[0] for c in ERROR_CASES]
)
def test_invalid_files_give_one_clear_robot_error(text: str, expected: list[str]) -> None:
    message = error_of(text)
    assert message.startswith(f"{FILE}: ")
    assert message.count(FILE) == 1  # no double prefixes from nested checks
    assert "Traceback" not in message
    for part in expected:
        assert part in message


def test_robot_constructor_errors_are_prefixed(monkeypatch: pytest.MonkeyPatch) -> None:
    def failing_robot(**_: Any) -> Robot:
        raise RobotError("a robot needs at least one joint")

    monkeypatch.setattr(robot_file, "Robot", failing_robot)
    assert error_of(joint_with("")) == f"{FILE}: a robot needs at least one joint"


def test_joint_constructor_errors_are_prefixed(monkeypatch: pytest.MonkeyPatch) -> None:
    def failing_joint(**_: Any) -> Any:
        raise RobotError("bad joint")

    monkeypatch.setattr(robot_tables, "Joint", failing_joint)
    assert error_of(HEADER + REV + REV) == f"{FILE}: joint 1: bad joint"


def test_pathological_expressions_fail_fast() -> None:
    start = time.perf_counter()
    for text in ("9**9**9**9", "(2**100)**100", "2**(10**20)", "(" * 250 + "1" + ")" * 249):
        with pytest.raises(RobotError):
            load(joint_with(f'a = "{text}"\n'))
    assert load(joint_with(f'a = "{"-" * 499}1"\n')).joints[0].a == -1
    assert time.perf_counter() - start < 2.0


def test_deeply_nested_value_is_shown_shortened() -> None:
    message = error_of(HEADER + "gravity = " + "[" * 200 + "]" * 200 + "\n" + REV)
    assert "'gravity' must be a list of 3 values, got [[[[...]]]]" in message


def test_deeply_nested_toml_is_a_robot_error() -> None:
    with pytest.raises(RobotError, match="not valid TOML"):
        load(HEADER + "gravity = " + "[" * 3000 + "]" * 3000 + "\n")


# --------------------------------------------------------------------------------------------
# Property tests
# --------------------------------------------------------------------------------------------

PARAMETER_POOL = ("L1", "L2", "h", "r_0", "offset")

small_ints = st.integers(min_value=-720, max_value=720)
small_floats = st.floats(
    min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False, allow_subnormal=False
).filter(lambda x: x == 0 or abs(x) >= 1e-300)  # closer to 0 is rejected (underflow)


def expected_number(value: int | float, *, angle: bool, unit: str) -> sp.Expr:
    """The hand rule: degrees -> exact rational multiple of pi; else Integer or Float."""
    if angle and unit == "deg":
        return sp.Rational(str(value)) * sp.pi / 180
    if isinstance(value, float) and not value.is_integer():
        return sp.Float(repr(value))
    return sp.Integer(int(value))


@st.composite
def dh_value(draw: st.DrawFn, params: list[str], *, angle: bool, unit: str) -> tuple[Any, Any]:
    """(value written to the file, expected SymPy value)."""
    kind = draw(st.sampled_from(["int", "float", "pi", "numeric-string", "param"]))
    if kind == "int":
        value = draw(small_ints)
        return value, expected_number(value, angle=angle, unit=unit)
    if kind == "float":
        value = draw(small_floats)
        return value, expected_number(value, angle=angle, unit=unit)
    k = draw(st.integers(min_value=1, max_value=12))
    if kind == "pi":
        return f"-pi/{k}", -sp.pi / k  # radians in every file
    if kind == "numeric-string":
        n = draw(small_ints)
        exact = sp.Rational(n, k)
        return f"{n}/{k}", exact * sp.pi / 180 if angle and unit == "deg" else exact
    if not params:
        return 0, sp.Integer(0)
    name = draw(st.sampled_from(params))
    c = draw(st.integers(min_value=-5, max_value=5))
    return f"{c}*{name} + {name}/{k}", c * S(name) + S(name) / k


@st.composite
def link_table(draw: st.DrawFn, params: list[str], unit: str) -> tuple[dict, dict]:
    mass = draw(st.floats(min_value=0, max_value=100).filter(lambda x: x == 0 or x >= 1e-300))
    com = [draw(dh_value(params, angle=False, unit=unit)) for _ in range(3)]
    # Principal moments satisfying the triangle inequality, so the tensor is physical.
    a = draw(st.floats(min_value=0, max_value=10).filter(lambda x: x == 0 or x >= 1e-300))
    b = draw(st.floats(min_value=0, max_value=10).filter(lambda x: x == 0 or x >= 1e-300))
    c = draw(
        st.floats(min_value=abs(a - b), max_value=a + b).filter(lambda x: x == 0 or x >= 1e-300)
    )
    inertia = {"ixx": a, "iyy": b, "izz": c}
    table: dict[str, Any] = {"mass": mass, "com": [v for v, _ in com], "inertia": inertia}
    expected = {
        "mass": expected_number(mass, angle=False, unit=unit),
        "com": tuple(e for _, e in com),
        "inertia": (*(expected_number(v, angle=False, unit=unit) for v in (a, b, c)), 0, 0, 0),
    }
    return table, expected


@st.composite
def joint_table(
    draw: st.DrawFn, index: int, params: list[str], unit: str
) -> tuple[dict[str, Any], dict[str, Any]]:
    kind = draw(st.sampled_from(["revolute", "prismatic"]))
    table: dict[str, Any] = {"type": kind}
    expected: dict[str, Any] = {"type": kind}
    for key in ("theta", "d", "a", "alpha"):
        if draw(st.booleans()):
            value, exp = draw(dh_value(params, angle=key in ("theta", "alpha"), unit=unit))
            table[key] = value
            expected[key] = exp
        else:
            expected[key] = sp.Integer(0)
    if draw(st.booleans()):
        table["name"] = f"j{index}_{draw(st.sampled_from(['a', 'b']))}"
    expected["name"] = table.get("name")
    if draw(st.booleans()):
        low = draw(st.integers(min_value=-360, max_value=359))
        high = draw(st.integers(min_value=low + 1, max_value=360))
        table["limits"] = [low, high]
        scale = (lambda x: math.radians(x)) if kind == "revolute" and unit == "deg" else float
        expected["limits"] = (scale(low), scale(high))
    else:
        expected["limits"] = None
    if draw(st.booleans()):
        table["link"], expected["link"] = draw(link_table(params, unit))
    else:
        expected["link"] = None
    return table, expected


@st.composite
def robot_document(draw: st.DrawFn) -> tuple[dict[str, Any], dict[str, Any]]:
    unit = draw(st.sampled_from(["deg", "rad"]))
    names = draw(st.lists(st.sampled_from(PARAMETER_POOL), unique=True, max_size=3))
    parameters = {n: draw(st.one_of(st.just("symbol"), small_floats)) for n in names}
    # Reserved names (C and Python keywords, symkin_*) are rejected by design: not well formed.
    name = st.from_regex(r"[a-z][a-z0-9_]{0,8}", fullmatch=True).filter(
        lambda n: not robot_name_reason(n)
    )
    doc: dict[str, Any] = {"name": draw(name)}
    if draw(st.booleans()) or unit == "rad":
        doc["angles"] = unit
    convention = draw(st.sampled_from(["standard", "modified"]))
    doc["convention"] = convention
    doc["title"] = draw(st.text(max_size=20).filter(str.isprintable))  # others: rejected
    if parameters:
        doc["parameters"] = parameters
    n = draw(st.integers(min_value=1, max_value=4))
    joints = [draw(joint_table(i, names, unit)) for i in range(1, n + 1)]
    doc["joints"] = [t for t, _ in joints]
    expected: dict[str, Any] = {
        "convention": convention,
        "parameters": tuple(
            (k, None if v == "symbol" else float(v)) for k, v in parameters.items()
        ),
        "joints": [e for _, e in joints],
    }
    if draw(st.booleans()):
        xyz = [draw(dh_value(names, angle=False, unit=unit)) for _ in range(3)]
        rpy = [draw(dh_value(names, angle=True, unit=unit)) for _ in range(3)]
        doc["tool"] = {"xyz": [v for v, _ in xyz], "rpy": [v for v, _ in rpy]}
        expected["tool"] = frame([e for _, e in xyz], [e for _, e in rpy])
    else:
        expected["tool"] = sp.eye(4)
    if draw(st.booleans()):
        gravity = [draw(small_floats) for _ in range(3)]
        doc["gravity"] = gravity
        expected["gravity"] = tuple(expected_number(g, angle=False, unit=unit) for g in gravity)
    else:
        expected["gravity"] = (0, 0, sp.Float("-9.81"))
    return doc, expected


def unique_joint_names(doc: dict[str, Any]) -> bool:
    names = [j["name"] for j in doc["joints"] if "name" in j]
    return len(names) == len(set(names))


@settings(deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow])
@given(robot_document())
def test_well_formed_files_load_to_the_generated_values(case: tuple[dict, dict]) -> None:
    doc, expected = case
    robot = load(to_toml(doc))
    assert robot.name == doc["name"] and robot.title == doc["title"]
    assert robot.convention == expected["convention"]
    assert robot.parameters == expected["parameters"]
    assert all(same(g, e) for g, e in zip(robot.gravity, expected["gravity"], strict=True))
    assert matrices_equal(robot.tool, expected["tool"])
    assert len(robot.joints) == len(expected["joints"])
    for joint, exp in zip(robot.joints, expected["joints"], strict=True):
        assert joint.type == exp["type"] and joint.name == exp["name"]
        for key in ("theta", "d", "a", "alpha"):
            assert same(getattr(joint, key), exp[key]), key
        if exp["limits"] is None:
            assert joint.limits is None
        else:
            assert joint.limits == pytest.approx(exp["limits"])
        if exp["link"] is None:
            assert joint.link is None
        else:
            assert joint.link is not None
            assert same(joint.link.mass, exp["link"]["mass"])
            assert all(same(*p) for p in zip(joint.link.com, exp["link"]["com"], strict=True))
            assert all(
                same(*p) for p in zip(joint.link.inertia, exp["link"]["inertia"], strict=True)
            )


# Garbage: random keys and values at every level, random text, truncated files.

ALL_KEYS = sorted(
    {
        *robot_file.TOP_KEYS, *robot_tables.JOINT_KEYS, *robot_tables.FRAME_KEYS,
        *robot_tables.LINK_KEYS, *robot_tables.INERTIA_KEYS, *robot_tables.FRICTION_KEYS,
        *robot_tables.STRIBECK_KEYS, *PARAMETER_POOL, "q1", "m1", "pi", "symbol",
    }
)  # fmt: skip

expression_text = st.text(alphabet="L12h pi()+-*/.0e9_,[]'\"jqsn", max_size=30)
scalars = st.one_of(
    st.integers(),
    st.integers(min_value=-(10**400), max_value=10**400),
    st.floats(),
    st.booleans(),
    st.text(max_size=20),
    expression_text,
    st.sampled_from(
        ["symbol", "revolute", "prismatic", "deg", "rad", "standard", "modified", "pi/2", "L1"]
    ),
    st.dates(),
)
toml_values = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(
            st.one_of(st.sampled_from(ALL_KEYS), st.text(max_size=6)), inner, max_size=4
        ),
    ),
    max_leaves=8,
)


def tables_in(doc: Any) -> list[dict[str, Any]]:
    """Every table (dict) inside the document, the document first."""
    found = []
    stack = [doc]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            found.append(item)
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
    return found


@st.composite
def mutated_text(draw: st.DrawFn) -> str:
    doc, _ = draw(robot_document())
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        tables = tables_in(doc)
        table = draw(st.sampled_from(tables))
        key = draw(st.one_of(st.sampled_from(ALL_KEYS), st.text(min_size=1, max_size=6)))
        if table and draw(st.booleans()):
            del table[draw(st.sampled_from(sorted(table)))]
        else:
            table[key] = draw(toml_values)
    text = to_toml(doc)
    if draw(st.integers(min_value=0, max_value=4)) == 0:
        text = text[: draw(st.integers(min_value=0, max_value=len(text)))]
    return text


def loads_or_robot_error(text: str) -> None:
    try:
        robot = load(text)
    except RobotError as exc:
        assert str(exc).startswith(f"{FILE}: ")
    else:
        assert isinstance(robot, Robot)


@pytest.mark.filterwarnings("ignore::symkin.errors.RobotWarning")
@settings(deadline=None, max_examples=150, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_text())
def test_mutated_files_give_a_robot_or_a_robot_error(text: str) -> None:
    loads_or_robot_error(text)


@settings(deadline=None, max_examples=100)
@given(st.one_of(st.text(max_size=200), st.text(alphabet='[]{}=",.\n name\tjoints', max_size=80)))
def test_random_text_gives_a_robot_or_a_robot_error(text: str) -> None:
    loads_or_robot_error(text)


@settings(deadline=None, max_examples=100)
@given(st.sampled_from([RPR, DEG_FILE, RAD_FILE, LINK_FILE]), st.data())
def test_truncated_or_corrupted_files_give_a_robot_or_a_robot_error(
    text: str, data: st.DataObject
) -> None:
    cut = data.draw(st.integers(min_value=0, max_value=len(text)))
    insert = data.draw(st.text(max_size=5))
    loads_or_robot_error(text[:cut] + insert + text[cut + data.draw(st.integers(0, 5)) :])


@settings(deadline=None, max_examples=200)
@given(expression_text)
def test_random_expressions_give_a_value_or_a_robot_error(text: str) -> None:
    doc = {"name": "arm", "parameters": {"L1": 1.5, "L2": "symbol"}, "joints": [
        {"type": "revolute", "a": text, "alpha": text, "link": {"mass": text}}
    ]}  # fmt: skip
    loads_or_robot_error(to_toml(doc))


def test_a_name_longer_than_the_limit_is_refused_at_load() -> None:
    """A 301-character name loaded and failed only when a file named after it was written."""
    text = f'name = "{"a" * 65}"\n[[joints]]\ntype = "revolute"\n'
    with pytest.raises(RobotError, match=r"^long\.toml: 'name' has 65 characters; at most 64"):
        robot_from_toml(text, "long.toml")
    assert robot_from_toml(text.replace("a" * 65, "a" * 64), "ok.toml").name == "a" * 64


def test_a_byte_order_mark_is_dropped(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + b'name = "bom"\n[[joints]]\ntype = "revolute"\n')
    assert load_robot(path).name == "bom"
