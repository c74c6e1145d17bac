"""``symkin eval --dynamics --wrench``: the wrench enters tau, the statics and energies are
printed, bad input is one message and exit code 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from numeric_dh import without_inertials
from symkin.cli import main

# Link data for the planar 2R (its file's own data are left out): two thin rods of 1 kg,
# centre mid-link.
ROD = {"m": 1.0, "cx": -0.5, "cy": 0.0, "cz": 0.0, "ixx": 0.0, "iyy": 1 / 12, "izz": 1 / 12}
SETS = [
    arg
    for i in (1, 2)
    for name in ("m", "cx", "cy", "cz", "ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    for arg in ("--set", f"{name}{i}={ROD.get(name, 0.0)}")
]


@pytest.fixture(scope="module")
def bare_2r(tmp_path_factory) -> str:
    """The catalogue planar 2R without its inertial data, so that --set gives them."""
    path = tmp_path_factory.mktemp("bare") / "planar_2r.toml"
    path.write_text(without_inertials("planar_2r"), encoding="utf-8")
    return str(path)


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_wrench_enters_tau_and_statics(capsys: pytest.CaptureFixture[str], bare_2r) -> None:
    q, dq = [0.3, 0.5], [0.1, -0.2]
    base = ["eval", bare_2r, "--q", "0.3,0.5", "--dq", "0.1,-0.2", "--ddq", "0.4,0.7"]
    base += ["--dynamics", *SETS, "--json"]
    code, out, _ = run(capsys, *base)
    assert code == 0
    free = json.loads(out)
    code, out, _ = run(capsys, *base, "--wrench", "1,2,0,0,0,0.5")
    assert code == 0
    loaded = json.loads(out)
    # -J^T w of the planar elbow by hand (unit lengths): fx = 1, fy = 2, nz = 0.5
    s1, c1, s12, c12 = np.sin(q[0]), np.cos(q[0]), np.sin(sum(q)), np.cos(sum(q))
    hold = np.array([(s1 + s12) - 2 * (c1 + c12) - 0.5, (s12 - 2 * c12) - 0.5])
    np.testing.assert_allclose(np.subtract(loaded["tau"], free["tau"]), hold, atol=1e-12)
    np.testing.assert_allclose(loaded["wrench_torque"], hold, atol=1e-12)
    np.testing.assert_allclose(loaded["static_torque"], hold, atol=1e-12)  # G = 0: flat arm
    assert free["wrench_torque"] is None and free["static_torque"] is None
    # T of two rods (hand): rod 1 turns about its end, rod 2 translates and turns
    w1, w2 = dq[0], dq[0] + dq[1]
    v2 = np.array([-s1 * w1 - 0.5 * s12 * w2, c1 * w1 + 0.5 * c12 * w2])
    kinetic = 0.5 * (1 / 3) * w1**2 + 0.5 * v2 @ v2 + 0.5 * (1 / 12) * w2**2
    assert loaded["kinetic_energy"] == pytest.approx(kinetic, rel=1e-12)
    assert loaded["potential_energy"] == pytest.approx(0.0, abs=1e-12)  # in a level plane
    assert loaded["lagrangian"] == pytest.approx(kinetic, rel=1e-12)


def test_text_report_prints_the_statics(capsys: pytest.CaptureFixture[str], bare_2r) -> None:
    code, out, _ = run(
        capsys, "eval", bare_2r, "--q", "0,0", "--dynamics", *SETS, "--wrench", "0,1,0,0,0,0"
    )
    assert code == 0
    assert "static torque G - J^T w = [-2. -1.]" in out  # a 1 N upward tip force, unit links


@pytest.mark.parametrize(
    ("wrench", "message"),
    [
        ("1,2,3", "expected six values FX,FY,FZ,MX,MY,MZ (N, N m), got 3"),
        ("1,2,3,4,5,nan", "--wrench MZ: expected a finite number, got 'nan'"),
        ("1,2,3,4,5,x", "--wrench MZ: expected a number"),
        ("1,2,3,4deg,5,6", "--wrench MX: a force or moment, not an angle"),
    ],
)
def test_bad_wrench_is_one_message(
    capsys: pytest.CaptureFixture[str], wrench: str, message: str
) -> None:
    code, out, err = run(
        capsys, "eval", "planar_2r", "--q", "0,0", "--dynamics", *SETS, "--wrench", wrench
    )
    assert code == 2 and out == ""
    assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_wrench_without_dynamics_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "eval", "planar_2r", "--q", "0,0", "--wrench", "0,0,0,0,0,0")
    assert code == 2 and "--wrench needs --dynamics" in err
