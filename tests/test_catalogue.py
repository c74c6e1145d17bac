"""The built-in robot catalogue (``src/symkin/robots/*.toml``) against independent sources.

These tests read the TOML files themselves with :mod:`tomllib` and compute forward kinematics
with their own small numpy DH product (standard and modified convention), so they check the
*data* without relying on symkin's loader or derivations.  Expected poses come from sources
that do not use the catalogue files:

* textbook closed forms (planar arms, SCARA, the lecture's RPR arm, Spong's cylindrical arm,
  spherical wrist and Stanford arm), typed in from the books, not derived from the files;
* published poses (Corke's book for the PUMA 560);
* numbers computed once with Peter Corke's Robotics Toolbox for Python
  (``roboticstoolbox-python`` 1.4.4 with ``rtb-data`` 2.0.0, installed in a scratch venv, not a
  project dependency) and pasted here with the call that produced them.

Only the last test uses symkin itself: the loader must list and load exactly these files.
"""

from __future__ import annotations

import ast
import math
import operator
import tomllib
from collections.abc import Callable, Mapping, Sequence
from importlib import resources
from typing import Any

import numpy as np
import pytest

CATALOGUE = (
    "planar_2r",
    "planar_3r",
    "scara",
    "rpr",
    "cylindrical_rtt_wrist",
    "puma560",
    "stanford",
    "ur5",
    "panda",
)
DEG = math.pi / 180
TOL = 1e-9  # every expected pose below is exact to ~1e-15

# Keys of the robot file contract (shared/ROBOT_FORMAT.md) plus the `source` extension.
TOP_KEYS = {
    "name", "title", "source", "convention", "angles", "gravity",
    "parameters", "joints", "tool", "base",
}  # fmt: skip
JOINT_KEYS = {"type", "name", "theta", "d", "a", "alpha", "limits", "link"}
FRAME_KEYS = {"xyz", "rpy"}


# ---------------------------------------------------------------------------------------------
# Reading the files and an independent DH product
# ---------------------------------------------------------------------------------------------


def _catalogue_dir() -> Any:
    return resources.files("symkin") / "robots"


def read_robot(name: str) -> dict[str, Any]:
    text = (_catalogue_dir() / f"{name}.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


_BINARY: dict[type, Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY: dict[type, Callable[[float], float]] = {ast.USub: operator.neg, ast.UAdd: operator.pos}


def _evaluate(expression: str, params: Mapping[str, float]) -> tuple[float, bool]:
    """Value of an expression of parameter names and pi; also whether it mentions pi."""
    mentions_pi = False

    def walk(node: ast.AST) -> float:
        nonlocal mentions_pi
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id == "pi":
                mentions_pi = True
                return math.pi
            return float(params[node.id])
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _UNARY[type(node.op)](walk(node.operand))
        raise ValueError(f"unsupported expression {expression!r}")

    value = walk(ast.parse(expression, mode="eval"))
    return value, mentions_pi


def _number(value: Any, params: Mapping[str, float], *, angle: bool, degrees: bool) -> float:
    """A file value in SI units and radians (expressions containing pi are radians)."""
    if isinstance(value, str):
        number, mentions_pi = _evaluate(value, params)
        return number * DEG if angle and degrees and not mentions_pi else number
    return float(value) * DEG if angle and degrees else float(value)


def _rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _ry(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _trans(x: float, y: float, z: float) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = (x, y, z)
    return matrix


def _frame(table: Mapping[str, Any], params: Mapping[str, float], degrees: bool) -> np.ndarray:
    """[base]/[tool]: translation, then fixed-axis roll-pitch-yaw R = Rz(y) Ry(p) Rx(r)."""
    x, y, z = (_number(v, params, angle=False, degrees=degrees) for v in table.get("xyz", [0] * 3))
    roll, pitch, yaw = (
        _number(v, params, angle=True, degrees=degrees) for v in table.get("rpy", [0] * 3)
    )
    return _trans(x, y, z) @ _rz(yaw) @ _ry(pitch) @ _rx(roll)


def fkine(
    doc: Mapping[str, Any], q: Sequence[float], overrides: Mapping[str, float] | None = None
) -> np.ndarray:
    """T = base * A_1 ... A_n * tool from the file's DH table (q in rad and m)."""
    params = {k: float(v) for k, v in doc.get("parameters", {}).items()}
    params.update(overrides or {})
    degrees = doc.get("angles", "deg") == "deg"
    joints = doc["joints"]
    assert len(q) == len(joints)
    transform = _frame(doc.get("base", {}), params, degrees)
    for joint, qi in zip(joints, q, strict=True):
        theta = _number(joint.get("theta", 0), params, angle=True, degrees=degrees)
        d = _number(joint.get("d", 0), params, angle=False, degrees=degrees)
        a = _number(joint.get("a", 0), params, angle=False, degrees=degrees)
        alpha = _number(joint.get("alpha", 0), params, angle=True, degrees=degrees)
        if joint["type"] == "revolute":
            theta += qi
        else:
            d += qi
        if doc.get("convention", "standard") == "standard":
            transform = transform @ _rz(theta) @ _trans(0, 0, d) @ _trans(a, 0, 0) @ _rx(alpha)
        else:  # modified (Craig): the row holds alpha_{i-1}, a_{i-1}
            transform = transform @ _rx(alpha) @ _trans(a, 0, 0) @ _rz(theta) @ _trans(0, 0, d)
    return transform @ _frame(doc.get("tool", {}), params, degrees)


def _homogeneous(rows: Sequence[Sequence[float]]) -> np.ndarray:
    """A 4x4 transform from its top three rows."""
    return np.vstack([np.array(rows, dtype=float), [0, 0, 0, 1.0]])


def _configs(n: int, count: int, seed: int, low: float = -math.pi, high: float = math.pi):
    rng = np.random.default_rng(seed)
    return [tuple(row) for row in rng.uniform(low, high, size=(count, n))]


def _assert_pose(actual: np.ndarray, expected: np.ndarray, tol: float = TOL) -> None:
    np.testing.assert_allclose(actual, expected, rtol=0, atol=tol)


# ---------------------------------------------------------------------------------------------
# The files themselves
# ---------------------------------------------------------------------------------------------


def test_catalogue_holds_exactly_the_expected_robots() -> None:
    files = sorted(
        entry.name.removesuffix(".toml")
        for entry in _catalogue_dir().iterdir()
        if entry.name.endswith(".toml")
    )
    assert files == sorted(CATALOGUE)


@pytest.mark.parametrize("name", CATALOGUE)
def test_file_follows_the_contract(name: str) -> None:
    doc = read_robot(name)
    assert doc["name"] == name
    assert set(doc) <= TOP_KEYS, set(doc) - TOP_KEYS
    assert isinstance(doc["title"], str) and doc["title"].strip()
    assert isinstance(doc["source"], str) and len(doc["source"]) > 40
    assert doc["angles"] == "deg"
    assert doc.get("convention", "standard") in ("standard", "modified")
    params = doc.get("parameters", {})
    assert params, "lengths are named parameters"
    assert all(isinstance(v, float) for v in params.values()), params
    assert doc["joints"]
    for joint in doc["joints"]:
        assert set(joint) <= JOINT_KEYS, set(joint) - JOINT_KEYS
        assert joint["type"] in ("revolute", "prismatic")
        for key in ("theta", "d", "a", "alpha"):
            value = joint.get(key, 0)
            if isinstance(value, str):  # a parameter expression must evaluate
                _evaluate(value, params)
            else:
                assert math.isfinite(value)
        for key in ("theta", "alpha"):  # constant angles are exact numbers of degrees
            assert isinstance(joint.get(key, 0), int), (key, joint)
        if "limits" in joint:
            low, high = joint["limits"]
            assert low < high
        # Inertial data: the PUMA 560 (Corke) and the Panda (Gaz et al.), on every joint.
        # Every catalogue robot carries inertial data (issue 21; docs/dynamics.md).
        assert "link" in joint, (name, joint)
    for key in ("base", "tool"):
        if key in doc:
            assert set(doc[key]) <= FRAME_KEYS


# Parameter names and values as printed in each source (see the robot file's `source`).
SOURCE_PARAMETERS: dict[str, dict[str, float]] = {
    "planar_2r": {"L1": 1.0, "L2": 1.0},
    "planar_3r": {"L1": 1.0, "L2": 0.8, "L3": 0.5},
    "scara": {"L1": 0.325, "L2": 0.225},
    "rpr": {"L3": 1.0},
    "cylindrical_rtt_wrist": {"d1": 0.5, "d6": 0.1},
    # Corke, RTB for MATLAB, mdl_puma560.m
    "puma560": {"a2": 0.4318, "a3": 0.0203, "d3": 0.15005, "d4": 0.4318},
    # Corke, RTB for MATLAB, mdl_stanford.m: L(1).d, L(2).d, L(6).d
    "stanford": {"d1": 0.412, "d2": 0.154, "d6": 0.263},
    # Universal Robots' UR5 DH table
    "ur5": {
        "d1": 0.089159,
        "a2": -0.425,
        "a3": -0.39225,
        "d4": 0.10915,
        "d5": 0.09465,
        "d6": 0.0823,
    },
    # Franka FCI documentation, DH table rows "Joint 1".."Joint 7"
    "panda": {"d1": 0.333, "d3": 0.316, "a4": 0.0825, "a5": -0.0825, "d5": 0.384, "a7": 0.088},
}


@pytest.mark.parametrize("name", CATALOGUE)
def test_parameters_are_named_and_valued_as_in_the_source(name: str) -> None:
    assert read_robot(name)["parameters"] == SOURCE_PARAMETERS[name]


# Joint limits as published (revolute in deg, prismatic in m), converted where noted.
SOURCE_LIMITS_DEG: dict[str, list[tuple[float, float] | None]] = {
    # mdl_puma560.m, 'qlim' (Wang & Chen 1991)
    "puma560": [(-160, 160), (-45, 225), (-225, 45), (-110, 170), (-100, 100), (-266, 266)],
    # mdl_stanford.m: +-170 deg, +-90 deg for joint 5, stroke [12, 12 + 38] inch
    "stanford": [
        (-170, 170),
        (-170, 170),
        (12 * 0.0254, 50 * 0.0254),
        (-170, 170),
        (-90, 90),
        (-170, 170),
    ],
    # UR5 technical specifications: +-360 deg on all joints
    "ur5": [(-360, 360)] * 6,
}

# Franka FCI documentation, Panda joint limits in rad (q_min, q_max)
PANDA_LIMITS_RAD = [
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
]


@pytest.mark.parametrize("name", sorted(SOURCE_LIMITS_DEG))
def test_joint_limits_match_the_source(name: str) -> None:
    limits = [tuple(j["limits"]) if "limits" in j else None for j in read_robot(name)["joints"]]
    expected = SOURCE_LIMITS_DEG[name]
    assert len(limits) == len(expected)
    for got, want in zip(limits, expected, strict=True):
        assert got == pytest.approx(want, abs=1e-12)


def test_panda_limits_match_franka_radians() -> None:
    joints = read_robot("panda")["joints"]
    got = [(j["limits"][0] * DEG, j["limits"][1] * DEG) for j in joints]
    # the file states degrees to 6 decimals: 5e-7 deg < 1e-8 rad
    np.testing.assert_allclose(got, PANDA_LIMITS_RAD, rtol=0, atol=1e-8)


def test_only_real_robots_claim_limits() -> None:
    for name in ("planar_2r", "planar_3r", "scara", "rpr", "cylindrical_rtt_wrist"):
        assert all("limits" not in j for j in read_robot(name)["joints"]), name


# ---------------------------------------------------------------------------------------------
# Textbook closed forms
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("overrides", [None, {"L1": 0.7, "L2": 0.3}])
@pytest.mark.parametrize("q", [(0.0, 0.0), (math.pi / 2, -math.pi / 2), *_configs(2, 4, 1)])
def test_planar_2r_closed_form(q: tuple[float, ...], overrides: dict[str, float] | None) -> None:
    doc = read_robot("planar_2r")
    p = {**doc["parameters"], **(overrides or {})}
    q1, q2 = q
    # x = L1 c1 + L2 c12, y = L1 s1 + L2 s12, orientation Rz(q1 + q2)
    expected = _rz(q1 + q2)
    expected[:3, 3] = (
        p["L1"] * math.cos(q1) + p["L2"] * math.cos(q1 + q2),
        p["L1"] * math.sin(q1) + p["L2"] * math.sin(q1 + q2),
        0.0,
    )
    _assert_pose(fkine(doc, q, overrides), expected)


@pytest.mark.parametrize("overrides", [None, {"L1": 0.4, "L2": 0.9, "L3": 0.2}])
@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0), *_configs(3, 4, 2)])
def test_planar_3r_closed_form(q: tuple[float, ...], overrides: dict[str, float] | None) -> None:
    doc = read_robot("planar_3r")
    p = {**doc["parameters"], **(overrides or {})}
    q1, q2, q3 = q
    # offsets +90 deg on joint 1 and -90 deg on joint 2: absolute link angles
    phi1, phi12, phi123 = q1 + math.pi / 2, q1 + q2, q1 + q2 + q3
    expected = _rz(phi123)
    expected[:3, 3] = (
        p["L1"] * math.cos(phi1) + p["L2"] * math.cos(phi12) + p["L3"] * math.cos(phi123),
        p["L1"] * math.sin(phi1) + p["L2"] * math.sin(phi12) + p["L3"] * math.sin(phi123),
        0.0,
    )
    _assert_pose(fkine(doc, q, overrides), expected)


def test_planar_3r_home_pose_points_up_then_right() -> None:
    doc = read_robot("planar_3r")
    p = doc["parameters"]
    # q = 0: link 1 along +y, links 2 and 3 along +x
    expected = _trans(p["L2"] + p["L3"], p["L1"], 0.0)
    _assert_pose(fkine(doc, (0.0, 0.0, 0.0)), expected)


@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0), (0.3, -1.2, 0.15), *_configs(3, 4, 3)])
def test_scara_closed_form(q: tuple[float, ...]) -> None:
    doc = read_robot("scara")
    p = doc["parameters"]
    q1, q2, q3 = q
    expected = _rz(q1 + q2)
    expected[:3, 3] = (
        p["L1"] * math.cos(q1) + p["L2"] * math.cos(q1 + q2),
        p["L1"] * math.sin(q1) + p["L2"] * math.sin(q1 + q2),
        q3,  # the prismatic joint moves up, along +z of the base
    )
    _assert_pose(fkine(doc, q), expected)


@pytest.mark.parametrize("q", [(0.2, 0.7, 0.1), (-1.0, 2.5, -0.3), *_configs(3, 3, 4)])
def test_scara_position_jacobian_determinant(q: tuple[float, ...]) -> None:
    doc = read_robot("scara")
    p = doc["parameters"]
    step = 1e-6
    columns = []
    for i in range(3):
        plus, minus = list(q), list(q)
        plus[i] += step
        minus[i] -= step
        columns.append((fkine(doc, plus)[:3, 3] - fkine(doc, minus)[:3, 3]) / (2 * step))
    jacobian = np.column_stack(columns)
    # central differences: error ~ step^2, far below the tolerance
    assert np.linalg.det(jacobian) == pytest.approx(p["L1"] * p["L2"] * math.sin(q[1]), abs=1e-8)


@pytest.mark.parametrize("overrides", [None, {"L3": 0.6}])
@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0), (0.4, 0.25, -0.8), *_configs(3, 4, 5)])
def test_rpr_closed_form(q: tuple[float, ...], overrides: dict[str, float] | None) -> None:
    doc = read_robot("rpr")
    L3 = {**doc["parameters"], **(overrides or {})}["L3"]
    q1, q2, q3 = q
    s1, c1, s3, c3 = math.sin(q1), math.cos(q1), math.sin(q3), math.cos(q3)
    # A1 = Rz(q1) Rx(90), A2 = Rz(90) Tz(q2) Rx(90), A3 = Rz(q3) Tx(L3), multiplied by hand
    expected = _homogeneous(
        [
            [s1 * s3, s1 * c3, c1, s1 * (q2 + L3 * s3)],
            [-c1 * s3, -c1 * c3, s1, -c1 * (q2 + L3 * s3)],
            [c3, -s3, 0, L3 * c3],
        ]
    )
    _assert_pose(fkine(doc, q, overrides), expected)


def _spong_spherical_wrist(q4: float, q5: float, q6: float, d6: float) -> np.ndarray:
    """Spong et al. (2006), Sec. 3.3, spherical wrist T_6^3 (Table 3.3)."""
    c4, s4, c5, s5 = math.cos(q4), math.sin(q4), math.cos(q5), math.sin(q5)
    c6, s6 = math.cos(q6), math.sin(q6)
    return _homogeneous(
        [
            [c4 * c5 * c6 - s4 * s6, -c4 * c5 * s6 - s4 * c6, c4 * s5, c4 * s5 * d6],
            [s4 * c5 * c6 + c4 * s6, -s4 * c5 * s6 + c4 * c6, s4 * s5, s4 * s5 * d6],
            [-s5 * c6, s5 * s6, c5, c5 * d6],
        ]
    )


@pytest.mark.parametrize("overrides", [None, {"d1": 1.2, "d6": 0.25}])
@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), *_configs(6, 4, 6)])
def test_cylindrical_with_spherical_wrist_closed_form(
    q: tuple[float, ...], overrides: dict[str, float] | None
) -> None:
    doc = read_robot("cylindrical_rtt_wrist")
    p = {**doc["parameters"], **(overrides or {})}
    q1, d2, d3, q4, q5, q6 = q
    c1, s1 = math.cos(q1), math.sin(q1)
    # Spong et al. (2006), Sec. 3.3, three-link cylindrical robot T_3^0 (Table 3.2)
    arm = _homogeneous([[c1, 0, -s1, -s1 * d3], [s1, 0, c1, c1 * d3], [0, -1, 0, p["d1"] + d2]])
    expected = arm @ _spong_spherical_wrist(q4, q5, q6, p["d6"])
    _assert_pose(fkine(doc, q, overrides), expected)


def _spong_stanford(q: Sequence[float], d2: float, d6: float) -> np.ndarray:
    """Spong et al. (2006), Sec. 3.3, Stanford manipulator T_6^0 (Table 3.4, d1 = 0)."""
    q1, q2, d3, q4, q5, q6 = q
    c1, s1, c2, s2 = math.cos(q1), math.sin(q1), math.cos(q2), math.sin(q2)
    c4, s4, c5, s5 = math.cos(q4), math.sin(q4), math.cos(q5), math.sin(q5)
    c6, s6 = math.cos(q6), math.sin(q6)
    return _homogeneous(
        [
            [
                c1 * (c2 * (c4 * c5 * c6 - s4 * s6) - s2 * s5 * c6) - s1 * (s4 * c5 * c6 + c4 * s6),
                c1 * (-c2 * (c4 * c5 * s6 + s4 * c6) + s2 * s5 * s6)
                - s1 * (-s4 * c5 * s6 + c4 * c6),
                c1 * (c2 * c4 * s5 + s2 * c5) - s1 * s4 * s5,
                c1 * s2 * d3 - s1 * d2 + d6 * (c1 * c2 * c4 * s5 + c1 * c5 * s2 - s1 * s4 * s5),
            ],
            [
                s1 * (c2 * (c4 * c5 * c6 - s4 * s6) - s2 * s5 * c6) + c1 * (s4 * c5 * c6 + c4 * s6),
                s1 * (-c2 * (c4 * c5 * s6 + s4 * c6) + s2 * s5 * s6)
                + c1 * (-s4 * c5 * s6 + c4 * c6),
                s1 * (c2 * c4 * s5 + s2 * c5) + c1 * s4 * s5,
                s1 * s2 * d3 + c1 * d2 + d6 * (c1 * s4 * s5 + c2 * c4 * s1 * s5 + c5 * s1 * s2),
            ],
            [
                -s2 * (c4 * c5 * c6 - s4 * s6) - c2 * s5 * c6,
                s2 * (c4 * c5 * s6 + s4 * c6) + c2 * s5 * s6,
                -s2 * c4 * s5 + c2 * c5,
                c2 * d3 + d6 * (c2 * c5 - c4 * s2 * s5),
            ],
        ]
    )


@pytest.mark.parametrize("overrides", [None, {"d1": 0.0, "d2": 0.3, "d6": 0.05}])
@pytest.mark.parametrize("q", [(0.0, 0.0, 0.5, 0.0, 0.0, 0.0), *_configs(6, 4, 7)])
def test_stanford_spong_closed_form(
    q: tuple[float, ...], overrides: dict[str, float] | None
) -> None:
    doc = read_robot("stanford")
    p = {**doc["parameters"], **(overrides or {})}
    # Spong's table has its base frame at the shoulder; the file raises it by d1 along z0
    expected = _trans(0, 0, p["d1"]) @ _spong_stanford(q, p["d2"], p["d6"])
    _assert_pose(fkine(doc, q, overrides), expected)


# ---------------------------------------------------------------------------------------------
# Published poses and Robotics Toolbox numbers
# ---------------------------------------------------------------------------------------------

# PUMA 560. qz and qr: Corke, "Robotics, Vision and Control", p560.fkine(qz) and
# p560.fkine(qr) with mdl_puma560 (identity rotation; t = (a2 + a3, -d3, d4) and
# (a3, -d3, a2 + d4)).  The others: roboticstoolbox-python
#   p = rtb.models.DH.Puma560(); p.links[0].d = 0.0   # drop the 26.45 in pedestal
#   p.fkine(np.radians(q)).A
PUMA_POSES = [
    ((0, 0, 0, 0, 0, 0), [[1, 0, 0, 0.4521], [0, 1, 0, -0.15005], [0, 0, 1, 0.4318]]),
    ((0, 90, -90, 0, 0, 0), [[1, 0, 0, 0.0203], [0, 1, 0, -0.15005], [0, 0, 1, 0.8636]]),
    (
        (0, 45, 180, 0, 45, 0),  # qn
        [
            [-2.78178084688463e-16, 6.12323399573677e-17, 1, 0.596303148574616],
            [-6.12323399573677e-17, 1, -6.12323399573677e-17, -0.15005],
            [-1, -6.12323399573677e-17, -3.13396163204581e-16, -0.014354267658087],
        ],
    ),
    (
        (10, -20, 30, -40, 50, -60),
        [
            [-0.215533103772415, 0.607451653675777, -0.764557368432738, 0.371496518768284],
            [-0.921427386892164, 0.132700274281278, 0.365187907645846, -0.0868599036153389],
            [0.323290970896663, 0.78319418131919, 0.531121287922501, 0.281080747869286],
        ],
    ),
]


@pytest.mark.parametrize(("q_deg", "rows"), PUMA_POSES)
def test_puma560_poses(q_deg: tuple[float, ...], rows: list[list[float]]) -> None:
    q = [v * DEG for v in q_deg]
    _assert_pose(fkine(read_robot("puma560"), q), _homogeneous(rows))


# Stanford arm against Corke's mdl_stanford.m table (RTB for MATLAB), built in
# roboticstoolbox-python because its own models.DH.Stanford differs (a3 = 0.0203, d6 = 0):
#   st = DHRobot([RevoluteDH(d=0.412, alpha=-pi/2), RevoluteDH(d=0.154, alpha=pi/2),
#                 PrismaticDH(theta=-pi/2), RevoluteDH(alpha=-pi/2), RevoluteDH(alpha=pi/2),
#                 RevoluteDH(d=0.263)])
#   st.fkine([q1, q2, d3, q4 + pi/2, q5, q6]).A
# Corke's -90 deg offset on the prismatic joint turns the wrist about z2, so his q4 is the
# catalogue's (Spong's) q4 + 90 deg.  q: angles in deg, d3 in m.
STANFORD_CORKE_POSES = [
    (
        (10, -20, 0.5, -40, 50, -60),
        [
            [-0.0072273049214917, 0.911130118341114, 0.412055425295287, -0.0867832869247795],
            [-0.884697454316716, 0.186246981061899, -0.42734351097314, 0.00957346327100196],
            [-0.466109622716688, -0.367632927656156, 0.804728432524831, 1.09348988814698],
        ],
    ),
    (
        (-100, 35, 0.9, 70, -15, 120),
        [
            [-0.00310002683925145, -0.946349344078913, -0.323130482615006, -0.0229633755964125],
            [0.890223119414623, 0.144580258098532, -0.431971465062056, -0.648726583989289],
            [0.455514201198265, -0.288997349346966, 0.842013862461382, 1.37068648568744],
        ],
    ),
]


@pytest.mark.parametrize(("q_mixed", "rows"), STANFORD_CORKE_POSES)
def test_stanford_matches_corke_model(q_mixed: tuple[float, ...], rows: list[list[float]]) -> None:
    q = [v * DEG if i != 2 else v for i, v in enumerate(q_mixed)]
    _assert_pose(fkine(read_robot("stanford"), q), _homogeneous(rows))


# UR5: roboticstoolbox-python  u = rtb.models.DH.UR5(); u.fkine(np.radians(q)).A
# That model has d1 = 0.089459, a typo for UR's published 0.089159 (Corke's MATLAB mdl_ur5.m
# has 0.089159).  d1 translates along the base z axis only, so the expected pose is RTB's
# with z lowered by the difference.
RTB_UR5_D1 = 0.089459
UR5_POSES = [
    (
        (0, 0, 0, 0, 0, 0),
        # t = (a2 + a3, -(d4 + d6), d1 - d5) with RTB's d1
        [[1, 0, 0, -0.81725], [0, 0, -1, -0.19145], [0, 1, 0, 0.089459 - 0.09465]],
    ),
    (
        (10, -20, 30, -40, 50, -60),
        [
            [-0.0858164926811875, 0.836169227561028, -0.54171630256426, -0.84595984109092],
            [-0.404062719764567, -0.526208982409765, -0.748222844697848, -0.313716869223527],
            [-0.910696902421635, 0.15467750227901, 0.383022221559489, 0.116257487589705],
        ],
    ),
    (
        (-120, -75, 100, -30, 90, 45),
        [
            [-0.643186644053904, 0.581558227337685, 0.498097349045872, 0.183340046345785],
            [0.300181616122014, -0.406925165064533, 0.862729915662821, 0.535854275332933],
            [0.704416026402759, 0.704416026402759, 0.0871557427476581, 0.247088552458813],
        ],
    ),
]


@pytest.mark.parametrize(("q_deg", "rows"), UR5_POSES)
def test_ur5_matches_robotics_toolbox(q_deg: tuple[float, ...], rows: list[list[float]]) -> None:
    doc = read_robot("ur5")
    expected = _homogeneous(rows)
    expected[2, 3] -= RTB_UR5_D1 - doc["parameters"]["d1"]
    _assert_pose(fkine(doc, [v * DEG for v in q_deg]), expected)


# Panda: the URDF model of roboticstoolbox-python (no DH table involved), flange frame:
#   pu = rtb.models.Panda(); pu.fkine(q, end="panda_link8").A
# (rtb-data's panda_arm_hand.urdf.xacro).  q in rad; the first one is Panda.qr.
PANDA_URDF_POSES = [
    (
        (0.0, -0.3, 0.0, -2.2, 0.0, 2.0, math.pi / 4),
        [
            [0.703574192576952, -0.703574192576952, 0.099833416646828, 0.473724040111762],
            [-0.707106781186547, -0.707106781186548, -1.20329446400524e-16, -5.22177275716081e-17],
            [0.0705928858999941, -0.0705928858999939, -0.995004165278026, 0.515513206152051],
        ],
    ),
    (
        (0.5, 0.4, -0.6, -1.8, 0.7, 1.2, -0.9),
        [
            [0.710766190477882, 0.255230157738706, -0.65549141035885, 0.537626802994647],
            [0.676610708611225, -0.502909786151762, 0.537847279425494, 0.055317921953256],
            [-0.192378199040783, -0.825796169507624, -0.530142730743674, 0.340793723400707],
        ],
    ),
]


@pytest.mark.parametrize(("q", "rows"), PANDA_URDF_POSES)
def test_panda_flange_matches_urdf(q: tuple[float, ...], rows: list[list[float]]) -> None:
    _assert_pose(fkine(read_robot("panda"), q), _homogeneous(rows))


def test_panda_zero_pose() -> None:
    # q = 0: flange at x = a4 + a5 + a7, z = d1 + d3 + d5 - 0.107, pointing down, x mirrored
    expected = _homogeneous(
        [[1, 0, 0, 0.088], [0, -1, 0, 0], [0, 0, -1, 0.333 + 0.316 + 0.384 - 0.107]]
    )
    _assert_pose(fkine(read_robot("panda"), (0.0,) * 7), expected)


# ---------------------------------------------------------------------------------------------
# symkin's loader
# ---------------------------------------------------------------------------------------------


def test_loader_lists_and_loads_every_catalogue_robot() -> None:
    from symkin.io.robot_file import catalogue_names, load_robot

    assert sorted(catalogue_names()) == sorted(CATALOGUE)
    for name in CATALOGUE:
        doc = read_robot(name)
        robot = load_robot(name)
        assert robot.name == name
        assert len(robot.joints) == len(doc["joints"])
        assert robot.convention == doc.get("convention", "standard")
        assert [n for n, _ in robot.parameters] == list(doc["parameters"])
        assert [v for _, v in robot.parameters] == pytest.approx(list(doc["parameters"].values()))
        for joint, table in zip(robot.joints, doc["joints"], strict=True):
            assert joint.type == table["type"]
            if "limits" in table:
                scale = DEG if table["type"] == "revolute" else 1.0
                want = (table["limits"][0] * scale, table["limits"][1] * scale)
                assert joint.limits == pytest.approx(want, abs=1e-12)
            else:
                assert joint.limits is None
