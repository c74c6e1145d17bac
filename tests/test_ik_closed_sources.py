"""The closed-form IK part of the C library, ``templates/c/lib/symkin_closed_form.{h,c}``, on
its own: strict C99 in double and float (``-Wconversion -Wdouble-promotion``, AddressSanitizer
and UBSan), checked against values derived here by hand with NumPy:

* the two-link elbow: both solutions reproduce the point through the forward formula
  ``l1 (cos b, sin b) + l2 (cos(b + d), sin(b + d))``, the one the point was made from is among
  them, ``sin delta >= 0`` comes first; out of reach gives none, full stretch off by rounding
  gives the stretched arm;
* the waist angle: ``Rz(theta_1) (X, offset) = (x, y)`` for both roots, ``X >= 0`` first;
* the clamped square root, the branch-flag tests (a truth table typed in from their
  definitions) and the inverse elementary rotations (``Rz(a)^T v``, ``Rx(a)^T v`` by NumPy).

Also: every generated closed-form IK (one robot per kind of arm) compiles without a warning in
float under ``-Wconversion -Wdouble-promotion``, with only the library functions it calls.
"""

from __future__ import annotations

import math
import re
import subprocess
from functools import cache
from pathlib import Path

import numpy as np
import pytest

import symkin
from codegen_helpers import CC, CONVERSION, ROOT, SANITIZE, STRICT, strip_comments, write_tree
from symkin.derive import derive
from symkin.emit.c import emit_c
from symkin.emit.ik_closed_c import emit_ik_closed_c
from symkin.kernels import kernel_from_outputs, state_inputs

pytestmark = pytest.mark.needs_cc

LIB = ROOT / "templates" / "c" / "lib"

# Reads lines "<function> <numbers...>" and prints each result as numbers (%.17g).
DRIVER = r"""
#include <stdio.h>
#include <string.h>
#include "symkin_closed_form.h"

static double read_real(void)
{
    double value = 0;
    if (scanf("%lf", &value) != 1) {
        value = 0;
    }
    return value;
}

static void print_pairs(int count, const real_t a[2], const real_t b[2])
{
    printf("%d %.17g %.17g", count, (double)a[0], (double)b[0]);
    printf(" %.17g %.17g\n", (double)a[1], (double)b[1]);
}

int main(void)
{
    char name[32];
    while (scanf("%31s", name) == 1) {
        real_t a[2], b[2], v[3], root;
        int count;
        if (strcmp(name, "two_link") == 0) {
            const real_t x = (real_t)read_real(), y = (real_t)read_real();
            const real_t l1 = (real_t)read_real(), l2 = (real_t)read_real();
            count = symkin_two_link(x, y, l1, l2, REAL(1e-6), a, b);
            print_pairs(count, a, b);
        } else if (strcmp(name, "shoulder") == 0) {
            const real_t x = (real_t)read_real(), y = (real_t)read_real();
            const real_t offset = (real_t)read_real(), scale = (real_t)read_real();
            count = symkin_shoulder(x, y, offset, scale, REAL(1e-6), a, b);
            print_pairs(count, a, b);
        } else if (strcmp(name, "clamped_sqrt") == 0) {
            const real_t value = (real_t)read_real(), scale2 = (real_t)read_real();
            count = symkin_clamped_sqrt(value, scale2, REAL(1e-6), &root);
            printf("%d %.17g\n", count, (double)root);
        } else if (strcmp(name, "flags") == 0) {
            const int k = (int)read_real();
            const real_t X = (real_t)read_real(), offset = (real_t)read_real();
            const int twist = (int)read_real();
            printf("%d %d\n", symkin_shoulder_right(X, offset), symkin_elbow_up(k, X, twist));
        } else {
            const real_t c = (real_t)read_real(), s = (real_t)read_real();
            int i;
            for (i = 0; i < 3; ++i) {
                v[i] = (real_t)read_real();
            }
            if (strcmp(name, "unrotate_z") == 0) {
                symkin_unrotate_z(c, s, v);
            } else {
                symkin_unrotate_x(c, s, v);
            }
            printf("3 %.17g %.17g %.17g\n", (double)v[0], (double)v[1], (double)v[2]);
        }
    }
    return 0;
}
"""


@cache
def driver(precision: str, root: Path) -> Path:
    """The driver and the library built with every warning and both sanitizers."""
    (root / "driver.c").write_text(DRIVER, encoding="utf-8")
    program = root / f"driver_{precision}"
    define = ["-DSYMKIN_FLOAT"] if precision == "float" else []
    command = [
        CC, *STRICT, *CONVERSION, *SANITIZE, *define, f"-I{LIB}",
        "-o", str(program), "driver.c", str(LIB / "symkin_closed_form.c"), "-lm",
    ]  # fmt: skip
    build = subprocess.run(command, cwd=root, capture_output=True, text=True, check=False)
    assert build.returncode == 0, build.stderr
    assert build.stderr == "", build.stderr  # not even a warning
    return program


def call(precision: str, root: Path, lines: list[str]) -> list[list[float]]:
    run = subprocess.run(
        [str(driver(precision, root))],
        input="\n".join(lines) + "\n",
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert run.returncode == 0 and run.stderr == "", run.stderr
    return [[float(v) for v in line.split()] for line in run.stdout.splitlines()]


PRECISIONS = {"double": 1e-12, "float": 2e-5}


@pytest.fixture(scope="module")
def build_root(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("closed_form_sources")


def two_link_point(l1: float, l2: float, beta: float, delta: float) -> np.ndarray:
    return np.array(
        [
            l1 * math.cos(beta) + l2 * math.cos(beta + delta),
            l1 * math.sin(beta) + l2 * math.sin(beta + delta),
        ]
    )


def angle_difference(a: float, b: float) -> float:
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


@pytest.mark.parametrize("precision", PRECISIONS)
def test_two_link_solutions_reach_the_point(build_root, precision):
    tol = PRECISIONS[precision]
    rng = np.random.default_rng(1)
    cases = [
        (rng.uniform(0.2, 1.5), rng.uniform(0.2, 1.5), rng.uniform(-3, 3), rng.uniform(-3, 3))
        for _ in range(20)
    ]
    lines = []
    for l1, l2, beta, delta in cases:
        x, y = two_link_point(l1, l2, beta, delta)
        lines.append(f"two_link {float(x)!r} {float(y)!r} {l1!r} {l2!r}")
    for (l1, l2, beta, delta), result in zip(
        cases, call(precision, build_root, lines), strict=True
    ):
        count, solutions = int(result[0]), [result[1:3], result[3:5]]
        assert count == 2
        target = two_link_point(l1, l2, beta, delta)
        for b, d in solutions:
            assert np.abs(two_link_point(l1, l2, b, d) - target).max() <= 10 * tol
        assert math.sin(solutions[0][1]) >= -tol and math.sin(solutions[1][1]) <= tol
        assert (
            min(max(angle_difference(b, beta), angle_difference(d, delta)) for b, d in solutions)
            <= 1e3 * tol
        )


@pytest.mark.parametrize("precision", PRECISIONS)
def test_two_link_edges_of_the_workspace(build_root, precision):
    # 0.7 + 0.4 = 1.1 is the reach; 0.3 the hole in the middle.
    stretched = 1.1 * (1 + 1e-8)  # rounding beyond full stretch: clamped, the arm straight
    lines = [
        "two_link 1.2 0.0 0.7 0.4",
        "two_link 0.0 0.2 0.7 0.4",
        f"two_link {stretched!r} 0.0 0.7 0.4",
    ]
    beyond, inside_hole, full = call(precision, build_root, lines)
    assert beyond[0] == 0 and inside_hole[0] == 0
    assert full[0] == 2
    assert np.allclose(full[1:], 0.0, atol=1e-3)  # beta = delta = 0 twice


@pytest.mark.parametrize("precision", PRECISIONS)
def test_shoulder_puts_the_point_at_the_offset(build_root, precision):
    tol = PRECISIONS[precision]
    rng = np.random.default_rng(2)
    cases = [(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.3, 0.3)) for _ in range(20)]
    cases = [(x, y, o) for x, y, o in cases if math.hypot(x, y) > abs(o) + 0.05]
    lines = [f"shoulder {x!r} {y!r} {o!r} 1.0" for x, y, o in cases]
    lines.append("shoulder 0.1 0.0 0.3 1.0")  # closer to the waist axis than the offset
    *results, too_close = call(precision, build_root, lines)
    assert too_close[0] == 0
    for (x, y, offset), result in zip(cases, results, strict=True):
        assert result[0] == 2 and result[1] >= 0 and result[3] <= 0
        for X, theta in (result[1:3], result[3:5]):
            c, s = math.cos(theta), math.sin(theta)
            assert abs(c * X - s * offset - x) <= 10 * tol
            assert abs(s * X + c * offset - y) <= 10 * tol
            assert abs(X * X + offset * offset - x * x - y * y) <= 10 * tol


@pytest.mark.parametrize("precision", PRECISIONS)
def test_clamped_sqrt(build_root, precision):
    lines = ["clamped_sqrt 2.25 1.0", "clamped_sqrt -1e-9 4.0", "clamped_sqrt -1e-3 4.0"]
    root, rounding, negative = call(precision, build_root, lines)
    assert root == [1, 1.5]
    assert rounding == [1, 0.0]  # within 1e-6 * 4 of zero
    assert negative == [0, 0.0]


@pytest.mark.parametrize("precision", PRECISIONS)
def test_branch_flag_tests(build_root, precision):
    # (k, X, offset, twist) -> (shoulder right, elbow up), from the definitions:
    # right: X offset < 0, or X >= 0 without an offset; up: -sign(sin delta) sign(X) twist > 0.
    table = {
        (0, 0.5, -0.1, 1): (1, 0),
        (1, 0.5, -0.1, 1): (1, 1),
        (0, -0.5, -0.1, 1): (0, 1),
        (0, 0.5, 0.1, -1): (0, 1),
        (1, -0.5, 0.0, -1): (0, 1),
        (0, 0.5, 0.0, -1): (1, 1),
    }
    lines = [f"flags {k} {X} {o} {t}" for k, X, o, t in table]
    results = call(precision, build_root, lines)
    assert [tuple(int(v) for v in r) for r in results] == list(table.values())


@pytest.mark.parametrize("precision", PRECISIONS)
def test_unrotate_is_the_transposed_rotation(build_root, precision):
    tol = PRECISIONS[precision]
    angle, v = 0.7, np.array([0.3, -1.2, 0.5])
    c, s = math.cos(angle), math.sin(angle)
    rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    vector = " ".join(repr(float(x)) for x in v)
    lines = [f"unrotate_z {c!r} {s!r} {vector}", f"unrotate_x {c!r} {s!r} {vector}"]
    z, x = call(precision, build_root, lines)
    assert np.abs(np.array(z[1:]) - rz.T @ v).max() <= tol
    assert np.abs(np.array(x[1:]) - rx.T @ v).max() <= tol


def test_library_allocates_nothing_and_uses_no_posix_constants():
    for path in (LIB / "symkin_closed_form.h", LIB / "symkin_closed_form.c"):
        text = strip_comments(path.read_text(encoding="utf-8"))
        assert not re.search(r"\b(malloc|calloc|realloc|free|alloca)\b", text)
        assert not re.search(r"\bM_[A-Z0-9_]+\b", text)
        assert not re.search(r"\b(double|float)\b", text)  # real_t only


# One robot per kind of arm.
KINDS = ("planar_2r", "planar_3r", "scara", "puma560", "stanford", "cylindrical_rtt_wrist", "ur5")


@pytest.mark.parametrize("name", KINDS)
def test_generated_float_closed_form_compiles_without_conversion_warnings(tmp_path, name):
    robot = symkin.load_robot(name)
    model = derive(robot)
    outputs = [("T", model.product_form.forward_kinematics, "pose of the tool")]
    fk = kernel_from_outputs("fk", "forward kinematics", state_inputs(model), outputs)
    for precision in ("float", "double"):
        files = {**emit_c(robot, (fk,), precision), **emit_ik_closed_c(robot, (fk,), precision)}
        write_tree(tmp_path / precision, files)
        command = [CC, *STRICT, *CONVERSION, "-c", f"{name}_ik_closed.c", "-o", "closed.o"]
        build = subprocess.run(
            command, cwd=tmp_path / precision / "c", capture_output=True, text=True, check=False
        )
        assert build.returncode == 0 and build.stderr == "", build.stderr
