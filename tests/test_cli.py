"""The ``symkin`` command line (``symkin.cli``) against an independent numeric DH model.

Every number the command prints is checked against a small NumPy product of elementary
transforms written in this file (``Rz Tz Tx Rx`` for standard DH, ``Rx Tx Rz Tz`` for modified
DH), with DH tables typed in from the robots' published sources or from the TOML text the test
writes, never read through symkin.  Velocities and accelerations are checked by finite
differences along ``q(t) = q + dq t + ddq t^2 / 2``.

Most commands run in-process through ``main([...])`` (fast); a few run the installed
``symkin`` script in real subprocesses, started concurrently by one fixture.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
import zlib
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from symkin.cli import main

DEG = math.pi / 180
ROBOTS_DIR = Path(__file__).resolve().parents[1] / "src" / "symkin" / "robots"
ROW_NAMES = ("x", "y", "z", "wx", "wy", "wz")
TOL = 1e-9


# ---------------------------------------------------------------------------------------------
# Independent numeric model
# ---------------------------------------------------------------------------------------------


def rot_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]], dtype=float)


def rot_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=float)


def rot_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def frame(xyz: Sequence[float], rpy: Sequence[float]) -> np.ndarray:
    """Fixed transform: translation, then fixed-axis roll-pitch-yaw (Rz(y) Ry(p) Rx(r))."""
    roll, pitch, yaw = rpy
    return trans(*xyz) @ rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)


@dataclass(frozen=True)
class Row:
    """One DH row in radians/metres; ``theta`` or ``d`` is the offset of the joint variable."""

    kind: str  # "R" or "P"
    theta: float = 0.0
    d: float = 0.0
    a: float = 0.0
    alpha: float = 0.0


@dataclass(frozen=True)
class Arm:
    rows: tuple[Row, ...]
    modified: bool = False
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))

    @property
    def n(self) -> int:
        return len(self.rows)

    def link(self, row: Row, q: float) -> np.ndarray:
        theta = row.theta + (q if row.kind == "R" else 0.0)
        d = row.d + (q if row.kind == "P" else 0.0)
        if self.modified:
            return rot_x(row.alpha) @ trans(x=row.a) @ rot_z(theta) @ trans(z=d)
        return rot_z(theta) @ trans(z=d) @ trans(x=row.a) @ rot_x(row.alpha)

    def frames(self, q: Sequence[float]) -> list[np.ndarray]:
        """``T_0_0 (= base), T_0_1, ..., T_0_n``."""
        out = [self.base]
        for row, qi in zip(self.rows, q, strict=True):
            out.append(out[-1] @ self.link(row, float(qi)))
        return out

    def pose(self, q: Sequence[float]) -> np.ndarray:
        return self.frames(q)[-1] @ self.tool

    def jacobian(self, q: Sequence[float]) -> np.ndarray:
        """Geometric Jacobian from joint axes (frame i-1 standard, frame i modified)."""
        frames = self.frames(q)
        p = self.pose(q)[:3, 3]
        axes = frames[1:] if self.modified else frames[:-1]
        columns = []
        for row, F in zip(self.rows, axes, strict=True):
            z, o = F[:3, 2], F[:3, 3]
            if row.kind == "R":
                columns.append(np.concatenate([np.cross(z, p - o), z]))
            else:
                columns.append(np.concatenate([z, np.zeros(3)]))
        return np.column_stack(columns)

    def point(self, link: int, r: Sequence[float], q: Sequence[float]) -> np.ndarray:
        return (self.frames(q)[link] @ np.array([*r, 1.0]))[:3]


def fd_jacobian(arm: Arm, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Geometric Jacobian by central differences of the pose: [dp/dq; vee(dR/dq R^T)]."""
    R = arm.pose(q)[:3, :3]
    columns = []
    for i in range(arm.n):
        step = np.zeros(arm.n)
        step[i] = h
        Tp, Tm = arm.pose(q + step), arm.pose(q - step)
        v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ R.T
        columns.append(np.concatenate([v, [W[2, 1], W[0, 2], W[1, 0]]]))
    return np.column_stack(columns)


def task(J: np.ndarray, rows: Sequence[str]) -> np.ndarray:
    return J[[ROW_NAMES.index(r) for r in rows], :]


# DH tables typed in from the robots' sources (see the catalogue files' `source` keys).
R90 = math.pi / 2
CATALOGUE: dict[str, tuple[Arm, dict[str, float], tuple[str, ...]]] = {
    "planar_2r": (
        Arm((Row("R", a=1.0), Row("R", a=1.0))),
        {"L1": 1.0, "L2": 1.0},
        ("x", "y"),
    ),
    "planar_3r": (
        Arm((Row("R", theta=R90, a=1.0), Row("R", theta=-R90, a=0.8), Row("R", a=0.5))),
        {"L1": 1.0, "L2": 0.8, "L3": 0.5},
        ("x", "y", "wz"),
    ),
    "scara": (
        Arm((Row("R", a=0.325), Row("R", a=0.225), Row("P"))),
        {"L1": 0.325, "L2": 0.225},
        ("x", "y", "z"),
    ),
    "rpr": (
        Arm((Row("R", alpha=R90), Row("P", theta=R90, alpha=R90), Row("R", a=1.0))),
        {"L3": 1.0},
        ("x", "y", "z"),
    ),
    "cylindrical_rtt_wrist": (
        Arm(
            (
                Row("R", d=0.5),
                Row("P", alpha=-R90),
                Row("P"),
                Row("R", alpha=-R90),
                Row("R", alpha=R90),
                Row("R", d=0.1),
            )
        ),
        {"d1": 0.5, "d6": 0.1},
        ROW_NAMES,
    ),
    "stanford": (
        Arm(
            (
                Row("R", d=0.412, alpha=-R90),
                Row("R", d=0.154, alpha=R90),
                Row("P"),
                Row("R", alpha=-R90),
                Row("R", alpha=R90),
                Row("R", d=0.263),
            )
        ),
        {"d1": 0.412, "d2": 0.154, "d6": 0.263},
        ROW_NAMES,
    ),
    "puma560": (
        Arm(
            (
                Row("R", alpha=R90),
                Row("R", a=0.4318),
                Row("R", d=0.15005, a=0.0203, alpha=-R90),
                Row("R", d=0.4318, alpha=R90),
                Row("R", alpha=-R90),
                Row("R"),
            )
        ),
        {"a2": 0.4318, "a3": 0.0203, "d3": 0.15005, "d4": 0.4318},
        ROW_NAMES,
    ),
    "ur5": (
        Arm(
            (
                Row("R", d=0.089159, alpha=R90),
                Row("R", a=-0.425),
                Row("R", a=-0.39225),
                Row("R", d=0.10915, alpha=R90),
                Row("R", d=0.09465, alpha=-R90),
                Row("R", d=0.0823),
            )
        ),
        {
            "d1": 0.089159,
            "a2": -0.425,
            "a3": -0.39225,
            "d4": 0.10915,
            "d5": 0.09465,
            "d6": 0.0823,
        },
        ROW_NAMES,
    ),
    "panda": (
        Arm(
            (
                Row("R", d=0.333),
                Row("R", alpha=-R90),
                Row("R", d=0.316, alpha=R90),
                Row("R", a=0.0825, alpha=R90),
                Row("R", a=-0.0825, d=0.384, alpha=-R90),
                Row("R", alpha=R90),
                Row("R", a=0.088, alpha=R90),
            ),
            modified=True,
            tool=trans(z=0.107),
        ),
        {"d1": 0.333, "d3": 0.316, "a4": 0.0825, "a5": -0.0825, "d5": 0.384, "a7": 0.088},
        ("x", "y", "z", "wz", "wx", "wy"),
    ),
}


# ---------------------------------------------------------------------------------------------
# Running the command
# ---------------------------------------------------------------------------------------------


def _no_nan(text: str) -> float:
    raise AssertionError(f"the JSON output contains {text}")


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    code, out, err = run(capsys, *argv, "--json")
    assert code == 0, err
    # Only one-line warnings may go to stderr (the catalogue PUMA's link-3 inertia, as Corke
    # published it, breaks the triangle inequality); the JSON stays clean on stdout.
    assert all(line.startswith("symkin: warning: ") for line in err.splitlines()), err
    return json.loads(out, parse_constant=_no_nan)


def values(v: Sequence[float]) -> str:
    """``"v1,v2,..."`` exactly (repr round-trips); negative values start with '-'."""
    return ",".join(repr(float(x)) for x in v)


def random_q(arm: Arm, rng: np.random.Generator) -> np.ndarray:
    return np.array(
        [rng.uniform(-2.5, 2.5) if r.kind == "R" else rng.uniform(0.2, 1.2) for r in arm.rows]
    )


def assert_user_error(code: int, out: str, err: str, *fragments: str) -> None:
    assert code == 2
    assert out == ""
    assert "Traceback" not in err
    assert err.startswith("symkin: error:"), err
    assert err.count("\n") == 1 and err.endswith("\n"), err
    for fragment in fragments:
        assert fragment in err, (fragment, err)


def check_eval(data: dict, arm: Arm, q: np.ndarray, rows: Sequence[str]) -> None:
    """Pose, Euler angles, Jacobian, task determinant and manipulability of ``eval --json``."""
    T = np.array(data["T"])
    expected = arm.pose(q)
    np.testing.assert_allclose(T, expected, atol=TOL)
    np.testing.assert_allclose(data["position"], expected[:3, 3], atol=TOL)

    psi, theta, phi = data["euler_zyx"]
    rebuilt = (rot_z(psi) @ rot_y(theta) @ rot_x(phi))[:3, :3]
    np.testing.assert_allclose(rebuilt, expected[:3, :3], atol=1e-9)
    assert -math.pi / 2 - 1e-12 <= theta <= math.pi / 2 + 1e-12

    J = np.array(data["jacobian"])
    assert J.shape == (6, arm.n)
    np.testing.assert_allclose(J, arm.jacobian(q), atol=TOL)
    np.testing.assert_allclose(J, fd_jacobian(arm, q), atol=1e-7)

    assert data["task_rows"] == list(rows)
    Jt = task(arm.jacobian(q), rows)
    if len(rows) == arm.n:
        assert data["det"] == pytest.approx(np.linalg.det(Jt), abs=1e-10)
    else:
        assert data["det"] is None
    manipulability = math.sqrt(max(np.linalg.det(Jt @ Jt.T), 0.0))
    # abs: sqrt(det(J J^T)) of a singular J is sqrt(rounding noise), up to ~1e-8
    assert data["manipulability"] == pytest.approx(manipulability, rel=1e-8, abs=1e-7)


def check_points(
    data: dict,
    arm: Arm,
    q: np.ndarray,
    dq: np.ndarray | None,
    ddq: np.ndarray | None,
    points: Sequence[tuple[int, Sequence[float]]],
) -> None:
    """``points`` of ``eval --json`` against finite differences along q + dq t + ddq t^2/2."""
    assert len(data["points"]) == len(points)
    for result, (link, r) in zip(data["points"], points, strict=True):
        assert result["link"] == link
        np.testing.assert_allclose(result["point"], r, atol=1e-15)
        np.testing.assert_allclose(result["position"], arm.point(link, r, q), atol=TOL)
        if dq is None:
            assert result["velocity"] is None
            assert result["acceleration"] is None
            continue
        path_ddq = np.zeros(arm.n) if ddq is None else ddq

        def at(
            t: float, link: int = link, r: Sequence[float] = r, ddq_: np.ndarray = path_ddq
        ) -> np.ndarray:
            return arm.point(link, r, q + dq * t + ddq_ * t * t / 2)

        h = 1e-5
        velocity = (at(h) - at(-h)) / (2 * h)
        np.testing.assert_allclose(result["velocity"], velocity, atol=1e-7)
        if ddq is None:
            assert result["acceleration"] is None
            continue
        h = 1e-4
        acceleration = (at(h) - 2 * at(0.0) + at(-h)) / h**2
        np.testing.assert_allclose(result["acceleration"], acceleration, atol=2e-5)


# ---------------------------------------------------------------------------------------------
# symkin list, --help
# ---------------------------------------------------------------------------------------------


def test_list_shows_every_catalogue_file(capsys: pytest.CaptureFixture[str]) -> None:
    files = sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))
    assert set(files) == set(CATALOGUE)  # the tables above cover the whole catalogue
    code, out, err = run(capsys, "list")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert sorted(line.split()[0] for line in lines) == files
    for line in lines:
        name = line.split()[0]
        assert f"{CATALOGUE[name][0].n} DOF" in line


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([], ("list", "show", "eval")),
        (["list"], ("usage: symkin list",)),
        (["show"], ("usage: symkin show", "--json", "--task")),
        (["eval"], ("usage: symkin eval", "--q", "--dq", "--ddq", "--set", "--point", "--task")),
    ],
)
def test_help(capsys: pytest.CaptureFixture[str], argv: list[str], expected: tuple[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, "--help"])
    assert exit_info.value.code == 0
    out, _ = capsys.readouterr()
    assert out.startswith("usage: symkin")
    for fragment in expected:
        assert fragment in out


# ---------------------------------------------------------------------------------------------
# symkin show --json: parse the expressions back and evaluate them
# ---------------------------------------------------------------------------------------------


def parse(text: str, names: dict[str, sp.Symbol]) -> sp.Expr:
    assert isinstance(text, str)
    expr = sp.sympify(text, locals=names)
    assert expr.free_symbols <= set(names.values()), text
    return expr


def symbols_of(
    n: int, parameters: dict[str, float]
) -> tuple[dict[str, sp.Symbol], list[sp.Symbol]]:
    q = [sp.Symbol(f"q{i}", real=True) for i in range(1, n + 1)]
    names = {s.name: s for s in q} | {p: sp.Symbol(p, real=True) for p in parameters}
    return names, q


def numeric(
    expr: sp.Expr | sp.MatrixBase, q: list[sp.Symbol], parameters, names
) -> Callable[[np.ndarray], np.ndarray]:
    substituted = expr.xreplace({names[p]: sp.Float(v) for p, v in parameters.items()})
    function = sp.lambdify([q], substituted, modules="numpy")
    return lambda qv: np.asarray(function(list(qv)), dtype=float)


def solve_condition(
    condition: sp.Eq, q: list[sp.Symbol], parameters, names, start: np.ndarray
) -> np.ndarray:
    """A configuration satisfying ``condition``: the other joints keep their ``start`` values."""
    assert isinstance(condition, sp.Eq), condition
    substitution = {names[p]: sp.Float(v) for p, v in parameters.items()}
    result = start.copy()
    if condition.lhs in q and not condition.rhs.free_symbols:  # Eq(q2, pi)
        result[q.index(condition.lhs)] = float(condition.rhs)
        return result
    residual = (condition.lhs - condition.rhs).xreplace(substitution)
    for variable in sorted(residual.free_symbols, key=lambda s: s.name):
        i = q.index(variable)
        others = {s: sp.Float(start[j]) for j, s in enumerate(q) if j != i}
        f = sp.lambdify(variable, residual.xreplace(others), modules="numpy")
        grid = np.linspace(-math.pi, math.pi, 4001)
        g = np.broadcast_to(np.asarray(f(grid), dtype=float), grid.shape)
        changes = np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) <= 0)[0]
        if changes.size == 0:
            continue
        lo, hi = grid[changes[0]], grid[changes[0] + 1]
        for _ in range(200):
            mid = (lo + hi) / 2
            if np.sign(f(mid)) == np.sign(f(lo)):
                lo = mid
            else:
                hi = mid
        result[i] = (lo + hi) / 2
        return result
    raise AssertionError(f"found no configuration with {condition}")


SHOW_ROBOTS = (
    "planar_2r",
    "planar_3r",
    "scara",
    "rpr",
    "cylindrical_rtt_wrist",
    "stanford",
    "panda",
)


@pytest.mark.parametrize("name", SHOW_ROBOTS)
def test_show_json_expressions_evaluate_to_the_independent_model(
    capsys: pytest.CaptureFixture[str], name: str
) -> None:
    arm, parameters, rows = CATALOGUE[name]
    data = run_json(capsys, "show", name)
    assert set(data) >= {"T", "jacobian", "det", "singular"}
    assert data["task_rows"] == list(rows)
    names, q = symbols_of(arm.n, parameters)

    T = numeric(sp.Matrix([[parse(e, names) for e in r] for r in data["T"]]), q, parameters, names)
    assert len(data["T"]) == 4 and all(len(r) == 4 for r in data["T"])
    J = numeric(
        sp.Matrix([[parse(e, names) for e in r] for r in data["jacobian"]]), q, parameters, names
    )
    assert len(data["jacobian"]) == 6 and all(len(r) == arm.n for r in data["jacobian"])
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    for _ in range(3):
        qv = random_q(arm, rng)
        np.testing.assert_allclose(T(qv), arm.pose(qv), atol=TOL)
        np.testing.assert_allclose(J(qv), arm.jacobian(qv), atol=TOL)

    if len(rows) != arm.n:
        assert data["det"] is None
        assert data["singular"] == []
        return
    det = numeric(parse(data["det"], names), q, parameters, names)
    qv = random_q(arm, rng)
    reference = np.linalg.det(task(arm.jacobian(qv), rows))
    assert abs(reference) > 1e-6  # a generic configuration: the checks below can fail
    assert float(det(qv)) == pytest.approx(reference, rel=1e-9, abs=1e-12)

    assert data["singular"], "a square task Jacobian of these robots has singularities"
    for text in data["singular"]:
        condition = parse(text, names)
        singular_q = solve_condition(condition, q, parameters, names, qv)
        assert abs(np.linalg.det(task(arm.jacobian(singular_q), rows))) < 1e-9, text


def test_show_scara_determinant_is_l1_l2_sin_q2(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "show", "scara")
    names, q = symbols_of(3, {"L1": 0.325, "L2": 0.225})
    L1, L2, q2 = names["L1"], names["L2"], q[1]
    det = parse(data["det"], names)
    assert sp.simplify(det - L1 * L2 * sp.sin(q2)) == 0
    conditions = {parse(s, names) for s in data["singular"]}
    assert conditions == {sp.Eq(q2, 0), sp.Eq(q2, sp.pi)}


def test_show_task_rows_choose_the_determinant(capsys: pytest.CaptureFixture[str]) -> None:
    # Rows x and wz of a planar 2R arm: det = -L1 sin(q1), singular at q1 = 0 and pi.
    data = run_json(capsys, "show", "planar_2r", "--task", "x,wz")
    names, (q1, _) = symbols_of(2, {"L1": 1.0, "L2": 1.0})
    assert sp.simplify(parse(data["det"], names) + names["L1"] * sp.sin(q1)) == 0
    assert {parse(s, names) for s in data["singular"]} == {sp.Eq(q1, 0), sp.Eq(q1, sp.pi)}
    # Fewer rows than joints: no determinant, no singular list.
    data = run_json(capsys, "show", "planar_3r", "--task", "x,y")
    assert data["det"] is None
    assert data["singular"] == []


def test_show_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "show", "scara")
    assert code == 0 and err == ""
    assert "L1*L2*sin(q2)" in out
    assert "q2 = 0" in out and "q2 = pi" in out


# ---------------------------------------------------------------------------------------------
# symkin eval --json on the catalogue
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_eval_catalogue_robot(capsys: pytest.CaptureFixture[str], name: str) -> None:
    arm, _, rows = CATALOGUE[name]
    q = random_q(arm, np.random.default_rng(7 + len(name)))
    q[0] = -abs(q[0]) - 0.1  # the value string starts with '-': a separate argument must work
    data = run_json(capsys, "eval", name, "--q", values(q))
    check_eval(data, arm, q, rows)
    if name == "panda":
        assert data["det"] is None


@pytest.mark.parametrize(
    ("name", "rows"),
    [("planar_3r", ("x", "y")), ("planar_2r", ("x", "wz")), ("scara", ("x", "y", "wz"))],
)
def test_eval_task_rows(capsys: pytest.CaptureFixture[str], name: str, rows: tuple[str]) -> None:
    arm = CATALOGUE[name][0]
    q = random_q(arm, np.random.default_rng(3))
    data = run_json(capsys, "eval", name, "--q", values(q), "--task", ",".join(rows))
    check_eval(data, arm, q, rows)


@pytest.mark.parametrize(
    ("name", "points"),
    [
        ("planar_2r", [(2, (0.0, 0.0, 0.0)), (1, (0.3, -0.2, 0.1)), (0, (0.1, 0.2, 0.3))]),
        ("rpr", [(3, (0.1, -0.2, 0.3)), (2, (-0.1, 0.0, 0.2))]),
        ("scara", [(3, (0.05, 0.02, -0.1)), (1, (-0.1, 0.1, 0.0))]),
        ("planar_3r", [(3, (0.0, 0.0, 0.0)), (2, (0.2, 0.1, 0.0))]),
    ],
)
def test_eval_points(capsys: pytest.CaptureFixture[str], name: str, points) -> None:
    arm = CATALOGUE[name][0]
    rng = np.random.default_rng(11)
    q, dq, ddq = random_q(arm, rng), rng.uniform(-2, 2, arm.n), rng.uniform(-2, 2, arm.n)
    point_args = [arg for link, r in points for arg in ("--point", f"{link}:{values(r)}")]
    base = ["eval", name, "--q", values(q), *point_args]

    data = run_json(capsys, *base, "--dq", values(dq), "--ddq", values(ddq))
    check_eval(data, arm, q, CATALOGUE[name][2])
    check_points(data, arm, q, dq, ddq, points)
    link, r = points[0]
    if link == arm.n and not any(r):  # the tool point: v = Jv dq
        np.testing.assert_allclose(data["points"][0]["velocity"], arm.jacobian(q)[:3] @ dq)

    if name == "planar_2r":  # without --ddq no acceleration, without --dq no velocity either
        check_points(run_json(capsys, *base, "--dq", values(dq)), arm, q, dq, None, points)
        check_points(run_json(capsys, *base), arm, q, None, None, points)


def test_eval_degrees_and_negative_values(capsys: pytest.CaptureFixture[str]) -> None:
    arm = CATALOGUE["planar_2r"][0]
    q = np.array([-30 * DEG, 45 * DEG])
    separate = run_json(capsys, "eval", "planar_2r", "--q", "-30deg,45deg")
    joined = run_json(capsys, "eval", "planar_2r", "--q=-30deg,45deg")
    radians = run_json(capsys, "eval", "planar_2r", "--q", values(q))
    assert separate == joined
    np.testing.assert_allclose(separate["T"], radians["T"], atol=1e-15)
    check_eval(separate, arm, q, ("x", "y"))
    # closed form of the planar 2R arm at q = (-30, 45) deg
    x = math.cos(-30 * DEG) + math.cos(15 * DEG)
    y = math.sin(-30 * DEG) + math.sin(15 * DEG)
    np.testing.assert_allclose(separate["position"], [x, y, 0.0], atol=1e-12)

    dq = np.array([-0.5, 20 * DEG])
    data = run_json(
        capsys,
        "eval", "planar_2r", "--q", "-30deg,45deg", "--dq", "-0.5,20deg",
        "--ddq", "-10deg,-0.25", "--point", "2:-0.1,0.2,-0.3",
    )  # fmt: skip
    check_points(data, arm, q, dq, np.array([-10 * DEG, -0.25]), [(2, (-0.1, 0.2, -0.3))])


def test_manipulability_at_a_singularity_is_abs_det(capsys: pytest.CaptureFixture[str]) -> None:
    # CONVENTIONS.md: mu = sqrt(det(J J^T)) equals |det J| when J is square.
    data = run_json(capsys, "eval", "planar_2r", "--q", "0.3,0")
    assert data["det"] == pytest.approx(0.0, abs=1e-15)
    assert data["manipulability"] == pytest.approx(abs(data["det"]), abs=1e-12)


def test_eval_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "eval", "scara", "--q", "0,90deg,0.1")
    assert code == 0 and err == ""
    assert "det = 0.073125" in out  # L1 L2 sin(90 deg) = 0.325 * 0.225
    line = next(x for x in out.splitlines() if x.startswith("position = "))
    position = [float(v) for v in line.partition("[")[2].rstrip("]").split()]
    np.testing.assert_allclose(position, [0.325, 0.225, 0.1], atol=1e-6)


def test_eval_euler_angles_at_gimbal_lock(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "pitched.toml"
    path.write_text(
        'name = "pitched"\n[[joints]]\ntype = "revolute"\na = 0.2\n'
        "[tool]\nxyz = [0.1, 0, 0]\nrpy = [0, 90, 0]\n"
    )
    arm = Arm((Row("R", a=0.2),), tool=frame((0.1, 0, 0), (0, R90, 0)))
    data = run_json(capsys, "eval", str(path), "--q", "0.7")
    assert data["euler_zyx_singular"] is True
    check_eval(data, arm, np.array([0.7]), ("x",))


# ---------------------------------------------------------------------------------------------
# symkin eval on user-written robot files
# ---------------------------------------------------------------------------------------------

# Standard DH, degrees: constant theta on both joint types, a prismatic joint with a negative
# offset, negative a and d, expressions of parameters, a parameter without a value, base and tool.
USER_STANDARD = """\
name = "user_std"
convention = "standard"
angles = "deg"

[parameters]
L1 = 0.4
h = "symbol"
off = -0.2

[[joints]]
type = "revolute"
theta = 30
d = "h"
a = "-L1/2"
alpha = 90

[[joints]]
type = "prismatic"
theta = -60
d = "off"
a = -0.15
alpha = -90

[[joints]]
type = "revolute"
d = -0.1
a = "L1"
alpha = 60

[base]
xyz = [0.1, -0.2, 0.3]
rpy = [0, 0, 30]

[tool]
xyz = [0.0, 0.02, 0.12]
rpy = [0, 45, 0]
"""


def user_standard_arm(h: float, L1: float = 0.4) -> Arm:
    return Arm(
        (
            Row("R", theta=30 * DEG, d=h, a=-L1 / 2, alpha=90 * DEG),
            Row("P", theta=-60 * DEG, d=-0.2, a=-0.15, alpha=-90 * DEG),
            Row("R", d=-0.1, a=L1, alpha=60 * DEG),
        ),
        base=frame((0.1, -0.2, 0.3), (0, 0, 30 * DEG)),
        tool=frame((0.0, 0.02, 0.12), (0, 45 * DEG, 0)),
    )


# Modified DH, radians: each row holds (alpha_{i-1}, a_{i-1}); a prismatic first joint with
# constant theta, negative a and d, a base mounted upside down, a tool.
USER_MODIFIED = """\
name = "user_mod"
convention = "modified"
angles = "rad"

[parameters]
a1 = -0.3
d2 = -0.25

[[joints]]
type = "prismatic"
theta = 0.5
d = 0.1
a = 0.1
alpha = 0.2

[[joints]]
type = "revolute"
theta = -0.7
d = "d2"
a = "a1"
alpha = "-pi/2"

[[joints]]
type = "revolute"
d = 0.15
a = 0.35
alpha = "pi/2"

[base]
xyz = [0, 0, 0.5]
rpy = [3.141592653589793, 0, 0]

[tool]
xyz = [0.01, 0, 0.1]
rpy = [0, 0, 0.3]
"""


def user_modified_arm(a1: float = -0.3) -> Arm:
    return Arm(
        (
            Row("P", theta=0.5, d=0.1, a=0.1, alpha=0.2),
            Row("R", theta=-0.7, d=-0.25, a=a1, alpha=-R90),
            Row("R", d=0.15, a=0.35, alpha=R90),
        ),
        modified=True,
        base=frame((0, 0, 0.5), (math.pi, 0, 0)),
        tool=frame((0.01, 0, 0.1), (0, 0, 0.3)),
    )


@pytest.fixture
def user_files(tmp_path: Path) -> dict[str, str]:
    files = {"standard": USER_STANDARD, "modified": USER_MODIFIED}
    for key, text in files.items():
        (tmp_path / f"{key}.toml").write_text(text)
    return {key: str(tmp_path / f"{key}.toml") for key in files}


def test_eval_user_standard_file_with_set(
    capsys: pytest.CaptureFixture[str], user_files: dict[str, str]
) -> None:
    rng = np.random.default_rng(5)
    arm = user_standard_arm(h=0.7, L1=0.55)
    q = np.array([-0.4, -0.3, 1.1])  # a negative prismatic value
    data = run_json(
        capsys, "eval", user_files["standard"], "--q", values(q), "--set", "h=0.7",
        "--set", "L1=0.55",
    )  # fmt: skip
    check_eval(data, arm, q, ("x", "y", "z"))

    # the file's L1 = 0.4 when it is not overridden
    data = run_json(capsys, "eval", user_files["standard"], "--q", values(q), "--set", "h=-0.3")
    check_eval(data, user_standard_arm(h=-0.3), q, ("x", "y", "z"))

    dq, ddq = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
    # link 2 (after the prismatic joint) and the base; link 3 is covered by the modified file
    points = [(2, (0.0, 0.1, -0.1)), (0, (0.3, 0.0, 0.0))]
    data = run_json(
        capsys, "eval", user_files["standard"], "--q", values(q), "--dq", values(dq),
        "--ddq", values(ddq), "--set", "h=0.7", "--set", "L1=0.55",
        *[a for link, r in points for a in ("--point", f"{link}:{values(r)}")],
    )  # fmt: skip
    check_points(data, arm, q, dq, ddq, points)


def test_eval_user_modified_file(
    capsys: pytest.CaptureFixture[str], user_files: dict[str, str]
) -> None:
    rng = np.random.default_rng(9)
    q = np.array([-0.15, 0.8, -1.3])
    data = run_json(capsys, "eval", user_files["modified"], "--q", values(q))
    check_eval(data, user_modified_arm(), q, ("x", "y", "z"))

    arm = user_modified_arm(a1=-0.45)
    dq, ddq = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
    points = [(3, (0.05, 0.1, -0.2)), (1, (0.2, -0.1, 0.0))]
    data = run_json(
        capsys, "eval", user_files["modified"], "--q", values(q), "--set", "a1=-0.45",
        "--dq", values(dq), "--ddq", values(ddq),
        *[a for link, r in points for a in ("--point", f"{link}:{values(r)}")],
    )  # fmt: skip
    check_eval(data, arm, q, ("x", "y", "z"))
    check_points(data, arm, q, dq, ddq, points)


def test_modified_file_matches_standard_catalogue_robot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    # The planar 2R arm in modified DH: (alpha0, a0) = 0, (alpha1, a1) = (0, L1), tool at L2.
    path = tmp_path / "planar_2r_modified.toml"
    path.write_text(
        'name = "planar_2r_modified"\nconvention = "modified"\n'
        "[parameters]\nL1 = 1.0\nL2 = 1.0\n"
        '[[joints]]\ntype = "revolute"\n'
        '[[joints]]\ntype = "revolute"\na = "L1"\n'
        '[tool]\nxyz = ["L2", 0, 0]\n'
    )
    q = "-20deg,70deg"
    modified = run_json(capsys, "eval", str(path), "--q", q)
    standard = run_json(capsys, "eval", "planar_2r", "--q", q)
    for key in ("T", "jacobian", "euler_zyx"):
        np.testing.assert_allclose(modified[key], standard[key], atol=1e-12)
    assert modified["det"] == pytest.approx(standard["det"], abs=1e-12)


def test_show_user_file_keeps_parameter_names(
    capsys: pytest.CaptureFixture[str], user_files: dict[str, str]
) -> None:
    data = run_json(capsys, "show", user_files["modified"])
    parameters = {"a1": -0.3, "d2": -0.25}
    names, q = symbols_of(3, parameters)
    T = sp.Matrix([[parse(e, names) for e in r] for r in data["T"]])
    assert {s.name for s in T.free_symbols} >= {"a1", "d2"}
    qv = np.array([0.3, -0.6, 1.7])
    np.testing.assert_allclose(
        numeric(T, q, parameters, names)(qv), user_modified_arm().pose(qv), atol=TOL
    )


# ---------------------------------------------------------------------------------------------
# User mistakes: exit status 2, one line on stderr, no traceback
# ---------------------------------------------------------------------------------------------

ROTARY = 'name = "bad"\n[[joints]]\ntype = "rotary"\n'


@pytest.mark.parametrize(
    ("argv", "fragments"),
    [
        (["eval", "no_such_robot", "--q", "0"], ("no_such_robot",)),
        (["show", "no_such_robot"], ("no_such_robot",)),
        (["eval", "scara", "--q", "0.1,0.2"], ("3 joints",)),
        (["eval", "scara", "--q", "0.1,0.2,0.3,0.4"], ("3 joints",)),
        (["eval", "scara", "--q", "0,0,0", "--dq", "1,2"], ("--dq",)),
        (["eval", "planar_2r", "--q", "0.1,abc"], ("'abc'",)),
        (["eval", "planar_2r", "--q", "0.1,nan"], ("nan",)),
        (["eval", "planar_2r", "--q", "0.1,1e999"], ("1e999",)),
        (["eval", "planar_2r", "--q", "0.1,30 degrees"], ("30 degrees",)),
        (["eval", "scara", "--q", "0,0,10deg"], ("prismatic",)),
        (["eval", "scara", "--q", "0,0,0", "--dq", "0,0,-1deg"], ("prismatic",)),
        (["eval", "scara", "--q", "0,0,0", "--ddq", "0,0,0"], ("--dq",)),
        (["eval", "scara", "--q", "0,0,0", "--set", "L9=1"], ("L9",)),
        (["eval", "scara", "--q", "0,0,0", "--set", "L1"], ("NAME=VALUE",)),
        (["eval", "scara", "--q", "0,0,0", "--set", "L1=long"], ("long",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "4:0,0,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "-1:0,0,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "1:0,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "1,0,0,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "one:0,0,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--point", "1:0,x,0"], ("--point",)),
        (["eval", "scara", "--q", "0,0,0", "--task", "x,vy"], ("vy", "task row")),
        (["eval", "scara", "--q", "0,0,0", "--task", "x,x"], ("repeat",)),
        (["show", "scara", "--task", "x,y,speed"], ("speed", "task row")),
    ],
)
def test_user_errors_in_process(
    capsys: pytest.CaptureFixture[str], argv: list[str], fragments: tuple[str]
) -> None:
    assert_user_error(*run(capsys, *argv), *fragments)


def test_file_errors_in_process(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, user_files: dict[str, str]
) -> None:
    rotary = tmp_path / "rotary.toml"
    rotary.write_text(ROTARY)
    assert_user_error(*run(capsys, "eval", str(rotary), "--q", "0"), "rotary", "joint 1")
    assert_user_error(*run(capsys, "show", str(rotary)), "rotary")
    missing = tmp_path / "missing.toml"
    assert_user_error(*run(capsys, "eval", str(missing), "--q", "0"), "missing.toml")
    broken = tmp_path / "broken.toml"
    broken.write_text("name = \n")
    assert_user_error(*run(capsys, "eval", str(broken), "--q", "0"), "broken.toml")

    # A parameter declared "symbol" has no value: eval needs --set.
    standard = user_files["standard"]
    assert_user_error(*run(capsys, "eval", standard, "--q", "0,0,0"), "h", "--set")
    assert_user_error(
        *run(capsys, "eval", standard, "--q", "0,0,0", "--set", "L1=0.3"), "h", "--set"
    )
    # deg on the prismatic joint 2 of a user file
    assert_user_error(
        *run(capsys, "eval", standard, "--q", "0,5deg,0", "--set", "h=1"), "joint 2", "prismatic"
    )


# ---------------------------------------------------------------------------------------------
# The installed script, in real subprocesses (~1 s each; started together by an autouse
# fixture with the first test of this module, collected by the tests at its end)
# ---------------------------------------------------------------------------------------------


def _symkin_script() -> str:
    script = Path(sys.executable).with_name("symkin")
    if script.exists():
        return str(script)
    found = shutil.which("symkin")
    assert found, "the symkin script is not installed"
    return found


@pytest.fixture(scope="module", autouse=True)
def script_processes(
    tmp_path_factory: pytest.TempPathFactory,
) -> Iterator[dict[str, subprocess.Popen[str]]]:
    """Start the script runs with the module's first test, so they overlap the other tests."""
    directory = tmp_path_factory.mktemp("cli")
    rotary = directory / "rotary.toml"
    rotary.write_text(ROTARY)
    symbol = directory / "symbolic.toml"
    symbol.write_text(USER_STANDARD)
    commands = {
        "list": ["list"],
        "eval": ["eval", "planar_2r", "--q", "-30deg,45deg", "--json"],
        "unknown_robot": ["eval", "no_such_robot", "--q", "0"],
        "rotary": ["eval", str(rotary), "--q", "0"],
        "symbol": ["eval", str(symbol), "--q", "-0.1,0.2,0.3"],
    }
    script = _symkin_script()
    processes = {
        key: subprocess.Popen(
            [script, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        for key, argv in commands.items()
    }
    yield processes
    for process in processes.values():
        if process.poll() is None:  # not collected (tests deselected or failed early)
            process.kill()
            process.communicate()


@pytest.fixture(scope="module")
def subprocess_results(
    script_processes: dict[str, subprocess.Popen[str]],
) -> dict[str, tuple[int, str, str]]:
    results = {}
    for key, process in script_processes.items():
        out, err = process.communicate(timeout=120)
        results[key] = (process.returncode, out, err)
    return results


def test_script_list(subprocess_results: dict[str, tuple[int, str, str]]) -> None:
    code, out, err = subprocess_results["list"]
    assert code == 0 and err == ""
    names = sorted(line.split()[0] for line in out.splitlines())
    assert names == sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def test_script_eval_negative_degrees(subprocess_results: dict[str, tuple[int, str, str]]) -> None:
    code, out, err = subprocess_results["eval"]
    assert code == 0, err
    q = np.array([-30 * DEG, 45 * DEG])
    check_eval(json.loads(out, parse_constant=_no_nan), CATALOGUE["planar_2r"][0], q, ("x", "y"))


@pytest.mark.parametrize(
    ("key", "fragments"),
    [
        ("unknown_robot", ("no_such_robot",)),
        ("rotary", ("rotary", "joint 1", "rotary.toml")),
        ("symbol", ("h", "--set")),
    ],
)
def test_script_user_errors(
    subprocess_results: dict[str, tuple[int, str, str]], key: str, fragments: tuple[str]
) -> None:
    assert_user_error(*subprocess_results[key], *fragments)
