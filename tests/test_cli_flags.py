"""Library errors name the function's parameters; the command line spells them as its flags
(:func:`symkin.cli.report.flag`).  Expected messages are written out by hand."""

from __future__ import annotations

from pathlib import Path

import pytest

import symkin
from symkin.cli import main
from symkin.cli.report import flag
from symkin.errors import ParameterError
from symkin.generate import check_backends
from symkin.solve.ik.path import follow_path
from symkin.solve.ik.target import pose_from_target

# The planar 2R arm with the second link length left symbolic (no value).
SYMBOLIC_ARM = """
name = "arm"
[parameters]
L1 = 1.0
L2 = "symbol"
[[joints]]
type = "revolute"
a = "L1"
[[joints]]
type = "revolute"
a = "L2"
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str]:
    status = main(list(argv))
    return status, capsys.readouterr().err


def test_a_missing_parameter_value_names_overrides_then_set(tmp_path: Path, capsys) -> None:
    path = tmp_path / "arm.toml"
    path.write_text(SYMBOLIC_ARM)
    with pytest.raises(ParameterError) as info:
        symkin.load_robot(path).parameter_values()
    assert str(info.value) == "parameter(s) L2 have no value; give one with overrides"
    assert run(capsys, "eval", str(path), "--q", "0,0") == (
        2,
        "symkin: error: parameter(s) L2 have no value; give one with --set NAME=VALUE\n",
    )


def test_a_path_without_steps_names_steps_then_the_flag(capsys) -> None:
    model = symkin.derive(symkin.load_robot("planar_2r"))
    start, end = pose_from_target([0.3, 0.2, 0.0]), pose_from_target([0.2, 0.3, 0.0])
    with pytest.raises(ParameterError) as info:
        follow_path(model, start, end, 0)
    assert str(info.value) == "steps: need at least 1 step, got 0"
    argv = ("ik", "planar_2r", "--path-from", "0.3,0.2", "--to", "0.2,0.3", "--steps", "0")
    assert run(capsys, *argv) == (2, "symkin: error: --steps: need at least 1 step, got 0\n")


def test_braces_a_user_typed_are_text_not_parameters(tmp_path: Path, capsys) -> None:
    with pytest.raises(ParameterError) as info:
        check_backends(["{x}"])
    choices = "numpy, c, python, casadi, latex"
    assert str(info.value) == f"backends: unknown backend '{{x}}'; choose from {choices}"
    argv = ("derive", "planar_2r", "--out", str(tmp_path), "--emit", "{x}")
    assert run(capsys, *argv) == (
        2,
        f"symkin: error: --emit: unknown backend '{{x}}'; choose from {choices}\n",
    )


@pytest.mark.parametrize("text", ["{", "a{b}", "{sections}"])
def test_braces_in_a_section_name_are_text(tmp_path: Path, capsys, text: str) -> None:
    # Found by review: '{' crashed the message template (exit 3), 'a{b}' printed 'a--b'.
    code, err = run(capsys, "latex", "planar_2r", "-o", str(tmp_path / "x.tex"), "--sections", text)
    assert code == 2
    assert f"--sections: unknown section(s) {text};" in err


@pytest.mark.parametrize(
    ("parameter", "command", "spelled"),
    [
        ("cartesian_goal", "trajopt", "--cartesian-goal"),  # the default rule
        ("overrides", "eval", "--set NAME=VALUE"),
        ("text_width_cm", "latex", "--text-width"),
        ("final_time", "trajopt", "--time"),
        ("torque_limits", "trajopt", "--torque-limit"),
        ("start", "trajopt", "--from"),
        ("start", "ik", "--start"),  # trajopt's spelling stays with trajopt
    ],
)
def test_flag_spellings(parameter: str, command: str, spelled: str) -> None:
    assert flag(parameter, command) == spelled


ANGLE_PARAMETER_ARM = """name = "angp"
angles = "rad"
[parameters]
L1 = 0.5
beta = 0.3
[[joints]]
type = "revolute"
a = "L1"
alpha = "beta"
[[joints]]
type = "revolute"
a = 0.5
"""


def test_set_takes_deg_for_an_angle_parameter_only(tmp_path: Path, capsys) -> None:
    """``--set L1=30deg`` on a length was silently 0.5236 m; on the twist ``beta`` it is the
    angle, as ``--set beta=0.5235987755982988`` (30 degrees by hand, in radians)."""
    robot = tmp_path / "angp.toml"
    robot.write_text(ANGLE_PARAMETER_ARM, encoding="utf-8")
    assert main(["eval", str(robot), "--q", "0,0", "--set", "L1=30deg"]) == 2
    assert "--set L1: 'deg' is for a parameter that is an angle" in capsys.readouterr().err
    assert main(["eval", str(robot), "--q", "0.2,0.4", "--set", "beta=30deg", "--json"]) == 0
    in_degrees = capsys.readouterr().out
    radians = str(30 * 3.141592653589793 / 180)
    assert main(["eval", str(robot), "--q", "0.2,0.4", "--set", f"beta={radians}", "--json"]) == 0
    assert capsys.readouterr().out == in_degrees


def test_set_deg_on_an_unknown_name_says_the_name_is_unknown(capsys) -> None:
    assert main(["eval", "planar_2r", "--q", "0,0", "--set", "L9=30deg"]) == 2
    assert "unknown parameter" in capsys.readouterr().err
