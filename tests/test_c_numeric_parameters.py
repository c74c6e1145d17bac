"""C of a robot without parameters (``symkin derive --numeric-parameters``): no ``p`` argument.

The planar 2R arm with its lengths folded into the code: the kernels, forward dynamics, the
numeric and the closed-form IK take no ``p``, the example and the CPython extension call them
without one, and everything compiles under strict warnings in double and float.

Expected values are typed in by hand, not taken from symkin: the planar 2R closed form
x = L1 c1 + L2 c12, y = L1 s1 + L2 s12, heading q1 + q2 (Spong, Hutchinson, Vidyasagar, Robot
Modeling and Control, Sec. 3.3), its two elbow solutions q2 = +-acos((x^2 + y^2 - L1^2 - L2^2)
/ (2 L1 L2)), and the mass matrix of two links whose centres of mass lie on them.
"""

from __future__ import annotations

import ctypes
import math
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from codegen_helpers import CC, CONVERSION, SHARED, STRICT, run_parallel
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.runtime.extension import load_extension

pytestmark = pytest.mark.needs_cc

# Unequal lengths (the file's are both 1), so that a swapped L1 and L2 shows.
L1, L2 = 0.7, 0.4
PRECISIONS = ("double", "float")
# fk and closed-form IK against the hand formulas; the numeric IK stops at its tolerances.
TOLERANCE = {"double": 1e-12, "float": 1e-5}
IK_TOLERANCE = {"double": 1e-9, "float": 3e-5}
SUCCESS = 0
# -Wvla: the numeric IK's work array must be of fixed size.
FLAGS = [*STRICT, *CONVERSION, "-Wvla"]
STATES = np.array([[0.3, -1.1], [-2.0, 0.7], [1.2, 2.5], [0.1, 0.2]])


def pose(q1: float, q2: float) -> np.ndarray:
    """Tool pose of the planar 2R arm: rotation by q1 + q2 about z, tool at (x, y, 0)."""
    c1, s1 = math.cos(q1), math.sin(q1)
    c12, s12 = math.cos(q1 + q2), math.sin(q1 + q2)
    return np.array(
        [
            [c12, -s12, 0.0, L1 * c1 + L2 * c12],
            [s12, c12, 0.0, L1 * s1 + L2 * s12],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


@dataclass
class Built:
    root: Path
    libraries: dict[str, ctypes.CDLL]
    dtypes: dict[str, type]
    max_solutions: int


def c_folder(root: Path, precision: str) -> Path:
    return root / precision / "c"


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Built:
    root = tmp_path_factory.mktemp("planar_2r_numeric")
    # The catalogue file without its inertial data: pi stays an input.
    bare = root / "planar_2r.toml"
    bare.write_text(without_inertials("planar_2r"), encoding="utf-8")
    common = ["--numeric-parameters", "--set", f"L1={L1}", "--set", f"L2={L2}"]
    argv = ["derive", str(bare), "--out", str(root / "double"), "--emit", "c,python", *common]
    assert main(argv) == 0
    argv = ["derive", str(bare), "--out", str(root / "float"), "--emit", "c", *common]
    assert main([*argv, "--precision", "float", "--no-build"]) == 0
    sources = ["planar_2r.c", "planar_2r_ik.c", "planar_2r_ik_closed.c"]
    commands = {}
    for precision in PRECISIONS:
        c = c_folder(root, precision)
        example = [CC, *FLAGS, "-o", str(c / "example"), str(c / "example.c")]
        commands[precision, "example"] = [*example, str(c / "planar_2r.c"), "-lm"]
        library = [CC, *FLAGS, *SHARED, "-o", str(c / "libplanar_2r.so")]
        commands[precision, "library"] = [*library, *(str(c / s) for s in sources), "-lm"]
    for build in run_parallel(commands, root).values():
        build.check()
    header = (c_folder(root, "double") / "planar_2r_ik_closed.h").read_text()
    (max_solutions,) = re.findall(r"#define PLANAR_2R_IK_CLOSED_MAX_SOLUTIONS (\d+)", header)
    return Built(
        root,
        {p: ctypes.CDLL(str(c_folder(root, p) / "libplanar_2r.so")) for p in PRECISIONS},
        {"double": np.float64, "float": np.float32},
        int(max_solutions),
    )


def declarations(c: Path) -> dict[str, str]:
    """``{function: parameter list}`` of every function the headers declare."""
    pattern = re.compile(r"^(?:void|int) (\w+)\(([^)]*)\);", re.M)
    return {
        name: parameters
        for header in sorted(c.glob("*.h"))
        for name, parameters in pattern.findall(header.read_text())
    }


@pytest.mark.parametrize("precision", PRECISIONS)
def test_no_function_takes_p(built, precision):
    c = c_folder(built.root, precision)
    declared = declarations(c)
    expected = {"planar_2r_fk", "planar_2r_fk_batch", "planar_2r_fk_jacobian", "planar_2r_ik"}
    expected |= {"planar_2r_ik_closed", "planar_2r_mass_matrix", "planar_2r_forward_dynamics"}
    assert expected <= declared.keys()
    with_p = {name: ps for name, ps in declared.items() if re.search(r"\*\s*p\b|\bp\[", ps)}
    assert with_p == {}
    assert declared["planar_2r_fk"] == f"const {precision} q[2], {precision} T[SYMKIN_RESTRICT 16]"
    # Forward dynamics takes the inertial parameters pi the robot file leaves out, not p.
    assert declared["planar_2r_forward_dynamics"] == (
        f"const {precision} q[2], const {precision} dq[2], const {precision} tau[2], "
        f"const {precision} *pi, {precision} ddq[SYMKIN_RESTRICT 2]"
    )
    for header in c.glob("*.h"):
        assert not re.search(r"^ \* p[:\[]", header.read_text(), re.M), header.name


@pytest.mark.parametrize("precision", PRECISIONS)
def test_example_prints_the_closed_form_pose(built, precision):
    c = c_folder(built.root, precision)
    done = subprocess.run([str(c / "example")], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "T of planar_2r at q = (0.1, 0.2):"
    printed = np.array([[float(v) for v in line.split()] for line in lines[1:5]])
    np.testing.assert_allclose(printed, pose(0.1, 0.2), rtol=0, atol=1e-6)  # printed %.6f


def array(built: Built, precision: str, values) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=built.dtypes[precision])


@pytest.mark.parametrize("precision", PRECISIONS)
def test_fk_is_the_closed_form(built, precision):
    fk = built.libraries[precision].planar_2r_fk
    fk.argtypes, fk.restype = [ctypes.c_void_p] * 2, None
    for q in STATES:
        T = array(built, precision, np.full(16, np.nan))
        fk(array(built, precision, q).ctypes.data, T.ctypes.data)
        np.testing.assert_allclose(T.reshape(4, 4), pose(*q), rtol=0, atol=TOLERANCE[precision])


@pytest.mark.parametrize("precision", PRECISIONS)
def test_numeric_ik_reaches_the_pose(built, precision):
    ik = built.libraries[precision].planar_2r_ik
    # T_target, q_seed, options (NULL: defaults), q, result (NULL)
    ik.argtypes, ik.restype = [ctypes.c_void_p] * 5, ctypes.c_int
    for q_true in STATES:
        target = array(built, precision, pose(*q_true))
        seed = array(built, precision, q_true + 0.3)
        q = array(built, precision, np.full(2, np.nan))
        status = ik(target.ctypes.data, seed.ctypes.data, None, q.ctypes.data, None)
        assert status == SUCCESS
        np.testing.assert_allclose(pose(*q), pose(*q_true), rtol=0, atol=IK_TOLERANCE[precision])


@pytest.mark.parametrize("precision", PRECISIONS)
def test_closed_form_ik_gives_both_elbows(built, precision):
    ik_closed = built.libraries[precision].planar_2r_ik_closed
    # T, q, branch (NULL), within_limits (NULL)
    ik_closed.argtypes, ik_closed.restype = [ctypes.c_void_p] * 4, ctypes.c_int
    tolerance = TOLERANCE[precision]
    for q_true in STATES:
        x, y = pose(*q_true)[:2, 3]
        elbow = math.acos((x * x + y * y - L1 * L1 - L2 * L2) / (2 * L1 * L2))
        target = array(built, precision, pose(*q_true))
        q = array(built, precision, np.full(2 * built.max_solutions, np.nan))
        count = ik_closed(target.ctypes.data, q.ctypes.data, None, None)
        assert count == 2
        solutions = q[:4].reshape(2, 2).astype(float)
        np.testing.assert_allclose(sorted(solutions[:, 1]), [-elbow, elbow], atol=10 * tolerance)
        for solution in solutions:
            np.testing.assert_allclose(pose(*solution)[:2, 3], [x, y], rtol=0, atol=tolerance)
        wrapped = np.angle(np.exp(1j * (solutions - q_true)))
        assert np.min(np.max(np.abs(wrapped), axis=1)) < 10 * tolerance
        assert np.all(np.isnan(q[4:]))


def mass_matrix(q2: float, inertial: np.ndarray) -> np.ndarray:
    """Two links turning about z, centre of mass of link i at (L_i + cx_i) along it (frame i is
    at its far end), izz about the centre of mass."""
    (m1, cx1, izz1), (m2, cx2, izz2) = inertial.reshape(2, 10)[:, [0, 1, 6]]
    r1, r2 = L1 + cx1, L2 + cx2
    c2 = math.cos(q2)
    m11 = m1 * r1**2 + izz1 + m2 * (L1**2 + r2**2 + 2 * L1 * r2 * c2) + izz2
    m12 = m2 * (r2**2 + L1 * r2 * c2) + izz2
    m22 = m2 * r2**2 + izz2
    return np.array([[m11, m12], [m12, m22]])


def test_extension_calls_the_kernels_without_p(built):
    extension = load_extension(next((built.root / "double" / "python").glob("planar_2r_ext*.so")))
    transforms = extension.fk(STATES)
    for T, q in zip(transforms, STATES, strict=True):
        np.testing.assert_allclose(T, pose(*q), rtol=0, atol=1e-12)
    # The Python API still takes p (the solvers pass it): empty, as the robot has none.
    np.testing.assert_array_equal(extension.fk(STATES[0], []), transforms[0])
    np.testing.assert_array_equal(extension.fk(STATES[0], p=None), transforms[0])
    with pytest.raises(ValueError, match=r"p must hold 0 numbers"):
        extension.fk(STATES[0], [1.0])
    # Per link: m, cx, cy, cz, ixx, iyy, izz, ixy, ixz, iyz; centres of mass mid-link.
    pi = np.array([2.0, -L1 / 2, 0, 0, 0.01, 0.02, 0.03, 0, 0, 0])
    pi = np.concatenate([pi, [1.5, -L2 / 2, 0, 0, 0.01, 0.02, 0.05, 0, 0, 0]])
    tau = np.array([0.8, -0.3])
    for q in STATES:
        M = mass_matrix(q[1], pi)
        np.testing.assert_allclose(extension.mass_matrix(q, pi=pi), M, rtol=0, atol=1e-12)
        # Gravity is along -z, normal to the plane, and dq = 0: M ddq = tau.
        ddq = extension.forward_dynamics(q, np.zeros(2), tau, pi=pi)
        np.testing.assert_allclose(ddq, np.linalg.solve(M, tau), rtol=0, atol=1e-10)
