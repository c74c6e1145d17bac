"""Documented inertial data (``inertia_note``): shown once by ``show``, no warning per command.

Issue 21: the catalogue PUMA's link 3 (Corke's lumped moments, ixx + izz = 0.0785 < iyy =
0.086) printed a triangle-inequality warning on every command.  User files without a note
still warn (tests/test_robot_file.py).
"""

from __future__ import annotations

import warnings

import pytest

from symkin import load_robot
from symkin.cli import main
from symkin.errors import RobotError
from symkin.io.robot_file import robot_from_toml

TEXT = """name = "arm"
[[joints]]
type = "revolute"
[joints.link]
mass = 1
inertia = {{ ixx = 1, iyy = 1, izz = 3 }}
{note}
"""


def test_a_note_silences_the_warning() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        robot = robot_from_toml(TEXT.format(note='inertia_note = "lumped, as published"'), "a")
    assert robot.joints[0].link.inertia_note == "lumped, as published"
    with pytest.warns(Warning, match="triangle inequality"):
        robot_from_toml(TEXT.format(note=""), "a")


def test_a_note_is_one_printable_line() -> None:
    with pytest.raises(RobotError, match="inertia_note"):
        robot_from_toml(TEXT.format(note='inertia_note = "a\\nb"'), "a")
    with pytest.raises(RobotError, match="inertia_note"):
        robot_from_toml(TEXT.format(note="inertia_note = 3"), "a")


def test_catalogue_puma_loads_quietly_and_show_prints_the_note(capsys) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        robot = load_robot("puma560")
    assert "0.0785 < iyy = 0.086" in robot.joints[2].link.inertia_note
    assert main(["eval", "puma560", "--q", "0,0,0,0,0,0"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert main(["show", "puma560", "--skip", "determinant"]) == 0
    out = capsys.readouterr()
    notes = [line for line in out.out.splitlines() if line.startswith("note:")]
    assert len(notes) == 1 and notes[0].startswith("note: joint 3 link inertia:")
    assert "warning" not in out.err
