"""``symkin ik`` end to end through :func:`symkin.cli.main`.

Numbers printed are checked with ``tests/numeric_dh.py`` (an independent numeric DH product)
and targets are built here from their definition (``R = Rz(rz) Ry(ry) Rx(rx)``), never with
symkin's own FK.  Plots are rendered and the PNG checked (size, not blank).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from numeric_dh import Rx, Ry, Rz, reference, vee
from symkin.cli import main

pytestmark = pytest.mark.filterwarnings("ignore::symkin.errors.RobotWarning")


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def target_pose(x, y, z, rx=0.0, ry=0.0, rz=0.0) -> np.ndarray:
    T = Rz(rz) @ Ry(ry) @ Rx(rx)
    T[:3, 3] = (x, y, z)
    return T


def pose_errors(name: str, q, target: np.ndarray) -> tuple[float, float]:
    T = reference(name).fk(np.asarray(q, dtype=float))
    relative = target[:3, :3].T @ T[:3, :3]
    angle = math.atan2(np.linalg.norm(vee(relative)), (np.trace(relative) - 1) / 2)
    return float(np.linalg.norm(T[:3, 3] - target[:3, 3])), angle


def assert_png(path: Path) -> None:
    """A real picture: a PNG header, some size, and many distinct colours."""
    import matplotlib.image

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 20_000
    pixels = matplotlib.image.imread(path)
    colours = np.unique(pixels.reshape(-1, pixels.shape[-1]).round(2), axis=0)
    assert len(colours) > 50


# ---------------------------------------------------------------------------------------------
# One target
# ---------------------------------------------------------------------------------------------


def test_full_pose_in_degrees(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(
        capsys, "ik", "puma560", "--target", "0.4,-0.2,0.3,10deg,80deg,-30deg", "--json"
    )
    data = json.loads(out)
    target = target_pose(0.4, -0.2, 0.3, math.radians(10), math.radians(80), math.radians(-30))
    assert status == 0 and data["success"] is True
    assert max(pose_errors("puma560", data["q"], target)) < 1e-9
    assert data["task_rows"] == ["x", "y", "z", "wx", "wy", "wz"]
    assert set(data) >= {"q", "position_error", "rotation_error", "iterations", "restarts"}


def test_text_output_and_negative_values(capsys: pytest.CaptureFixture[str]) -> None:
    """Values may start with a minus sign; the q lines give rad and deg."""
    status, out, _ = run(capsys, "ik", "planar_2r", "--target", "-0.6,1.1", "--q0", "-1,-1")
    assert status == 0
    assert "task rows x, y; Levenberg-Marquardt" in out and "solved after" in out
    q = [float(line.split()[2]) for line in out.splitlines() if line.strip().startswith("q")]
    degrees = [float(line.split()[5]) for line in out.splitlines() if "deg" in line]
    assert np.linalg.norm(reference("planar_2r").fk(np.array(q))[:2, 3] - [-0.6, 1.1]) < 1e-5
    assert degrees == pytest.approx([math.degrees(v) for v in q], abs=1e-3)


def test_compact_task_and_position_only(capsys: pytest.CaptureFixture[str]) -> None:
    """--task xy on a planar 3R arm: position only, orientation free; x,y,z on the PUMA."""
    status, out, _ = run(
        capsys, "ik", "planar_3r", "--target", "1.2,0.9,0", "--task", "xy", "--json"
    )
    data = json.loads(out)
    assert status == 0 and data["task_rows"] == ["x", "y"]
    assert np.linalg.norm(reference("planar_3r").fk(np.array(data["q"]))[:2, 3] - [1.2, 0.9]) < 1e-9
    status, out, _ = run(capsys, "ik", "puma560", "--target", "0.3,0.3,0.2", "--json")
    data = json.loads(out)
    assert status == 0 and data["task_rows"] == ["x", "y", "z"]
    assert pose_errors("puma560", data["q"], target_pose(0.3, 0.3, 0.2))[0] < 1e-9


def test_newton_method(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run(
        capsys, "ik", "scara", "--target", "0.4,0.3,0.1", "--method", "newton", "--json"
    )
    data = json.loads(out)
    assert status == 0 and data["method"] == "newton"
    assert pose_errors("scara", data["q"], target_pose(0.4, 0.3, 0.1))[0] < 1e-9


@pytest.mark.needs_cc
@pytest.mark.parametrize("backend", ["auto", "c", "numpy", "python"])
def test_the_backend_option_picks_the_implementation(
    backend: str, capsys: pytest.CaptureFixture[str]
) -> None:
    status, out, _ = run(
        capsys, "ik", "rpr", "--target", "0.3,0.4,0.5", "--backend", backend, "--json"
    )
    data = json.loads(out)
    assert status == 0 and data["backend"] == ("c" if backend == "auto" else backend)
    assert pose_errors("rpr", data["q"], target_pose(0.3, 0.4, 0.5))[0] < 1e-9


def test_a_backend_that_cannot_run_the_request_is_one_message(
    capsys: pytest.CaptureFixture[str],
) -> None:
    status, out, err = run(
        capsys, "ik", "rpr", "--target", "0.3,0.4,0.5", "--method", "newton", "--backend", "c"
    )
    assert status == 2 and out == "" and "Traceback" not in err
    assert err.count("symkin: error:") == 1 and "--backend" in err and "use 'python'" in err


def test_unreachable_target_exits_1_with_the_closest_pose(
    capsys: pytest.CaptureFixture[str],
) -> None:
    status, out, err = run(capsys, "ik", "planar_2r", "--target", "3,0", "--restarts", "2")
    assert status == 1
    assert "NOT solved, closest pose reached" in out
    assert "position error 1 m" in out  # 3 - (L1 + L2)
    assert err == ""


# ---------------------------------------------------------------------------------------------
# All solutions
# ---------------------------------------------------------------------------------------------


def test_all_solutions_closed_form(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    plot = tmp_path / "all.png"
    argv = ["ik", "puma560", "--target", "0.4,0.2,0.3,0,90deg,0", "--all"]
    status, out, err = run(capsys, *argv, "--json")
    data = json.loads(out)
    target = target_pose(0.4, 0.2, 0.3, 0.0, math.pi / 2, 0.0)
    assert status == 0 and data["method"] == "closed form" and data["complete"] is True
    assert len(data["solutions"]) == 8
    for solution in data["solutions"]:
        assert max(pose_errors("puma560", solution["q"], target)) < 1e-9
        assert set(solution["branch"]) == {"shoulder", "elbow", "wrist"}
    status, out, err = run(capsys, *argv, "--plot", str(plot))
    assert status == 0 and "8 solutions by closed form" in out and "shoulder=" in out
    assert f"wrote {plot}" in err
    assert_png(plot)


def test_all_solutions_numeric_say_so(capsys: pytest.CaptureFixture[str]) -> None:
    """The RPR arm has no closed form here: a numeric search, flagged as possibly incomplete."""
    q = np.array([0.4, 0.3, -0.7])
    point = reference("rpr").fk(q)[:3, 3]
    text = ",".join(f"{v:.12f}" for v in point)
    status, out, _ = run(capsys, "ik", "rpr", "--target", text, "--all", "--json")
    data = json.loads(out)
    assert status == 0 and data["method"] == "numeric" and data["complete"] is False
    assert data["solutions"]
    for solution in data["solutions"]:
        assert np.linalg.norm(reference("rpr").fk(np.array(solution["q"]))[:3, 3] - point) < 1e-9
    assert any(np.allclose(np.array(s["q"]), q, atol=1e-6) for s in data["solutions"])
    status, out, _ = run(capsys, "ik", "rpr", "--target", text, "--all")
    assert "by numeric (distinct solutions from 64 seeds, possibly not all)" in out


# ---------------------------------------------------------------------------------------------
# Paths
# ---------------------------------------------------------------------------------------------


def test_lecture_table(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    q0 = np.radians([30.0, 60.0])
    x0 = reference("planar_2r").fk(q0)[:2, 3]
    start = f"{x0[0]:.15f},{x0[1]:.15f}"
    argv = [
        "ik",
        "planar_2r",
        "--path-from",
        start,
        "--q0",
        "30deg,60deg",
        "--to",
        "1,1.2",
        "--steps",
        "5",
        "--table",
    ]
    status, out, _ = run(capsys, *argv)
    lines = out.splitlines()
    assert status == 0
    assert lines[1].split() == ["i", "x_i", "y_i", "q1", "q2", "x_real", "y_real", "dx", "dy"]
    labels = [line.split()[0] for line in lines[2:]]
    assert labels[:6] == ["0", "1", "2", "3", "4", "5"] and labels[6] == "5a"
    row1 = [float(v) for v in lines[3].split()[1:]]
    assert row1[0:2] == pytest.approx(x0 + (np.array([1.0, 1.2]) - x0) / 5, abs=1e-6)
    status, out, _ = run(capsys, *argv, "--json")
    data = json.loads(out)
    assert [r["i"] for r in data["rows"]] == labels
    q1 = np.array(data["rows"][1]["q"])
    J = reference("planar_2r").jacobian(q0, method="complex")[:2]
    expected = q0 + np.linalg.solve(J, np.array(data["rows"][1]["target"]) - x0)
    np.testing.assert_allclose(q1, expected, atol=1e-12)
    np.testing.assert_allclose(
        data["rows"][1]["real"], reference("planar_2r").fk(q1)[:2, 3], atol=1e-12
    )
    plot = tmp_path / "table.png"
    status, _, _ = run(capsys, *argv, "--plot", str(plot))
    assert status == 0
    assert_png(plot)


def test_path_follower(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    plot = tmp_path / "path.png"
    status, out, _ = run(
        capsys,
        "ik",
        "puma560",
        "--path-from",
        "0.5,0.2,0.2,0,90deg,0",
        "--to",
        "0.4,-0.2,0.4,0,90deg,30deg",
        "--steps",
        "6",
        "--json",
        "--plot",
        str(plot),
    )
    data = json.loads(out)
    assert status == 0 and data["success"] is True and len(data["waypoints"]) == 7
    for waypoint in data["waypoints"]:
        assert max(pose_errors("puma560", waypoint["q"], np.array(waypoint["target"]))) < 1e-9
    assert_png(plot)
    status, out, _ = run(
        capsys, "ik", "planar_2r", "--path-from", "1.5,0.2", "--to", "0.2,1.5", "--steps", "3"
    )
    assert status == 0 and len(out.splitlines()) == 2 + 4


# ---------------------------------------------------------------------------------------------
# Bad input: one line on stderr, exit status 2
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--target", "1,2,3,4"], "--target: expected x,y or x,y,z or x,y,z,rx,ry,rz"),
        (["--target", "1deg,0,0"], "--target: x, y, z are lengths in metres"),
        (["--target", "0.3,0.2,abc"], "--target: expected a number"),
        (["--target", "0.3,0.2,0.1", "--q0", "0,0"], "--q0: puma560 has 6 joints"),
        ([], "give either --target or --path-from"),
        (["--target", "0.3,0,0", "--path-from", "0.3,0,0"], "give either --target"),
        (["--path-from", "0.3,0,0.2"], "--path-from needs --to and --steps"),
        (
            ["--path-from", "0.3,0,0.2", "--to", "0.3,0.1,0.2", "--steps", "3", "--table"],
            "--table starts from a known pair",
        ),
        (["--path-from", "0.3,0,0.2", "--to", "0.3,0.1", "--steps", "3"], "same number"),
        (["--path-from", "0.3,0,0.2", "--to", "0.3,0.1,0.2", "--steps", "0"], "at least 1 step"),
        (["--target", "0.3,0,0.2", "--steps", "3"], "go with --path-from"),
        (["--target", "0.3,0,0.2", "--task", "x,q"], "unknown task row"),
        (["--target", "0.3,0,0.2", "--all"], "infinitely many solutions"),
        (["--target", "0.3,0,0.2", "--tolerance", "-1"], "tolerance must be positive"),
        (["--target", "0.3,0,0.2", "--restarts", "-1"], "--restarts: expected a count >= 0"),
        (["--target", "0.3,0,0.2", "--set", "a9=1"], "unknown parameter"),
    ],
)
def test_bad_input_is_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    status, out, err = run(capsys, "ik", "puma560", *argv)
    lines = err.strip().splitlines()
    assert status == 2
    assert len(lines) == 1 and lines[0].startswith("symkin: error: ")
    assert message in lines[0]
    assert "Traceback" not in err and out == ""
