"""symkin dh and symkin urdf on the command line: outputs, files, and bad input (exit 2)."""

from __future__ import annotations

import json
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from symkin import catalogue_names, load_robot
from symkin.cli import main
from symkin.emit.urdf import urdf_text

DATA = Path(__file__).parent / "data"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_dh_text_names_cases_transforms_and_proof(capsys):
    code, out, _ = run(capsys, "dh", "ur5")
    assert code == 0
    assert "intersecting" in out and "parallel" in out and "coincident" in out
    assert "base =" in out and "tool =" in out
    assert "Proof: symbolic" in out


def test_dh_text_writes_a_negative_offset_as_a_difference(capsys, tmp_path):
    """theta = q1 - 10 deg (printed "q1 + -10" before)."""
    robot = tmp_path / "offset.toml"
    robot.write_text(
        'name = "offset"\nangles = "deg"\n[[joints]]\ntype = "revolute"\ntheta = -10\na = 0.5\n'
        '[[joints]]\ntype = "revolute"\ntheta = 20\na = 0.3\n'
    )
    code, out, _ = run(capsys, "dh", str(robot))
    assert code == 0 and "q1 - 10" in out and "q2 + 20" in out and "+ -" not in out


def test_dh_json_rows_are_sympy_text(capsys):
    code, out, _ = run(capsys, "dh", "panda", "--convention", "modified", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["convention"] == "modified"
    assert [row["alpha"] for row in data["rows"]][:3] == ["0", "-pi/2", "pi/2"]
    assert data["proof"]["method"] == "symbolic" and data["proof"]["numeric_error"] < 1e-12


def test_dh_toml_writes_a_loadable_robot_file(capsys, tmp_path):
    target = tmp_path / "out" / "ur5_dh.toml"
    code, out, _ = run(capsys, "dh", "ur5", "--convention", "modified", "--toml", str(target))
    assert code == 0 and f"wrote {target}" in out
    robot = load_robot(target)
    assert robot.convention == "modified" and robot.dof == 6
    assert robot.joints[0].name == "shoulder_pan"


def test_dh_latex_writes_every_step(capsys, tmp_path):
    target = tmp_path / "panda_dh.tex"
    assert run(capsys, "dh", "panda", "--latex", str(target))[0] == 0
    text = target.read_text()
    assert text.count(r"\subsection*") == 7 and "intersect" in text and "skew" in text


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["dh", "no_such_robot"], "no_such_robot"),
        (["dh", str(DATA / "dh_coincident_revolutes.toml")], "coincident axes"),
        (["dh", str(DATA / "dh_parallel_prismatics.toml")], "prismatic joint along the previous"),
        (["urdf", "ur5", "-o", "."], "is a folder"),
    ],
)
def test_bad_input_is_one_message_and_exit_2(capsys, argv, words):
    code, _, err = run(capsys, *argv)
    assert code == 2 and words in err and "Traceback" not in err
    assert err.count("\n") == 1


@pytest.mark.parametrize(
    "outputs",
    [
        ("urdf", "{robot}", "-o", "{robot}"),
        ("dh", "{robot}", "--toml", "{robot}"),
        ("dh", "{robot}", "--latex", "{folder}/../{folder_name}/{robot_name}"),
        ("dh", "{robot}", "--toml", "{folder}/a.toml", "--latex", "{folder}/a.toml"),
    ],
)
def test_outputs_never_replace_the_robot_file_or_each_other(capsys, tmp_path, outputs):
    """Before the check, each of these replaced the user's robot file (or one output the
    other) without a word."""
    robot = tmp_path / "arm.urdf"
    robot.write_text(urdf_text(load_robot("planar_2r"), "test"), encoding="utf-8")
    before = robot.read_text(encoding="utf-8")
    names = {"robot": robot, "folder": tmp_path, "folder_name": tmp_path.name}
    argv = [part.format(robot_name=robot.name, **names) for part in outputs]
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and "give another file name" in err
    assert robot.read_text(encoding="utf-8") == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.urdf"]


def test_dh_uses_set_values_and_names_a_missing_one(capsys, tmp_path):
    robot_file = tmp_path / "free.toml"
    robot_file.write_text(
        'name = "free"\n[parameters]\nl1 = "symbol"\n[[joints]]\ntype = "revolute"\na = "l1"\n'
    )
    code, _, err = run(capsys, "dh", str(robot_file))
    assert code == 2 and "l1 have no value" in err and "--set" in err
    code, out, _ = run(capsys, "dh", str(robot_file), "--set", "l1=0.5", "--json")
    assert code == 0 and json.loads(out)["rows"][0]["a"] == "0.500000000000000"


def test_urdf_command_writes_the_file(capsys, tmp_path):
    target = tmp_path / "ur5.urdf"
    code, out, _ = run(capsys, "urdf", "ur5", "-o", str(target))
    assert code == 0 and str(target) in out
    root = ET.parse(target).getroot()
    assert root.tag == "robot" and len(root.findall("joint")) == 7  # six joints and the tool


@pytest.mark.parametrize("name", catalogue_names())
def test_urdf_of_every_catalogue_robot_is_well_formed(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = load_robot(name)
    root = ET.fromstring(urdf_text(robot, "test"))
    joints = [j for j in root.findall("joint") if j.get("type") != "fixed"]
    assert len(joints) == robot.dof
    for joint in joints:
        axis = [float(v) for v in joint.find("axis").get("xyz").split()]
        assert axis == [0, 0, 1]
        if joint.get("type") in ("revolute", "prismatic"):
            limit = joint.find("limit")
            assert float(limit.get("lower")) < float(limit.get("upper"))
    masses = [float(m.get("value")) for m in root.iter("mass")]
    expected = [float(j.link.mass) for j in robot.joints if j.link is not None]
    assert np.allclose(masses, expected)


@pytest.mark.needs_latex
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_latex_compiles(capsys, tmp_path, convention):
    from symkin.runtime.latex_build import compile_pdf

    target = tmp_path / "stanford_dh.tex"
    assert run(capsys, "dh", "stanford", "--convention", convention, "--latex", str(target))[0] == 0
    assert compile_pdf(target).is_file()
